#include "renderer/settings_json.h"

#include "renderer/core/atomic_file.h"
#include "renderer/core/text.h"
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <variant>

namespace vplab {

namespace {

using Json = nlohmann::json;

std::string quoted(const std::string& key) {
  return "'" + key + "'";
}

/// At most kExcerptChars of a text for an error message, so a huge value or key never becomes a huge message.
constexpr std::size_t kExcerptChars = 40;
std::string excerpt(const std::string& text) {
  if (text.size() <= kExcerptChars) return text;
  return text.substr(0, kExcerptChars) + "... (" + std::to_string(text.size()) + " characters)";
}
std::string excerpt(const Json& value) {
  // A deep or long value is summarised by its type instead of dumped whole.
  if (value.is_structured()) return value.is_object() ? "an object" : "an array";
  return excerpt(value.dump());
}

Json toJson(const Settings& s, const SettingInfo& info) {
  return std::visit(
      [&](const auto& member) -> Json {
        using M = std::decay_t<decltype(member)>;
        if constexpr (std::is_same_v<M, SettingChoice>) {
          return member.names.at(static_cast<std::size_t>(member.get(s)));
        } else {
          using T = std::decay_t<decltype(s.*member)>;
          if constexpr (std::is_same_v<T, float>) {
            float v = s.*member;
            if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
            return v;
          } else {
            return s.*member;
          }
        }
      },
      info.member);
}

// Reads one value with the member's type. Integers must be integral and representable: 3.5 for an int is an error,
// not a truncation, and so is -1 for the unsigned seed.
void fromJson(Settings& s, const SettingInfo& info, const Json& value, const std::string& where) {
  std::visit(
      [&](const auto& member) {
        using M = std::decay_t<decltype(member)>;
        if constexpr (std::is_same_v<M, SettingChoice>) {
          if (value.is_string()) {
            try {
              return parseSetting(s, info, value.get<std::string>());
            } catch (const std::invalid_argument& e) {
              throw SettingsJsonError(where + ": " + e.what() + ", got " + excerpt(value));
            }
          }
          throw SettingsJsonError(where + ": expected a string, got " + excerpt(value));
        } else {
          using T = std::decay_t<decltype(s.*member)>;
          if constexpr (std::is_same_v<T, bool>) {
            if (!value.is_boolean()) throw SettingsJsonError(where + ": expected true or false, got " + excerpt(value));
            s.*member = value.get<bool>();
          } else if constexpr (std::is_same_v<T, float>) {
            if (value.is_string()) {
              const std::string text = value.get<std::string>();
              if (text != "inf" && text != "-inf")
                throw SettingsJsonError(where + ": expected a number or \"inf\", got " + excerpt(value));
              s.*member = text == "inf" ? kInfinity : -kInfinity;
            } else if (value.is_number()) {
              double d = value.get<double>();
              if (std::abs(d) > std::numeric_limits<float>::max())
                throw SettingsJsonError(where + ": " + excerpt(value) + " does not fit a float");
              s.*member = static_cast<float>(d);
            } else {
              throw SettingsJsonError(where + ": expected a number, got " + excerpt(value));
            }
          } else {
            bool integral = value.is_number_integer() ||
                            (value.is_number_float() && std::floor(value.get<double>()) == value.get<double>());
            if (!integral) throw SettingsJsonError(where + ": expected an integer, got " + excerpt(value));
            double d = value.get<double>();
            if (d < static_cast<double>(std::numeric_limits<T>::min()) ||
                d > static_cast<double>(std::numeric_limits<T>::max()))
              throw SettingsJsonError(where + ": " + excerpt(value) + " is out of range");
            s.*member = static_cast<T>(d);
          }
        }
      },
      info.member);
}

/// Settings are one flat object: nesting deeper than this is rejected before parsing (a recursive parser would
/// otherwise run out of stack on a hostile file).
constexpr int kMaxJsonDepth = 64;

void requireShallow(const std::string& json, const std::string& source) {
  int depth = 0;
  bool inString = false, escaped = false;
  for (char c : json) {
    if (inString) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '{' || c == '[') {
      if (++depth > kMaxJsonDepth)
        throw SettingsJsonError(source + ": nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    } else if (c == '}' || c == ']') {
      --depth;
    }
  }
}

// validateSettings() messages start with the member name, which is also the JSON key.
void validateOrThrow(const Settings& s, const std::string& source) {
  std::vector<std::string> problems = validateSettings(s);
  if (problems.empty()) return;
  std::string message = source + ": ";
  for (std::size_t i = 0; i < problems.size(); ++i) message += (i ? "; " : "") + problems[i];
  throw SettingsJsonError(message);
}

}  // namespace

const std::vector<std::string>& settingsJsonKeys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> k;
    for (const SettingInfo& info : settingsTable()) k.emplace_back(info.key);
    return k;
  }();
  return keys;
}

std::string settingsToJson(const Settings& settings) {
  Json j = Json::object();
  for (const SettingInfo& info : settingsTable()) j[info.key] = toJson(settings, info);
  return j.dump(2) + "\n";
}

void applySettingsJson(const std::string& json, Settings& settings, const std::string& source) {
  requireShallow(json, source);
  Json parsed;
  try {
    parsed = Json::parse(json);
  } catch (const Json::exception& e) {
    // Every JSON error (a number beyond a double's range included) is a settings error, exit 2, naming the key.
    throw SettingsJsonError(source + ": " + describeJsonError(json, e));
  }
  if (!parsed.is_object()) throw SettingsJsonError(source + ": expected a JSON object of settings");
  Settings result = settings;
  for (const auto& [key, value] : parsed.items()) {
    // "size": "WxH", as the command line's --size, sets width and height.
    if (key == "size") {
      unsigned w = 0, h = 0;
      char tail = 0;
      if (!value.is_string() || std::sscanf(value.get<std::string>().c_str(), "%ux%u%c", &w, &h, &tail) != 2 ||
          w > 1u << 20 || h > 1u << 20)
        throw SettingsJsonError(source + ": 'size': expected \"WxH\" (for example \"256x256\"), got " + excerpt(value));
      const SettingInfo& width = *findSetting("width");
      if (w < width.min || w > width.max || h < width.min || h > width.max)
        throw SettingsJsonError(source + ": 'size': \"" + value.get<std::string>() +
                                "\": width and height must each be in [" + std::to_string(int(width.min)) + ", " +
                                std::to_string(int(width.max)) + "]");
      fromJson(result, width, Json(w), source + ": 'size' (its width)");
      fromJson(result, *findSetting("height"), Json(h), source + ": 'size' (its height)");
      continue;
    }
    const SettingInfo* info = findSetting(key);
    if (!info)
      throw SettingsJsonError(source + ": unknown key " + quoted(excerpt(key)) +
                              " (not a setting; command options such as --method go on the command line)");
    fromJson(result, *info, value, source + ": " + quoted(key));
  }
  validateOrThrow(result, source);
  settings = result;
}

void setSettingFromText(Settings& settings, const std::string& key, const std::string& value) {
  const SettingInfo* info = findSetting(key);
  if (!info) throw SettingsJsonError("unknown setting " + quoted(excerpt(key)));
  // Numbers and booleans parse as JSON; anything else (an enum name, "inf") is taken as a string.
  Json parsed;
  try {
    requireShallow(value, quoted(key));
    parsed = Json::parse(value);
  } catch (const std::exception&) {
    parsed = value;
  }
  Settings result = settings;
  fromJson(result, *info, parsed, quoted(key));
  validateOrThrow(result, quoted(key));
  settings = result;
}

void loadSettingsFile(const std::string& path, Settings& settings) {
  std::string text;
  try {
    // A settings file is a flat object of a few dozen keys; a megabyte is far more than any.
    text = readInputFile(path, 1u << 20, "a settings file");
  } catch (const FileReadError& e) {
    throw SettingsJsonError(e.what());
  }
  applySettingsJson(text, settings, path);
}

void saveSettingsFile(const std::string& path, const Settings& settings) {
  try {
    writeFileAtomically(path, settingsToJson(settings));
  } catch (const FileWriteError& e) {
    throw SettingsJsonError(e.what());
  }
}

}  // namespace vplab
