#include "renderer/vpl/generation_methods.h"

#include "renderer/vpl/generation_detail.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace vplab {

const std::vector<GenerationMethod>& generationMethods() {
  static const std::vector<GenerationMethod> methods = {
      {VplGeneration::Light, "light", "light tracing", "Keller 1997",
       "VPLs where the light goes: at every bounce of light paths traced from the lights", false,
       &generateLightTraced},
      {VplGeneration::Bidirectional, "bidirectional", "bidirectional IR", "Segovia et al. 2006",
       "candidates from light paths and from camera points, resampled in proportion to their importance", true,
       &generateBidirectional},
      {VplGeneration::Metropolis, "metropolis", "Metropolis IR", "Segovia et al. 2007",
       "light paths from Markov chains whose target is the paths' importance to the camera", true,
       &generateMetropolis},
  };
  return methods;
}

const GenerationMethod& generationMethod(VplGeneration id) {
  for (const GenerationMethod& m : generationMethods())
    if (m.id == id) return m;
  throw std::logic_error("generation method missing from generationMethods()");
}

const char* toString(VplGeneration generation) { return generationMethod(generation).name; }

bool parseGeneration(const std::string& text, VplGeneration& out) {
  for (const GenerationMethod& m : generationMethods())
    if (text == m.name) {
      out = m.id;
      return true;
    }
  return false;
}

const std::vector<GenerationVariant>& generationVariants() {
  static const std::vector<GenerationVariant> variants = {
      {"vpl", "light tracing", VplGeneration::Light, false},
      {"reject", "light tracing + rejection", VplGeneration::Light, true},
      {"bidirectional", "bidirectional IR", VplGeneration::Bidirectional, false},
      {"metropolis", "Metropolis IR", VplGeneration::Metropolis, false},
  };
  return variants;
}

const GenerationVariant& generationVariantOf(const Settings& settings) {
  for (const GenerationVariant& v : generationVariants())
    if (v.generation == settings.generation && v.rejection == (settings.rejection && v.generation == VplGeneration::Light))
      return v;
  return generationVariants().front();
}

const GenerationVariant* findGenerationVariant(const std::string& name) {
  for (const GenerationVariant& v : generationVariants())
    if (name == v.name) return &v;
  return nullptr;
}

void applyGenerationVariant(const GenerationVariant& variant, Settings& settings) {
  settings.generation = variant.generation;
  settings.rejection = variant.rejection;
}

std::string describeVplStats(const VplStats& st) {
  char buf[512];
  int n = std::snprintf(buf, sizeof buf, "%s: %llu VPLs of %llu candidates (acceptance %.1f%%", toString(st.generation),
                        static_cast<unsigned long long>(st.accepted), static_cast<unsigned long long>(st.candidates),
                        100.0 * st.acceptanceRate);
  std::string line(buf, static_cast<std::size_t>(std::max(n, 0)));
  if (st.predictedAcceptance > 0.0) {
    std::snprintf(buf, sizeof buf, ", pilot predicts %.1f +- %.1f%%", 100.0 * st.predictedAcceptance,
                  100.0 * st.acceptanceSpread);
    line += buf;
  }
  line += ")";
  if (st.candidateCapReached) line += ", candidate cap reached";
  if (st.generation == VplGeneration::Bidirectional) {
    std::snprintf(buf, sizeof buf, ", %llu light paths + %llu camera candidates",
                  static_cast<unsigned long long>(st.pathsTraced), static_cast<unsigned long long>(st.cameraCandidates));
    line += buf;
  } else if (st.generation == VplGeneration::Metropolis) {
    std::snprintf(buf, sizeof buf, ", %llu bootstrap paths, %llu mutations (%.1f%% accepted)",
                  static_cast<unsigned long long>(st.pathsTraced), static_cast<unsigned long long>(st.chainSteps),
                  100.0 * st.mutationAcceptance);
    line += buf;
  } else {
    std::snprintf(buf, sizeof buf, ", %llu light paths", static_cast<unsigned long long>(st.pathsTraced));
    line += buf;
  }
  std::snprintf(buf, sizeof buf, ", %.3f s", st.generationSeconds);
  return line + buf;
}

bool usesImportancePoints(const Settings& settings) {
  return settings.rejection || generationMethod(settings.generation).usesImportance;
}

}  // namespace vplab
