#include "app/settings_options.h"

#include "renderer/settings_json.h"

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

void applySettingOption(const CommandLine& cl, Settings& s, const SettingInfo& info) {
  std::string flag = settingFlag(info.key);
  auto text = cl.value(flag);
  if (!text) return;
  try {
    parseSetting(s, info, *text);
  } catch (const std::invalid_argument& e) {
    throw CliError("option --" + flag + ": '" + *text + "': " + e.what());
  }
}

void validateForCommandLine(const Settings& s) {
  std::vector<std::string> problems = validateSettings(s, SettingSpelling::Flag);
  if (!problems.empty()) throw CliError(problems.front());
}

const SettingInfo& settingNamed(const std::string& key) {
  const SettingInfo* info = findSetting(key);
  if (!info) throw std::logic_error("no setting '" + key + "'");
  return *info;
}

}  // namespace

std::vector<OptionSpec> settingOptions(const Settings& defaults, unsigned use) {
  std::vector<OptionSpec> options = {
      {"settings", "F.json", "settings file (keys as in --help's flags, camelCase); other options override it"}};
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
  if (use & kUseImage) cl.getSize("size", s.width, s.height);
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
