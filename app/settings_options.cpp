#include "app/settings_options.h"

#include "renderer/settings_json.h"

namespace vplab::cli {

namespace {

bool isSwitch(const SettingInfo& info) {
  return std::holds_alternative<bool Settings::*>(info.member);
}

}  // namespace

std::vector<OptionSpec> settingOptions(const Settings& defaults, unsigned use) {
  std::vector<OptionSpec> options = {
      {"settings", "F.json", "settings file (keys as in --help's flags, camelCase); other options override it"}};
  if (use & kUseImage)
    options.push_back({"size", "WxH",
                       "image size in pixels (default " + std::to_string(defaults.width) + "x" +
                           std::to_string(defaults.height) + ")"});
  for (const SettingInfo& info : settingsTable()) {
    if (!(info.use & use) || !info.commandLine) continue;
    OptionSpec o{settingFlag(info.key), info.valueName, info.help};
    o.help += " (default " + formatSetting(defaults, info) + ")";
    if (isSwitch(info)) {
      o.switchWithValue = true;
      o.valueName = "true|false";
    }
    options.push_back(o);
  }
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
  if (use & kUseImage) cl.getSize("size", s.width, s.height);
  for (const SettingInfo& info : settingsTable()) {
    if (!(info.use & use) || !info.commandLine) continue;
    std::string flag = settingFlag(info.key);
    auto text = cl.value(flag);
    if (!text) continue;
    try {
      parseSetting(s, info, *text);
    } catch (const std::invalid_argument& e) {
      throw CliError("option --" + flag + ": '" + *text + "': " + e.what());
    }
  }
  std::vector<std::string> problems = validateSettings(s, SettingSpelling::Flag);
  if (!problems.empty()) throw CliError(problems.front());
}

}  // namespace vplab::cli
