#include "renderer/settings_json.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <variant>

namespace vplab {

namespace {

using Json = nlohmann::json;

// One row per Settings member: the JSON key and where the value lives. The table is the single list both directions
// walk, so a member added to Settings and here is saved, loaded and scriptable at once.
using MemberPtr = std::variant<int Settings::*, uint32_t Settings::*, float Settings::*, bool Settings::*,
                               Components Settings::*, Stage Settings::*, VisibilityMethod Settings::*,
                               VplGeneration Settings::*>;
struct Field {
  const char* key;
  MemberPtr member;
};

const std::vector<Field>& fields() {
  static const std::vector<Field> table = {
      {"width", &Settings::width},
      {"height", &Settings::height},
      {"seed", &Settings::seed},
      {"threads", &Settings::threads},
      {"exposure", &Settings::exposure},
      {"stage", &Settings::stage},
      {"samplesPerPixel", &Settings::samplesPerPixel},
      {"exactSamplesPerPixel", &Settings::exactSamplesPerPixel},
      {"maxDepth", &Settings::maxDepth},
      {"components", &Settings::components},
      {"generation", &Settings::generation},
      {"vplCount", &Settings::vplCount},
      {"vplMaxBounces", &Settings::vplMaxBounces},
      {"importancePoints", &Settings::importancePoints},
      {"rejection", &Settings::rejection},
      {"rejectionEpsilon", &Settings::rejectionEpsilon},
      {"rejectionPilotVpls", &Settings::rejectionPilotVpls},
      {"rejectionMaxCandidateFactor", &Settings::rejectionMaxCandidateFactor},
      {"birCandidateFactor", &Settings::birCandidateFactor},
      {"birLightShare", &Settings::birLightShare},
      {"birEpsilon", &Settings::birEpsilon},
      {"mirChains", &Settings::mirChains},
      {"mirLargeStepProbability", &Settings::mirLargeStepProbability},
      {"mirBurnIn", &Settings::mirBurnIn},
      {"mirBootstrapPaths", &Settings::mirBootstrapPaths},
      {"mirEpsilon", &Settings::mirEpsilon},
      {"clampBound", &Settings::clampBound},
      {"ssbcSteps", &Settings::ssbcSteps},
      {"ssbcCoarseRings", &Settings::ssbcCoarseRings},
      {"vslRadius", &Settings::vslRadius},
      {"vslRadiusFromDensity", &Settings::vslRadiusFromDensity},
      {"vslSamples", &Settings::vslSamples},
      {"directLightSamples", &Settings::directLightSamples},
      {"interleave", &Settings::interleave},
      {"shadowMapSize", &Settings::shadowMapSize},
      {"shadowBias", &Settings::shadowBias},
      {"visibility", &Settings::visibility},
      {"ismTileSize", &Settings::ismTileSize},
      {"ismPointBudget", &Settings::ismPointBudget},
  };
  return table;
}

const Field* findField(const std::string& key) {
  for (const Field& f : fields())
    if (key == f.key) return &f;
  return nullptr;
}

std::string quoted(const std::string& key) { return "'" + key + "'"; }

Json toJson(const Settings& s, const Field& f) {
  return std::visit(
      [&](auto member) -> Json {
        using T = std::decay_t<decltype(s.*member)>;
        if constexpr (std::is_same_v<T, Components> || std::is_same_v<T, Stage> ||
                      std::is_same_v<T, VisibilityMethod> || std::is_same_v<T, VplGeneration>) {
          return toString(s.*member);
        } else if constexpr (std::is_same_v<T, float>) {
          float v = s.*member;
          if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
          return v;
        } else {
          return s.*member;
        }
      },
      f.member);
}

// Reads one value with the member's type. Integers must be integral and representable: 3.5 for an int is an error,
// not a truncation, and so is -1 for the unsigned seed.
void fromJson(Settings& s, const Field& f, const Json& value, const std::string& where) {
  std::visit(
      [&](auto member) {
        using T = std::decay_t<decltype(s.*member)>;
        if constexpr (std::is_same_v<T, bool>) {
          if (!value.is_boolean()) throw SettingsJsonError(where + ": expected true or false, got " + value.dump());
          s.*member = value.get<bool>();
        } else if constexpr (std::is_same_v<T, Components>) {
          Components c;
          if (!value.is_string() || !parseComponents(value.get<std::string>(), c))
            throw SettingsJsonError(where + ": expected \"all\", \"direct\" or \"indirect\", got " + value.dump());
          s.*member = c;
        } else if constexpr (std::is_same_v<T, Stage>) {
          Stage st;
          if (!value.is_string() || !parseStage(value.get<std::string>(), st))
            throw SettingsJsonError(where + ": expected \"auto\", \"none\" or \"studio\", got " + value.dump());
          s.*member = st;
        } else if constexpr (std::is_same_v<T, VisibilityMethod>) {
          VisibilityMethod v;
          if (!value.is_string() || !parseVisibilityMethod(value.get<std::string>(), v))
            throw SettingsJsonError(where + ": expected \"cube\" or \"ism\", got " + value.dump());
          s.*member = v;
        } else if constexpr (std::is_same_v<T, VplGeneration>) {
          VplGeneration g;
          if (!value.is_string() || !parseGeneration(value.get<std::string>(), g))
            throw SettingsJsonError(where + ": expected \"light\", \"bidirectional\" or \"metropolis\", got " +
                                    value.dump());
          s.*member = g;
        } else if constexpr (std::is_same_v<T, float>) {
          if (value.is_string()) {
            const std::string text = value.get<std::string>();
            if (text != "inf" && text != "-inf")
              throw SettingsJsonError(where + ": expected a number or \"inf\", got " + value.dump());
            s.*member = text == "inf" ? kInfinity : -kInfinity;
          } else if (value.is_number()) {
            double d = value.get<double>();
            if (std::abs(d) > std::numeric_limits<float>::max())
              throw SettingsJsonError(where + ": " + value.dump() + " does not fit a float");
            s.*member = static_cast<float>(d);
          } else {
            throw SettingsJsonError(where + ": expected a number, got " + value.dump());
          }
        } else {
          bool integral = value.is_number_integer() ||
                          (value.is_number_float() && std::floor(value.get<double>()) == value.get<double>());
          if (!integral) throw SettingsJsonError(where + ": expected an integer, got " + value.dump());
          double d = value.get<double>();
          if (d < static_cast<double>(std::numeric_limits<T>::min()) ||
              d > static_cast<double>(std::numeric_limits<T>::max()))
            throw SettingsJsonError(where + ": " + value.dump() + " is out of range");
          s.*member = static_cast<T>(d);
        }
      },
      f.member);
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
    for (const Field& f : fields()) k.emplace_back(f.key);
    return k;
  }();
  return keys;
}

std::string settingsToJson(const Settings& settings) {
  Json j = Json::object();
  for (const Field& f : fields()) j[f.key] = toJson(settings, f);
  return j.dump(2) + "\n";
}

void applySettingsJson(const std::string& json, Settings& settings, const std::string& source) {
  Json parsed;
  try {
    parsed = Json::parse(json);
  } catch (const Json::parse_error& e) {
    throw SettingsJsonError(source + ": not valid JSON: " + e.what());
  }
  if (!parsed.is_object()) throw SettingsJsonError(source + ": expected a JSON object of settings");
  Settings result = settings;
  for (const auto& [key, value] : parsed.items()) {
    const Field* f = findField(key);
    if (!f) throw SettingsJsonError(source + ": unknown key " + quoted(key));
    fromJson(result, *f, value, source + ": " + quoted(key));
  }
  validateOrThrow(result, source);
  settings = result;
}

void setSettingFromText(Settings& settings, const std::string& key, const std::string& value) {
  const Field* f = findField(key);
  if (!f) throw SettingsJsonError("unknown setting " + quoted(key));
  // Numbers and booleans parse as JSON; anything else (an enum name, "inf") is taken as a string.
  Json parsed;
  try {
    parsed = Json::parse(value);
  } catch (const Json::parse_error&) {
    parsed = value;
  }
  Settings result = settings;
  fromJson(result, *f, parsed, quoted(key));
  validateOrThrow(result, quoted(key));
  settings = result;
}

void loadSettingsFile(const std::string& path, Settings& settings) {
  std::ifstream in(path);
  if (!in) throw SettingsJsonError(path + ": cannot open");
  std::stringstream text;
  text << in.rdbuf();
  applySettingsJson(text.str(), settings, path);
}

void saveSettingsFile(const std::string& path, const Settings& settings) {
  std::ofstream out(path);
  if (!out) throw SettingsJsonError(path + ": cannot open for writing");
  out << settingsToJson(settings);
  if (!out) throw SettingsJsonError(path + ": write failed");
}

}  // namespace vplab
