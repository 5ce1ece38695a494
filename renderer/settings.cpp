#include "renderer/settings.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace vplab {

namespace {

template <typename T>
void checkRange(std::vector<std::string>& problems, const char* name, T value, T lo, T hi) {
  bool ok;
  if constexpr (std::is_floating_point_v<T>)
    ok = !std::isnan(value) && value >= lo && value <= hi;
  else
    ok = value >= lo && value <= hi;
  if (!ok) {
    std::ostringstream s;
    s << name << " = " << value << " is outside [" << lo << ", " << hi << "]";
    problems.push_back(s.str());
  }
}

// A share or probability that must be positive: (0, 1].
void checkUnitInterval(std::vector<std::string>& problems, const char* name, float value) {
  if (value > 0.0f && value <= 1.0f) return;
  std::ostringstream s;
  s << name << " = " << value << " is outside (0, 1]";
  problems.push_back(s.str());
}

}  // namespace

std::vector<std::string> validateSettings(const Settings& s) {
  std::vector<std::string> p;
  checkRange(p, "width", s.width, 1, 16384);
  checkRange(p, "height", s.height, 1, 16384);
  checkRange(p, "threads", s.threads, 0, 1024);
  checkRange(p, "exposure", s.exposure, -20.0f, 20.0f);
  checkRange(p, "samplesPerPixel", s.samplesPerPixel, 1, 1 << 20);
  checkRange(p, "exactSamplesPerPixel", s.exactSamplesPerPixel, 1, 1 << 20);
  checkRange(p, "maxDepth", s.maxDepth, 1, 1024);
  checkRange(p, "vplCount", s.vplCount, 0, 1 << 20);
  checkRange(p, "vplMaxBounces", s.vplMaxBounces, 1, 64);
  checkRange(p, "rejectionEpsilon", s.rejectionEpsilon, 0.0f, 1.0f);
  checkRange(p, "rejectionPilotVpls", s.rejectionPilotVpls, 1, 65536);
  checkRange(p, "importancePoints", s.importancePoints, 1, 65536);
  checkRange(p, "rejectionMaxCandidateFactor", s.rejectionMaxCandidateFactor, 1, 10000);
  if (s.rejection && s.generation != VplGeneration::Light)
    p.push_back(std::string("rejection = true needs generation = light (") + toString(s.generation) +
                " already chooses its VPLs by importance)");
  checkRange(p, "birCandidateFactor", s.birCandidateFactor, 1, 256);
  checkUnitInterval(p, "birLightShare", s.birLightShare);
  checkRange(p, "birEpsilon", s.birEpsilon, 0.0f, 1.0f);
  checkRange(p, "mirChains", s.mirChains, 1, 4096);
  checkUnitInterval(p, "mirLargeStepProbability", s.mirLargeStepProbability);
  checkRange(p, "mirBurnIn", s.mirBurnIn, 0, 100000);
  checkRange(p, "mirBootstrapPaths", s.mirBootstrapPaths, 16, 1 << 20);
  checkRange(p, "mirEpsilon", s.mirEpsilon, 0.0f, 1.0f);
  checkRange(p, "clampBound", s.clampBound, 0.0f, kInfinity);
  checkRange(p, "ssbcSteps", s.ssbcSteps, 0, 2);
  checkRange(p, "vslRadius", s.vslRadius, 0.0f, std::numeric_limits<float>::max());
  checkRange(p, "vslSamples", s.vslSamples, 1, 256);
  checkRange(p, "directLightSamples", s.directLightSamples, 1, 4096);
  checkRange(p, "interleave", s.interleave, 1, 8);
  checkRange(p, "shadowMapSize", s.shadowMapSize, 16, 2048);
  checkRange(p, "shadowBias", s.shadowBias, 0.0f, 0.1f);
  checkRange(p, "ismTileSize", s.ismTileSize, 16, 512);
  if (s.ismTileSize > 0 && (s.ismTileSize & (s.ismTileSize - 1)) != 0)
    p.push_back("ismTileSize = " + std::to_string(s.ismTileSize) + " is not a power of two");
  checkRange(p, "ismPointBudget", s.ismPointBudget, 1024, 1 << 25);
  return p;
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

const char* toString(VisibilityMethod visibility) {
  switch (visibility) {
    case VisibilityMethod::Cube: return "cube";
    case VisibilityMethod::Ism: return "ism";
  }
  return "?";
}

bool parseVisibilityMethod(const std::string& text, VisibilityMethod& out) {
  for (VisibilityMethod v : {VisibilityMethod::Cube, VisibilityMethod::Ism})
    if (text == toString(v)) {
      out = v;
      return true;
    }
  return false;
}

bool parseMethod(const std::string& text, Method& out) {
  for (Method m : {Method::Reference, Method::Vpl, Method::VplKK, Method::Vsl})
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
