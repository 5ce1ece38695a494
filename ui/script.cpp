#include "ui/script.h"

#include "ui/presets.h"

#include <fstream>
#include <map>
#include <sstream>

namespace vplab::ui {

namespace {

struct Arity {
  int min;
  int max;  // -1: rest of the line is one argument
};

const std::map<std::string, Arity>& verbs() {
  static const std::map<std::string, Arity> table = {
      {"set", {2, 2}},
      {"orbit", {2, 2}},
      {"pan", {2, 2}},
      {"zoom", {1, 1}},
      {"reset-camera", {0, 0}},
      {"light", {3, 5}},
      {"view", {1, 1}},
      {"preset", {1, -1}},
      {"frames", {1, 1}},
      {"screenshot", {1, 1}},
      {"save-view", {1, 1}},
      {"offline", {1, 1}},
      {"wait-offline", {0, 0}},
      {"load-settings", {1, 1}},
      {"save-settings", {1, 1}},
      {"mark", {0, 0}},
      {"expect-no-vpl-regeneration", {0, 0}},
      {"expect-no-shadow-map-render", {0, 0}},
      {"expect-vpl-regeneration", {0, 0}},
      {"counters", {0, 0}},
      {"time-frames", {1, 3}},
      {"preset-state", {0, 0}},
      {"preview-scale", {1, 1}},
      {"change-cost", {0, 0}},
  };
  return table;
}

std::string where(const std::string& source, int line) { return source + ":" + std::to_string(line) + ": "; }

}  // namespace

std::vector<ScriptCommand> parseScript(const std::string& text, const std::string& source) {
  std::vector<ScriptCommand> commands;
  std::istringstream lines(text);
  std::string raw;
  int lineNumber = 0;
  while (std::getline(lines, raw)) {
    ++lineNumber;
    if (auto hash = raw.find('#'); hash != std::string::npos) raw.erase(hash);
    std::istringstream words(raw);
    ScriptCommand c;
    c.line = lineNumber;
    if (!(words >> c.verb)) continue;
    auto it = verbs().find(c.verb);
    if (it == verbs().end()) throw ScriptError(where(source, lineNumber) + "unknown command '" + c.verb + "'");
    if (it->second.max < 0) {
      std::string rest;
      std::getline(words >> std::ws, rest);
      while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\t' || rest.back() == '\r')) rest.pop_back();
      if (!rest.empty()) c.args.push_back(rest);
    } else {
      for (std::string w; words >> w;) c.args.push_back(w);
    }
    int n = static_cast<int>(c.args.size());
    int max = it->second.max < 0 ? 1 : it->second.max;
    if (n < it->second.min || n > max)
      throw ScriptError(where(source, lineNumber) + "'" + c.verb + "' takes " + std::to_string(it->second.min) +
                        (max != it->second.min ? " to " + std::to_string(max) : "") + " arguments, got " +
                        std::to_string(n));
    if (c.verb == "light") {
      const std::string& what = c.args[1];
      if (!((what == "move" && n == 5) || (what == "intensity" && n == 3)))
        throw ScriptError(where(source, lineNumber) + "expected 'light <i> move dx dy dz' or 'light <i> intensity s'");
    }
    if (c.verb == "preset" && !findPreset(c.args[0]))
      throw ScriptError(where(source, lineNumber) + unknownPresetMessage(c.args[0]));
    if (c.verb == "offline" && c.args[0] != "reference" && c.args[0] != "vpl")
      throw ScriptError(where(source, lineNumber) + "offline takes 'reference' or 'vpl'");
    for (std::size_t i = 0; i < c.args.size(); ++i) {
      bool numeric = c.verb == "orbit" || c.verb == "pan" || c.verb == "zoom" || c.verb == "frames" ||
                     (c.verb == "time-frames" && i != 1) || c.verb == "preview-scale" || (c.verb == "light" && i != 1);
      if (numeric) scriptNumber(c, i, source);
    }
    commands.push_back(std::move(c));
  }
  return commands;
}

std::vector<ScriptCommand> loadScript(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ScriptError(path + ": cannot open script");
  std::stringstream text;
  text << in.rdbuf();
  return parseScript(text.str(), path);
}

double scriptNumber(const ScriptCommand& c, std::size_t i, const std::string& source) {
  const std::string& text = c.args.at(i);
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty())
    throw ScriptError(where(source, c.line) + "'" + text + "' is not a number (argument " + std::to_string(i + 1) +
                      " of '" + c.verb + "')");
  return value;
}

}  // namespace vplab::ui
