#include "renderer/invalidation.h"

#include "renderer/offline/render_methods.h"
#include "renderer/vpl/generation_methods.h"

namespace vplab {

Staleness& Staleness::operator|=(const Staleness& o) {
  vpls |= o.vpls;
  representatives |= o.representatives;
  vplShadowMaps |= o.vplShadowMaps;
  lightShadowMaps |= o.lightShadowMaps;
  gbuffer |= o.gbuffer;
  direct |= o.direct;
  gather |= o.gather;
  ssbc |= o.ssbc;
  tonemap |= o.tonemap;
  offline |= o.offline;
  return *this;
}

Staleness Staleness::all() {
  Staleness s;
  s.vpls = s.representatives = s.vplShadowMaps = s.lightShadowMaps = s.gbuffer = s.direct = s.gather = s.ssbc =
      s.tonemap = s.offline = true;
  return s;
}

Staleness Staleness::propagated() const {
  Staleness s = *this;
  s.vplShadowMaps |= s.vpls;
  s.representatives |= s.vpls;
  s.direct |= s.gbuffer || s.lightShadowMaps;
  s.gather |= s.gbuffer || s.vpls || s.representatives || s.vplShadowMaps;
  s.ssbc |= s.direct || s.gather;
  s.tonemap |= s.ssbc;
  return s;
}

std::string toString(const Staleness& s) {
  std::string out;
  auto add = [&](bool on, const char* name) {
    if (!on) return;
    if (!out.empty()) out += ' ';
    out += name;
  };
  add(s.vpls, "vpls");
  add(s.representatives, "representatives");
  add(s.vplShadowMaps, "vplShadowMaps");
  add(s.lightShadowMaps, "lightShadowMaps");
  add(s.gbuffer, "gbuffer");
  add(s.direct, "direct");
  add(s.gather, "gather");
  add(s.ssbc, "ssbc");
  add(s.tonemap, "tonemap");
  add(s.offline, "offline");
  return out.empty() ? "nothing" : out;
}

Staleness staleAfterSettingsChange(const Settings& a, const Settings& b, Method method) {
  Staleness s;
  const bool usesVpls = method != Method::Reference;

  // Image size: every per-pixel buffer, and the importance points are pixels of that image.
  if (a.width != b.width || a.height != b.height) {
    s.gbuffer = s.representatives = s.offline = true;
    s.vpls |= usesImportancePoints(a) || usesImportancePoints(b);
  }
  // The seed drives the VPL sequence, the light sample points and the offline sample streams.
  if (a.seed != b.seed) s.vpls = s.lightShadowMaps = s.offline = true;
  if (a.exposure != b.exposure) s.tonemap = true;

  // Reference-only parameters; the VPL methods also take samplesPerPixel (KK and VSL are stochastic).
  if (a.samplesPerPixel != b.samplesPerPixel || a.maxDepth != b.maxDepth) s.offline = true;
  // The editor's exact VPL render takes its own sample count.
  if (a.exactSamplesPerPixel != b.exactSamplesPerPixel) s.offline |= method != Method::Reference;
  if (a.components != b.components) s.gather = s.offline = true;

  // VPL generation (docs/methods.md, "VPL generation"). A method's parameters only matter while it is in use in
  // either state.
  bool vplsChanged = a.generation != b.generation || a.vplCount != b.vplCount || a.vplMaxBounces != b.vplMaxBounces ||
                     a.rejection != b.rejection;
  if (usesImportancePoints(a) || usesImportancePoints(b)) vplsChanged |= a.importancePoints != b.importancePoints;
  if (a.rejection || b.rejection)
    vplsChanged |= a.rejectionEpsilon != b.rejectionEpsilon || a.rejectionPilotVpls != b.rejectionPilotVpls ||
                   a.rejectionMaxCandidateFactor != b.rejectionMaxCandidateFactor;
  auto uses = [&](VplGeneration g) { return a.generation == g || b.generation == g; };
  if (uses(VplGeneration::Bidirectional))
    vplsChanged |= a.birCandidateFactor != b.birCandidateFactor || a.birLightShare != b.birLightShare ||
                   a.birEpsilon != b.birEpsilon;
  if (uses(VplGeneration::Metropolis))
    vplsChanged |= a.mirChains != b.mirChains || a.mirLargeStepProbability != b.mirLargeStepProbability ||
                   a.mirBurnIn != b.mirBurnIn || a.mirBootstrapPaths != b.mirBootstrapPaths ||
                   a.mirEpsilon != b.mirEpsilon;
  if (vplsChanged) {
    s.vpls = true;
    s.offline |= usesVpls;
  }

  // The bound b acts in the gather only (section 4): VPLs and shadow maps stay. The offline methods that clamp go
  // stale (their table row says which): the VPL render, KK compensation (its region depends on b) and approximate
  // compensation in media; the VSL, VRL and beam methods do not clamp.
  if (a.clampBound != b.clampBound || a.clampBoundRelative != b.clampBoundRelative) {
    s.gather = true;
    s.offline |= renderMethod(method).usesClampBound;
  }
  // The CPU's virtual ray lights and beams (sections 19, 20): their samples and the beams' radius schedule.
  if (a.vrlSamples != b.vrlSamples) s.offline |= method == Method::Vrl || method == Method::Vbl;
  if (a.beamRadius != b.beamRadius || a.beamPasses != b.beamPasses || a.beamShrink != b.beamShrink)
    s.offline |= method == Method::Vbl;
  if (a.ssbcSteps != b.ssbcSteps || a.ssbcCoarseRings != b.ssbcCoarseRings) s.ssbc = true;

  // VSLs (section 7) change the gather integral, not the VPL positions. The cone samples are the CPU estimator's
  // only: the preview evaluates the integral without samples.
  if (a.vslRadius != b.vslRadius || a.vslRadiusFromDensity != b.vslRadiusFromDensity) {
    s.gather = true;
    s.offline |= method == Method::Vsl;
  }
  if (a.vslSamples != b.vslSamples) s.offline |= method == Method::Vsl;

  // Preview-only parameters (section 8).
  if (a.directLightSamples != b.directLightSamples || a.lightShadowMapSize != b.lightShadowMapSize)
    s.lightShadowMaps = true;
  // Both the direct light and the gather are interleaved; the bias is the VPL maps' (the lights' maps offset the
  // receiver by a texel instead).
  if (a.interleave != b.interleave) s.direct = s.gather = true;
  if (a.shadowBias != b.shadowBias) s.gather = true;
  // The indirect light's own G-buffer is made with the G-buffer.
  if (a.indirectDownscale != b.indirectDownscale) s.gbuffer = true;
  if (a.previewRepresentatives != b.previewRepresentatives) s.representatives = true;
  // Where the preview keeps a density grid: every pass that reads the media.
  if (a.previewGridInBuffer != b.previewGridInBuffer) s.direct = s.gather = true;
  if (a.shadowMapSize != b.shadowMapSize || a.visibility != b.visibility || a.ismTileSize != b.ismTileSize ||
      a.ismPointBudget != b.ismPointBudget)
    s.vplShadowMaps = true;
  return s.propagated();
}

Staleness staleAfterCameraMove() {
  Staleness s;
  s.gbuffer = s.representatives = s.offline = true;
  return s.propagated();
}

Staleness staleAfterLightEdit() {
  Staleness s;
  s.vpls = s.lightShadowMaps = s.offline = true;
  return s.propagated();
}

Staleness staleAfterMediumEdit(const std::vector<Medium>& before, const std::vector<Medium>& after) {
  // Only what light meets counts: the interacting media, in order, with their coefficients, phase and region.
  auto interacting = [](const std::vector<Medium>& media) {
    std::vector<const Medium*> out;
    for (const Medium& m : media)
      if (!m.isVacuum()) out.push_back(&m);
    return out;
  };
  const std::vector<const Medium*> a = interacting(before), b = interacting(after);
  bool same = a.size() == b.size();
  for (std::size_t i = 0; same && i < a.size(); ++i)
    same = a[i]->sigmaA == b[i]->sigmaA && a[i]->sigmaS == b[i]->sigmaS && a[i]->g == b[i]->g &&
           a[i]->fillsSpace == b[i]->fillsSpace && (a[i]->fillsSpace || a[i]->worldFromBox == b[i]->worldFromBox) &&
           a[i]->density == b[i]->density && a[i]->densityScale == b[i]->densityScale;
  Staleness s;
  if (same) return s;
  s.vpls = s.direct = s.offline = true;
  return s.propagated();
}

}  // namespace vplab
