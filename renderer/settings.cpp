#include "renderer/settings.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace vplab {

namespace {

/// An enum member of N values 0..N-1, named by toString().
template <typename E, int N, E Settings::*Member>
SettingChoice choice() {
  SettingChoice c;
  for (int i = 0; i < N; ++i) c.names.emplace_back(toString(static_cast<E>(i)));
  c.get = [](const Settings& s) { return static_cast<int>(s.*Member); };
  c.set = [](Settings& s, int i) { s.*Member = static_cast<E>(i); };
  return c;
}

constexpr double kMaxFloat = std::numeric_limits<float>::max();
constexpr unsigned kUseVplGather = kUseCpuVpl | kUseGl;

std::string formatNumber(double v, bool integral) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream s;
  if (integral)
    s << static_cast<long long>(v);
  else
    s << v;
  return s.str();
}

std::string spelled(const std::string& key, SettingSpelling spelling) {
  return spelling == SettingSpelling::Flag ? "--" + settingFlag(key) : key;
}

}  // namespace

const std::vector<SettingInfo>& settingsTable() {
  // key, member, min, max, value name, help (unit; the default is appended per command), passes.
  static const std::vector<SettingInfo> table = {
      {"width", &Settings::width, 1, 16384, "W", "image width in pixels", kUseImage, false},
      {"height", &Settings::height, 1, 16384, "H", "image height in pixels", kUseImage, false},
      {"seed", &Settings::seed, 0, 4294967295.0, "S", "seed of every random sequence", kUseImage},
      {"threads", &Settings::threads, 0, 1024, "T", "CPU worker threads, 0 = all cores", kUseImage},
      {"exposure", &Settings::exposure, -20, 20, "EV", "PNG and display exposure in stops", kUseImage},
      {"stage", choice<Stage, 3, &Settings::stage>(), 0, 0, "auto|none|studio",
       "studio around the model: ground, backdrop, area light (auto: only for a scene without lights)", kUseImage},
      {"samplesPerPixel", &Settings::samplesPerPixel, 1, 1 << 20, "N", "samples per pixel of the path-traced reference",
       kUseReference},
      {"exactSamplesPerPixel", &Settings::exactSamplesPerPixel, 1, 1 << 20, "N",
       "samples per pixel of the exact VPL render (each sums every VPL)", kUseCpuVpl},
      {"maxDepth", &Settings::maxDepth, 1, 1024, "D", "maximum path length in bounces (reference, vpl-kk)",
       kUseReference | kUseCpuVpl},
      {"components", choice<Components, 3, &Settings::components>(), 0, 0, "all|direct|indirect",
       "radiance components in the image", kUseReference | kUseCpuVpl | kUseGl},
      {"generation", choice<VplGeneration, 3, &Settings::generation>(), 0, 0, "light|bidirectional|metropolis",
       "how VPLs are generated", kUseGeneration},
      {"vplCount", &Settings::vplCount, 0, 1 << 20, "N",
       "number of VPLs (expected; accepted ones with rejection; about this many from metropolis)", kUseGeneration},
      {"vplMaxBounces", &Settings::vplMaxBounces, 1, 64, "K", "VPLs are stored at bounces 1..K", kUseGeneration},
      {"importancePoints", &Settings::importancePoints, 1, 65536, "M",
       "camera-visible points a VPL's importance is measured at (rejection, bidirectional, metropolis)",
       kUseGeneration},
      {"rejection", &Settings::rejection, 0, 0, "",
       "rejection of unimportant VPLs (Georgiev-Slusallek; generation light)", kUseGeneration},
      {"rejectionEpsilon", &Settings::rejectionEpsilon, 0, 1, "e", "rejection epsilon: p = min(Phi/Phi_v + e, 1)",
       kUseGeneration},
      {"rejectionPilotVpls", &Settings::rejectionPilotVpls, 1, 65536, "N", "pilot VPLs that estimate Phi_v",
       kUseGeneration},
      {"rejectionMaxCandidateFactor", &Settings::rejectionMaxCandidateFactor, 1, 10000, "F",
       "cap on candidates traced, as a multiple of the VPL count", kUseGeneration},
      {"birCandidateFactor", &Settings::birCandidateFactor, 1, 256, "F", "bidirectional: candidates per kept VPL",
       kUseGeneration},
      {"birLightShare", &Settings::birLightShare, 0, 1, "s", "bidirectional: share of light-traced candidates",
       kUseGeneration, true, SettingBound::AboveMin},
      {"birEpsilon", &Settings::birEpsilon, 0, 1, "e", "bidirectional: defensive share of the resampling",
       kUseGeneration},
      {"mirChains", &Settings::mirChains, 1, 4096, "C", "metropolis: independent Markov chains", kUseGeneration},
      {"mirLargeStepProbability", &Settings::mirLargeStepProbability, 0, 1, "p",
       "metropolis: probability of a large step", kUseGeneration, true, SettingBound::AboveMin},
      {"mirBurnIn", &Settings::mirBurnIn, 0, 100000, "B", "metropolis: states discarded per chain", kUseGeneration},
      {"mirBootstrapPaths", &Settings::mirBootstrapPaths, 16, 1 << 20, "N",
       "metropolis: light paths estimating the normalisation", kUseGeneration},
      {"mirEpsilon", &Settings::mirEpsilon, 0, 1, "e", "metropolis: defensive share of the target", kUseGeneration},
      {"clampBound", &Settings::clampBound, 0, kInfinity, "b", "clamp bound b on the geometry term, 1/m^2, inf = none",
       kUseVplGather},
      {"clampBoundRelative", &Settings::clampBoundRelative, 0, kInfinity, "B",
       "clamp bound in units of 1/diagonal^2 of the scene: b = B / diagonal^2, replaces --clamp-bound; 0 = off",
       kUseVplGather},
      {"ssbcSteps", &Settings::ssbcSteps, 0, 2, "0|1|2", "screen-space bias compensation steps", kUseGl},
      {"ssbcCoarseRings", &Settings::ssbcCoarseRings, 0, 0, "", "SSBC rings >= 4 px away on a 4 px grid", kUseGl},
      {"vslRadius", &Settings::vslRadius, 0, kMaxFloat, "r", "virtual spherical light radius in metres, 0 = points",
       kUseGeneration},
      {"vslRadiusFromDensity", &Settings::vslRadiusFromDensity, 0, 0, "",
       "each VSL radius from the local VPL density, scaled by the VSL radius", kUseGeneration},
      {"vslSamples", &Settings::vslSamples, 1, 256, "N", "samples per VSL of the exact CPU render (one-sample MIS)",
       kUseCpuVpl},
      {"lvlTileSize", &Settings::lvlTileSize, 1, 64, "T", "local virtual lights: side of the pixel tiles sharing them",
       kUseCpuVpl},
      {"lvlLightsPerTile", &Settings::lvlLightsPerTile, 1, 4096, "K",
       "local virtual lights per tile and camera sample", kUseCpuVpl},
      {"lightcutError", &Settings::lightcutError, 0, 1, "e",
       "lightcuts: refine a node while its error bound exceeds e x the receiver's estimate; 0 = the exact sum",
       kUseCpuVpl},
      {"lightcutMax", &Settings::lightcutMax, 1, 1 << 24, "N", "lightcuts: most light-tree nodes per cut",
       kUseCpuVpl},
      {"mrcsRows", &Settings::mrcsRows, 1, 4096, "R", "matrix row-column sampling: pixels rendered against every VPL",
       kUseCpuVpl},
      {"mrcsClusters", &Settings::mrcsClusters, 1, 1 << 20, "K",
       "matrix row-column sampling: VPL clusters (one representative each per pixel sample)", kUseCpuVpl},
      {"vrlSamples", &Settings::vrlSamples, 1, 256, "N", "samples per VRL and pixel sample", kUseCpuVpl},
      {"beamRadius", &Settings::beamRadius, 0, kMaxFloat, "r",
       "first virtual beam radius in metres, 0 = 2 % of the scene diagonal", kUseCpuVpl},
      {"beamPasses", &Settings::beamPasses, 1, 4096, "P", "progressive virtual beam passes (fresh VPLs each)",
       kUseCpuVpl},
      {"beamShrink", &Settings::beamShrink, 0, 1, "a", "virtual beam radius shrink alpha: r_i = r_1 (i+1)^((a-1)/2)",
       kUseCpuVpl, true, SettingBound::AboveMin},
      {"directLightSamples", &Settings::directLightSamples, 1, 4096, "K", "shadow-mapped area-light samples", kUseGl},
      {"interleave", &Settings::interleave, 1, 8, "k", "interleaved sampling k x k, 1 = off", kUseGl},
      {"indirectDownscale", &Settings::indirectDownscale, 1, 4, "s",
       "indirect light and its compensation at 1/s of the width and height, upsampled along surfaces", kUseGl},
      {"shadowMapSize", &Settings::shadowMapSize, 16, 2048, "S", "VPL shadow-map resolution in texels", kUseGl},
      {"lightShadowMapSize", &Settings::lightShadowMapSize, 16, 4096, "S",
       "lights' shadow maps: texels per side of a point or spot light's cube face (area-light cells S/2, directional "
       "lights 2S)",
       kUseGl, true, SettingBound::PowerOfTwo},
      {"shadowBias", &Settings::shadowBias, 0, 0.1, "B", "VPL shadow depth bias, fraction of the scene diagonal",
       kUseGl},
      {"visibility", choice<VisibilityMethod, 3, &Settings::visibility>(), 0, 0, "cube|ism|auto",
       "VPL visibility: cube shadow maps, imperfect shadow maps, or auto: cube maps while triangles x VPLs <= "
       VPLAB_AUTO_CUBE_LIMIT,
       kUseGl},
      {"ismTileSize", &Settings::ismTileSize, 16, 512, "T", "imperfect shadow map tile, texels per side", kUseGl, true,
       SettingBound::PowerOfTwo},
      {"ismPointBudget", &Settings::ismPointBudget, 1024, 1 << 25, "P",
       "imperfect shadow maps: surface points shared among the VPLs", kUseGl},
      {"previewRepresentatives", &Settings::previewRepresentatives, 16, 65536, "R",
       "the preview gathers at most R lights: a larger VPL set is reduced per view to R light-tree clusters", kUseGl},
      {"previewGridInBuffer", &Settings::previewGridInBuffer, 0, 0, "",
       "density grids as NanoVDB storage buffers even where a 3D texture holds them", kUseGl},
  };
  return table;
}

const SettingInfo* findSetting(const std::string& key) {
  for (const SettingInfo& info : settingsTable())
    if (key == info.key) return &info;
  return nullptr;
}

std::string settingFlag(const std::string& key) {
  std::string flag;
  for (char c : key) {
    if (std::isupper(static_cast<unsigned char>(c))) {
      flag += '-';
      flag += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    } else {
      flag += c;
    }
  }
  return flag;
}

std::string formatSetting(const Settings& s, const SettingInfo& info) {
  return std::visit(
      [&](const auto& member) -> std::string {
        using M = std::decay_t<decltype(member)>;
        if constexpr (std::is_same_v<M, SettingChoice>) {
          return member.names.at(static_cast<std::size_t>(member.get(s)));
        } else {
          using T = std::decay_t<decltype(s.*member)>;
          if constexpr (std::is_same_v<T, bool>)
            return s.*member ? "true" : "false";
          else
            return formatNumber(static_cast<double>(s.*member), !std::is_floating_point_v<T>);
        }
      },
      info.member);
}

void parseSetting(Settings& s, const SettingInfo& info, const std::string& text) {
  std::visit(
      [&](const auto& member) {
        using M = std::decay_t<decltype(member)>;
        if constexpr (std::is_same_v<M, SettingChoice>) {
          for (std::size_t i = 0; i < member.names.size(); ++i)
            if (text == member.names[i]) return member.set(s, static_cast<int>(i));
          std::string list;
          for (std::size_t i = 0; i < member.names.size(); ++i) list += (i ? ", " : "") + member.names[i];
          throw std::invalid_argument("expected one of " + list);
        } else {
          using T = std::decay_t<decltype(s.*member)>;
          if constexpr (std::is_same_v<T, bool>) {
            if (text == "true" || text == "on" || text == "1") return void(s.*member = true);
            if (text == "false" || text == "off" || text == "0") return void(s.*member = false);
            throw std::invalid_argument("expected true or false");
          } else if constexpr (std::is_floating_point_v<T>) {
            if (text == "inf" || text == "infinity") return void(s.*member = kInfinity);
            char* end = nullptr;
            double v = std::strtod(text.c_str(), &end);
            if (text.empty() || *end != '\0' || std::isnan(v) || std::abs(v) > kMaxFloat)
              throw std::invalid_argument("expected a number or inf");
            s.*member = static_cast<T>(v);
          } else {
            char* end = nullptr;
            errno = 0;
            long long v = std::strtoll(text.c_str(), &end, 10);
            if (text.empty() || *end != '\0' || errno == ERANGE ||
                v < static_cast<long long>(std::numeric_limits<T>::min()) ||
                v > static_cast<long long>(std::numeric_limits<T>::max()))
              throw std::invalid_argument(std::string("expected an integer in [") +
                                          std::to_string(std::numeric_limits<T>::min()) + ", " +
                                          std::to_string(std::numeric_limits<T>::max()) + "]");
            s.*member = static_cast<T>(v);
          }
        }
      },
      info.member);
}

std::vector<std::string> validateSettings(const Settings& s, SettingSpelling spelling) {
  std::vector<std::string> problems;
  for (const SettingInfo& info : settingsTable()) {
    std::visit(
        [&](const auto& member) {
          using M = std::decay_t<decltype(member)>;
          if constexpr (!std::is_same_v<M, SettingChoice>) {
            using T = std::decay_t<decltype(s.*member)>;
            if constexpr (!std::is_same_v<T, bool>) {
              double v = static_cast<double>(s.*member);
              bool aboveMin = info.bound == SettingBound::AboveMin ? v > info.min : v >= info.min;
              bool integral = !std::is_floating_point_v<T>;
              if (std::isnan(v) || !aboveMin || v > info.max) {
                problems.push_back(spelled(info.key, spelling) + " = " + formatSetting(s, info) + " is outside " +
                                   (info.bound == SettingBound::AboveMin ? "(" : "[") +
                                   formatNumber(info.min, integral) + ", " + formatNumber(info.max, integral) + "]");
              } else if (info.bound == SettingBound::PowerOfTwo) {
                auto n = static_cast<long long>(v);
                if ((n & (n - 1)) != 0)
                  problems.push_back(spelled(info.key, spelling) + " = " + formatSetting(s, info) +
                                     " is not a power of two");
              }
            }
          }
        },
        info.member);
  }
  // Rules between settings.
  if (s.rejection && s.generation != VplGeneration::Light)
    problems.push_back(spelled("rejection", spelling) + " = true needs " + spelled("generation", spelling) +
                       " = light (" + toString(s.generation) + " already chooses its VPLs by importance)");
  return problems;
}

void requireValidSettings(const Settings& settings) {
  std::vector<std::string> problems = validateSettings(settings);
  if (problems.empty()) return;
  std::string message = "invalid settings: ";
  for (std::size_t i = 0; i < problems.size(); ++i) message += (i ? "; " : "") + problems[i];
  throw std::invalid_argument(message);
}

const char* toString(Method method) {
  switch (method) {
    case Method::Reference: return "reference";
    case Method::Vpl: return "vpl";
    case Method::VplKK: return "vpl-kk";
    case Method::Vsl: return "vsl";
    case Method::VplAbc: return "vpl-abc";
    case Method::Vrl: return "vrl";
    case Method::Vbl: return "vbl";
    case Method::Lvl: return "lvl";
    case Method::Lightcuts: return "lightcuts";
    case Method::LightcutsKK: return "lightcuts-kk";
    case Method::Mrcs: return "mrcs";
  }
  return "?";
}

const char* toString(Components components) {
  switch (components) {
    case Components::All: return "all";
    case Components::Direct: return "direct";
    case Components::Indirect: return "indirect";
  }
  return "?";
}

const char* toString(Stage stage) {
  switch (stage) {
    case Stage::Auto: return "auto";
    case Stage::None: return "none";
    case Stage::Studio: return "studio";
  }
  return "?";
}

Settings previewDefaultSettings() {
  Settings s;
  s.interleave = 4;
  s.indirectDownscale = 2;
  // VPL maps of 64^2 per cube face instead of 128^2: a quarter of the texels, which were most of the maps' cost, and
  // on seven bundled scenes the same error against the reference within 0.6 % (docs/benchmarks.md "Depth masks for
  // the compensation's sparse passes; VPL maps of 64^2 per face in the preview").
  s.shadowMapSize = 128;
  return s;
}

Settings offlineRenderSettings(const Settings& settings, Method method) {
  Settings s = settings;
  if (method != Method::Reference) s.samplesPerPixel = settings.exactSamplesPerPixel;
  return s;
}

const char* toString(VisibilityMethod visibility) {
  switch (visibility) {
    case VisibilityMethod::Cube: return "cube";
    case VisibilityMethod::Ism: return "ism";
    case VisibilityMethod::Auto: return "auto";
  }
  return "?";
}

void resolveClampBound(Settings& settings, float sceneDiagonal) {
  if (!(settings.clampBoundRelative > 0.0f)) return;
  const double diagonal = std::max(static_cast<double>(sceneDiagonal), 1e-12);
  settings.clampBound = static_cast<float>(
      std::min(static_cast<double>(settings.clampBoundRelative) / (diagonal * diagonal), kMaxFloat));
}

VisibilityMethod resolveVisibility(VisibilityMethod requested, std::size_t triangles, std::size_t vplCount) {
  if (requested != VisibilityMethod::Auto) return requested;
  return static_cast<double>(triangles) * static_cast<double>(vplCount) <= kAutoCubeTriangleVpls
             ? VisibilityMethod::Cube
             : VisibilityMethod::Ism;
}

bool parseVisibilityMethod(const std::string& text, VisibilityMethod& out) {
  for (VisibilityMethod v : {VisibilityMethod::Cube, VisibilityMethod::Ism, VisibilityMethod::Auto})
    if (text == toString(v)) {
      out = v;
      return true;
    }
  return false;
}

bool parseMethod(const std::string& text, Method& out) {
  for (Method m : {Method::Reference, Method::Vpl, Method::VplKK, Method::Vsl, Method::VplAbc, Method::Vrl, Method::Vbl,
                   Method::Lvl, Method::Lightcuts, Method::LightcutsKK,
                   Method::Mrcs})
    if (text == toString(m)) {
      out = m;
      return true;
    }
  return false;
}

bool parseComponents(const std::string& text, Components& out) {
  for (Components c : {Components::All, Components::Direct, Components::Indirect})
    if (text == toString(c)) {
      out = c;
      return true;
    }
  return false;
}

bool parseStage(const std::string& text, Stage& out) {
  for (Stage s : {Stage::Auto, Stage::None, Stage::Studio})
    if (text == toString(s)) {
      out = s;
      return true;
    }
  return false;
}

}  // namespace vplab
