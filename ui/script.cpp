#include "ui/script.h"

#include "renderer/core/text.h"
#include "renderer/image/image_io.h"
#include "renderer/settings_json.h"
#include "ui/editor_state.h"
#include "ui/media_panel.h"
#include "ui/presets.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
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
      {"coarse-first-after", {1, 1}},
      {"medium", {2, 5}},
      {"save-sidecar", {0, 0}},
  };
  return table;
}

std::string where(const std::string& source, int line) { return source + ":" + std::to_string(line) + ": "; }

/// The offline methods a script names (the reference and the plain VPL render go by 'reference' and 'vpl').
std::string renderMethodNamesForScripts() {
  std::string names;
  for (Method m : {Method::VplKK, Method::Vsl, Method::VplAbc, Method::Vrl, Method::Vbl})
    names += (names.empty() ? "" : ", ") + std::string(toString(m));
  return names;
}

[[noreturn]] void fail(const ScriptCommand& c, const std::string& source, const std::string& message) {
  throw ScriptError(where(source, c.line) + c.verb + ": " + message);
}

/// The scene's media with the `medium` command applied (the same functions as the media panel).
std::vector<Medium> editedMedia(const EditorState& state, const ScriptCommand& c, const std::string& source) {
  std::vector<Medium> media = state.media();
  if (c.args[0] == "add") {
    media.push_back(c.args[1] == "box" ? newFogBox(state.scene()) : newFogEverywhere(state.scene()));
    return media;
  }
  const double index = scriptNumber(c, 0, source);
  if (!(index >= 0.0 && index < static_cast<double>(media.size())))
    fail(c, source, "no medium " + printable(c.args[0]) + " (the scene has " + std::to_string(media.size()) + ")");
  Medium& m = media[static_cast<std::size_t>(index)];
  const std::string& what = c.args[1];
  auto v = [&] {
    return glm::vec3(scriptNumber(c, 2, source), scriptNumber(c, 3, source), scriptNumber(c, 4, source));
  };
  if (what == "remove") media.erase(media.begin() + static_cast<std::ptrdiff_t>(index));
  if (what == "g") m.g = static_cast<float>(scriptNumber(c, 2, source));
  if (what == "sigmaA") m.sigmaA = v();
  if (what == "sigmaS") m.sigmaS = v();
  if (what == "move") moveMediumBox(m, v());
  if (what == "size") resizeMediumBox(m, v());
  if (what == "density") {
    // On a homogeneous medium the scale would be stored and do nothing: say so instead.
    if (!m.heterogeneous())
      fail(c, source,
           "medium " + c.args[0] + " ('" + printable(m.name) + "') has no density grid; 'medium " + c.args[0] +
               " vdb <path>' attaches one");
    m.densityScale = static_cast<float>(scriptNumber(c, 2, source));
  }
  if (what == "vdb") {
    if (m.fillsSpace)
      fail(c, source, "medium " + c.args[0] + " ('" + printable(m.name) + "') fills all space: a grid needs a box");
    attachVdb(state.scene(), media, static_cast<int>(index), c.args[2],
              c.args.size() > 3 ? c.args[3] : kDefaultDensityGrid);  // VdbError: the file's one-line message
  }
  return media;
}

bool runStateVerb(EditorState& state, const ScriptCommand& c, const std::string& source) {
  auto num = [&](std::size_t i) { return static_cast<float>(scriptNumber(c, i, source)); };
  auto print = [](const std::string& line) {
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  };
  if (c.verb == "set") {
    Settings next = state.settings();
    setSettingFromText(next, c.args[0], c.args[1]);
    if (c.args[0] == "width" || c.args[0] == "height") state.setFitPreview(false);  // an explicit image size
    state.requestSettings(next);
  } else if (c.verb == "orbit") {
    state.camera().orbit(glm::radians(num(0)), glm::radians(num(1)));
    state.cameraMoved();
  } else if (c.verb == "pan") {
    state.camera().pan(num(0), num(1));
    state.cameraMoved();
  } else if (c.verb == "zoom") {
    state.camera().zoom(num(0));
    state.cameraMoved();
  } else if (c.verb == "reset-camera") {
    state.resetCamera();
  } else if (c.verb == "light") {
    auto index = static_cast<std::size_t>(num(0));
    if (c.args[1] == "move")
      state.editLight(index, glm::vec3(num(2), num(3), num(4)), 1.0f);
    else
      state.editLight(index, glm::vec3(0.0f), num(2));
  } else if (c.verb == "medium") {
    if (!state.editMedia(editedMedia(state, c, source))) fail(c, source, state.mediaError());
  } else if (c.verb == "save-sidecar") {
    print("save-sidecar " + state.saveSidecar());
  } else if (c.verb == "view") {
    const auto* mode = std::find_if(std::begin(kAllViewModes), std::end(kAllViewModes),
                                    [&](ViewMode m) { return c.args[0] == toString(m); });
    if (mode == std::end(kAllViewModes)) fail(c, source, "unknown view '" + c.args[0] + "'");
    state.setView(*mode);
  } else if (c.verb == "preset") {
    const TeachingPreset* preset = findPreset(c.args[0]);
    if (!preset) fail(c, source, unknownPresetMessage(c.args[0]));
    if (!state.applyPreset(*preset)) fail(c, source, state.sceneError());
    print(presetDescription(*preset));
  } else if (c.verb == "preview-scale") {
    state.setPreviewScale(num(0));
  } else if (c.verb == "coarse-first-after") {
    state.coarseFirstAfterMs = c.args[0] == "off" ? std::numeric_limits<double>::infinity() : num(0);
  } else if (c.verb == "change-cost") {
    char line[400];
    const ChangeTimer& t = state.changeTimer();
    const PreviewTimings& p = t.lastPasses();
    std::snprintf(line, sizeof line,
                  "change-cost size=%dx%d ms=%.1f first_image_ms=%.1f coarse=%d frames=%d pending=%d pass_ms "
                  "gbuffer=%.1f direct_shadow=%.1f direct=%.1f vpl_shadow=%.1f gather=%.1f media=%.1f ssbc=%.1f",
                  state.settings().width, state.settings().height, t.lastMs(), t.lastFirstImageMs(),
                  t.lastHadCoarseImage(), t.lastFrames(), t.pending(), p.gbufferMs, p.directShadowMs, p.directMs,
                  p.vplShadowMs, p.gatherMs, p.mediaMs, p.ssbcMs);
    print(line);
  } else if (c.verb == "preset-state") {
    print("preset-state " + state.presetState());
  } else if (c.verb == "save-view") {
    state.finishWork();
    if (state.previewImage().empty())
      fail(c, source, "no preview image" + (state.previewError().empty() ? "" : ": " + state.previewError()));
    writeImage(c.args[0], state.previewImage(), state.settings().exposure);
    print("save-view " + c.args[0] + " " + std::to_string(state.previewImage().width) + "x" +
          std::to_string(state.previewImage().height));
  } else if (c.verb == "offline") {
    state.finishWork();  // the offline pass must use the VPLs of the current settings
    Method method = Method::Reference;
    if (c.args[0] == "vpl") {
      state.startOffline(OfflineRequest::Exact);
    } else if (parseMethod(c.args[0], method) && method != Method::Reference) {
      state.setOfflineMethod(method);
      state.startOffline(OfflineRequest::Chosen);
    } else {
      state.startOffline(OfflineRequest::Reference);
    }
  } else if (c.verb == "load-settings") {
    Settings next = state.settings();
    loadSettingsFile(c.args[0], next);
    state.requestSettings(next);
  } else if (c.verb == "save-settings") {
    saveSettingsFile(c.args[0], state.settings());
  } else if (c.verb == "mark") {
    state.mark();
  } else if (c.verb == "expect-no-vpl-regeneration" || c.verb == "expect-no-shadow-map-render" ||
             c.verb == "expect-vpl-regeneration") {
    const WorkCounters n = state.sinceMark();
    if (c.verb == "expect-no-vpl-regeneration" && n.vplGenerations != 0)
      fail(c, source, std::to_string(n.vplGenerations) + " VPL generation(s) since the mark");
    if (c.verb == "expect-no-shadow-map-render" && n.vplShadowMaps != 0)
      fail(c, source, std::to_string(n.vplShadowMaps) + " VPL shadow-map render(s) since the mark");
    if (c.verb == "expect-vpl-regeneration" && n.vplGenerations == 0) fail(c, source, "no VPL generation since the mark");
  } else if (c.verb == "counters") {
    state.finishWork();
    const WorkCounters n = state.counters();
    print("counters vplGenerations=" + std::to_string(n.vplGenerations) + " vplShadowMaps=" +
          std::to_string(n.vplShadowMaps) + " gathers=" + std::to_string(n.gathers));
  } else {
    return false;  // frames, screenshot, wait-offline, time-frames: the window's frame loop runs them
  }
  return true;
}

}  // namespace

bool runStateCommand(EditorState& state, const ScriptCommand& c, const std::string& source) {
  try {
    return runStateVerb(state, c, source);
  } catch (const ScriptError&) {
    throw;
  } catch (const std::exception& e) {
    fail(c, source, e.what());  // a light that does not exist, a file that cannot be written: named by its line
  }
}

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
    if (it == verbs().end())
      throw ScriptError(where(source, lineNumber) + "unknown command '" + printable(c.verb) + "'");
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
    Method method;
    if (c.verb == "offline" && c.args[0] != "vpl" && !parseMethod(c.args[0], method))
      throw ScriptError(where(source, lineNumber) + "offline takes 'reference', 'vpl' (the exact counterpart of the "
                        "preview) or a method: " + renderMethodNamesForScripts());
    if (c.verb == "medium") {
      const std::string& what = c.args[1];
      const bool add = c.args[0] == "add" && n == 2 && (what == "box" || what == "space");
      const bool edit = c.args[0] != "add" && ((what == "remove" && n == 2) ||
                                               ((what == "g" || what == "density") && n == 3) ||
                                               (what == "vdb" && (n == 3 || n == 4)) ||
                                               ((what == "sigmaA" || what == "sigmaS" || what == "move" ||
                                                 what == "size") && n == 5));
      if (!add && !edit)
        throw ScriptError(where(source, lineNumber) + "expected 'medium add box|space', 'medium <i> remove', "
                          "'medium <i> g|density <v>', 'medium <i> vdb <path> [grid]' or "
                          "'medium <i> sigmaA|sigmaS|move|size <x> <y> <z>'");
    }
    for (std::size_t i = 0; i < c.args.size(); ++i) {
      // A medium's index and values are numbers; a .vdb's path and grid name are not.
      const bool mediumNumber = c.verb == "medium" && c.args[0] != "add" && i != 1 && (c.args[1] != "vdb" || i == 0);
      bool numeric = c.verb == "orbit" || c.verb == "pan" || c.verb == "zoom" || c.verb == "frames" ||
                     (c.verb == "time-frames" && i != 1) || c.verb == "preview-scale" || (c.verb == "light" && i != 1) ||
                     (c.verb == "coarse-first-after" && c.args[0] != "off") || mediumNumber;
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
    throw ScriptError(where(source, c.line) + "'" + printable(text) + "' is not a number (argument " +
                      std::to_string(i + 1) + " of '" + c.verb + "')");
  return value;
}

}  // namespace vplab::ui
