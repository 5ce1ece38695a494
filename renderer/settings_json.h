#pragma once
// Settings as JSON: the editor's save/load, the CLI's --settings file and the tests all read and write this one
// spelling. Keys are the Settings member names ("clampBound", "vplCount", ...); a file may hold any subset of them
// and the rest keep the values of the Settings it is applied to. Unknown keys, wrong types and out-of-range values
// are errors that name the key, so a typo never silently falls back to a default.

#include "renderer/settings.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace vplab {

/// A JSON text that cannot be applied to Settings. The message names the file (when there is one) and the key.
struct SettingsJsonError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Every key settingsToJson() writes, in Settings member order.
const std::vector<std::string>& settingsJsonKeys();

/// All members as one pretty-printed JSON object. The unbounded clamp is written as the string "inf" because JSON
/// has no infinity; enums are written by name ("all", "direct", "indirect").
std::string settingsToJson(const Settings& settings);

/// Applies the keys present in `json` (an object) on top of `settings`, then validates the whole result. On any
/// error `settings` is left unchanged and SettingsJsonError is thrown; `source` (a file name) prefixes the message.
void applySettingsJson(const std::string& json, Settings& settings, const std::string& source = "settings");

/// Sets one member from text, as a script line or a command-line override spells it: "clampBound 0.5",
/// "rejection true", "components indirect", "clampBound inf". Throws SettingsJsonError naming the key.
void setSettingFromText(Settings& settings, const std::string& key, const std::string& value);

/// Reads a JSON file and applies it on top of `settings` (throws SettingsJsonError naming the file).
void loadSettingsFile(const std::string& path, Settings& settings);
/// Writes settingsToJson() to a file (throws SettingsJsonError naming the file when it cannot be written).
void saveSettingsFile(const std::string& path, const Settings& settings);

}  // namespace vplab
