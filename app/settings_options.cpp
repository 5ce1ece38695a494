#include "app/settings_options.h"

#include "renderer/settings_json.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace vplab::cli {

namespace {

bool isSwitch(const SettingInfo& info) {
  return std::holds_alternative<bool Settings::*>(info.member);
}

OptionSpec settingOption(const Settings& defaults, const SettingInfo& info) {
  OptionSpec o{settingFlag(info.key), info.valueName, info.help};
  o.help += " (default " + formatSetting(defaults, info) + ")";
  if (isSwitch(info)) {
    o.switchWithValue = true;
    o.valueName = "true|false";
  }
  return o;
}

std::string rangeOf(const SettingInfo& info, bool integral) {
  auto number = [&](double v) {
    char text[32];
    std::snprintf(text, sizeof text, integral ? "%.0f" : "%g", v);
    return std::string(text);
  };
  return std::string(info.bound == SettingBound::AboveMin ? "(" : "[") + number(info.min) + ", " + number(info.max) +
         "]";
}

/// Why a number the parser refused was refused, with the setting's own range: parseSetting() quotes the limits of
/// the C++ type ("an integer in [-2147483648, 2147483647]", "a number") for 1e9 or 1e300, not what the flag takes.
std::string numberProblem(const SettingInfo& info, const std::string& text, const std::string& parserSays) {
  const bool integral = parserSays.rfind("expected an integer", 0) == 0;
  const bool floating = parserSays.rfind("expected a number", 0) == 0;
  if (!integral && !floating) return parserSays;
  char* end = nullptr;
  errno = 0;
  double v = std::strtod(text.c_str(), &end);
  const bool isNumber = !text.empty() && *end == '\0' && !std::isnan(v);
  if (integral) {
    if (isNumber && std::isfinite(v) && v == std::floor(v) && errno != ERANGE) {
      if (v < info.min || v > info.max) return "outside " + rangeOf(info, true);
      char digits[32];
      std::snprintf(digits, sizeof digits, "%.0f", v);
      return std::string("expected an integer written in digits (") + digits + ")";
    }
    return "expected an integer in " + rangeOf(info, true);
  }
  if (!isNumber) return "expected a number in " + rangeOf(info, false);
  return "out of the range of a float (at most +-3.4e38); expected a number in " + rangeOf(info, false);
}

void applySettingOption(const CommandLine& cl, Settings& s, const SettingInfo& info) {
  std::string flag = settingFlag(info.key);
  auto text = cl.value(flag);
  if (!text) return;
  try {
    parseSetting(s, info, *text);
  } catch (const std::invalid_argument& e) {
    throw CliError("option --" + flag + ": '" + *text + "': " + numberProblem(info, *text, e.what()));
  }
}

void validateForCommandLine(const Settings& s) {
  std::vector<std::string> problems = validateSettings(s, SettingSpelling::Flag);
  if (problems.empty()) return;
  // width and height have no flags: they come from --size WxH (or a settings file's keys).
  std::string problem = problems.front();
  for (const char* key : {"width", "height"})
    if (problem.rfind(std::string("--") + key + " ", 0) == 0)
      problem = std::string(key) + " (--size WxH or the settings key \"" + key + "\")" +
                problem.substr(2 + std::strlen(key));
  throw CliError(problem);
}

const SettingInfo& settingNamed(const std::string& key) {
  const SettingInfo* info = findSetting(key);
  if (!info) throw std::logic_error("no setting '" + key + "'");
  return *info;
}

}  // namespace

std::vector<OptionSpec> settingOptions(const Settings& defaults, unsigned use) {
  std::vector<OptionSpec> options = {
      {"settings", "F.json",
       "settings file: the flags marked (default ...) below as camelCase keys (\"clampBound\": 0.5) and \"size\": "
       "\"WxH\"; command options (--method, --frames, -o) are not settings; flags override it"}};
  if (use & kUseImage)
    options.push_back({"size", "WxH",
                       "image size in pixels (default " + std::to_string(defaults.width) + "x" +
                           std::to_string(defaults.height) + ")"});
  for (const SettingInfo& info : settingsTable())
    if ((info.use & use) && info.commandLine) options.push_back(settingOption(defaults, info));
  return options;
}

void applySettingsOptions(const CommandLine& cl, Settings& s, unsigned use) {
  if (auto file = cl.value("settings")) {
    try {
      loadSettingsFile(*file, s);
    } catch (const SettingsJsonError& e) {
      throw CliError(std::string("option --settings: ") + e.what());
    }
  }
  if (use & kUseImage) {
    cl.getSize("size", s.width, s.height);
    // --size sets the table's width and height, which have no flags of their own: name the flag the user typed.
    const SettingInfo& w = settingNamed("width");
    const SettingInfo& h = settingNamed("height");
    auto size = cl.value("size");
    if (size && (s.width < w.min || s.width > w.max || s.height < h.min || s.height > h.max))
      throw CliError("option --size: '" + *size + "': width and height must each be in " + rangeOf(w, true) +
                     " pixels");
  }
  for (const SettingInfo& info : settingsTable())
    if ((info.use & use) && info.commandLine) applySettingOption(cl, s, info);
  validateForCommandLine(s);
}

std::vector<OptionSpec> settingOptions(const Settings& defaults, const std::vector<std::string>& keys) {
  std::vector<OptionSpec> options;
  for (const std::string& key : keys) options.push_back(settingOption(defaults, settingNamed(key)));
  return options;
}

void applySettingsOptions(const CommandLine& cl, Settings& s, const std::vector<std::string>& keys) {
  for (const std::string& key : keys) applySettingOption(cl, s, settingNamed(key));
  validateForCommandLine(s);
}

}  // namespace vplab::cli
