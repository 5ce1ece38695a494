#pragma once
// The exact VPL renderer (Embree pass): every pixel sample sums all VPLs with exact shadow rays.
//
// Per camera sample through a jittered pixel position, at the first hit x1 (wo toward the camera):
//   L = Le(x1 -> wo)                                   [components All, Direct]
//     + estimateDirectLight(x1)                         [All, Direct]  (the reference's own estimator)
//     + sum_i C_i(x1) V(x1, x2_i)                        [All, Indirect]
//     + K(x1)                                           [All, Indirect, Method::VplKK only]
//
// Method::Vpl, VplKK: C_i = f(x1; wo, w) G_b f(x2; w_in, -w) Phi_i, G_b = min(G, clampBound)
//   (vpl_contribution.h; clampBound = inf is bit-identical to no clamp).
// Method::VplKK: K(x1) is Kollig & Keller's 2004 compensation of the residual transport T_r (docs/theory.md §5):
//   draw w ~ f(x1) cos (pdf p) and trace to x2; if G(x1, x2) > b:
//     K(x1) = f(x1; wo, w) (1 - b / G) cos1 L_r(x2 -> x1) / p,
//     L_r(x2 -> x1) = estimateDirectLight(x2) + sum_i C_i(x2) V + K(x2)      (never Le(x2): T_r acts on L - Le)
//   else K(x1) = 0 (x2 lies outside the bounded region: the recursion ends). Depth is capped at Settings::maxDepth.
// Method::Vsl (Hasan et al. 2009, docs/theory.md §7), clampBound ignored, r_i = vslRadii() (Vpl::radius):
//   C_i = Phi_i T_i,   T_i = 1 / (pi r^2) * integral over Omega of f(x1; wo, w) f(x2; w_in, -w) cos1 cos2 dw
//   Omega: the cone from x1 subtended by the sphere (centre x2, radius r); the whole sphere of directions when
//   |x2 - x1| <= r (so points inside the sphere stay finite). cos1 = max(0, n1.w), cos2 = max(0, n2.(-w)), and w
//   must leave x1 on its front side and reach x2 on the VPL's front side (geometric normals), as for point VPLs.
//   V is one shadow ray to the sphere's centre. T_i is computed exactly, without bias:
//   - a pure-Lambert pair whose cone no surface plane cuts: the closed form of vsl_integral.h (no samples);
//   - a cone entirely behind either surface, or two surfaces facing the same way: 0;
//   - otherwise S = Settings::vslSamples samples under one-sample MIS (balance heuristic, Veach 1997): each sample
//     picks the cone (uniform, pdf 1 / Omega) or the BRDF sampling of a glossy end (f(x1) cos1 from x1, or f(x2)
//     cos2 from the VPL toward -w), with probabilities 1/2 : 1/2 for one glossy end, 1/2 : 1/4 : 1/4 for two, the
//     cone alone for two Lambert ends; T ~ 1/S sum g(w_k) / sum_j p_j pdf_j(w_k) over the samples inside Omega.
//   r = 0 is the point VPL without clamp. As r -> 0, Omega -> pi r^2 / d^2 and C_i -> the point VPL; for d >> r it
//   equals the point VPL.
//
// Random numbers come from the progressive driver's per-(pixel, sample) stream, so the image does not depend on
// the thread count. Samples per pixel: Settings::samplesPerPixel (one VPL sum per sample).

#include "renderer/core/parallel.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/interaction.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/progressive.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"

#include <cstdint>
#include <functional>
#include <memory>

namespace vplab {

/// Per-gather counters (the VPL part only).
struct GatherTally {
  double clampedLum = 0.0;
  double unclampedLum = 0.0;
  uint64_t shadowRays = 0;
  uint64_t evaluations = 0;
  void add(const GatherTally& o) {
    clampedLum += o.clampedLum;
    unclampedLum += o.unclampedLum;
    shadowRays += o.shadowRays;
    evaluations += o.evaluations;
  }
};

struct VplContext;

/// The renderer's estimators at any path vertex, for methods built on them (local virtual lights): the bounded VPL
/// gather and Kollig & Keller's compensation, for one VplSet and Settings (the method decides G_b or the VSLs).
class VplTransport {
 public:
  VplTransport(const OfflineScene& offline, const VplSet& vpls, Method method, const Settings& settings);
  ~VplTransport();
  VplTransport(const VplTransport&) = delete;
  VplTransport& operator=(const VplTransport&) = delete;

  /// sum_i C_i(x) V(x, x2_i) with exact shadow rays.
  glm::vec3 gather(const Interaction& x, Rng& rng, GatherTally& tally, bool trackUnclamped) const;
  /// K(x) at recursion depth `depth` (0 at the camera vertex). On a surface, `incident` (when given and the sample is
  /// valid) receives the sampled direction and the light behind it, so that K toward another wo is f(wo, wi) weight.
  glm::vec3 compensation(const Interaction& x, Rng& rng, int depth, GatherTally& tally,
                         IncidentSample* incident = nullptr) const;
  /// The compensation of the residual that renderVpl adds at x for the transport's method: Kollig & Keller's for
  /// VplKK, the approximate one for VplAbc (in a medium one residual bounce over the ball |y - x| < 1/sqrt(b)), 0 for
  /// Vpl and Vsl or without a bound. Tests take the medium's part of an image with it.
  glm::vec3 methodCompensation(const Interaction& x, Rng& rng, GatherTally& tally) const;

  const std::vector<Vpl>& vpls() const;
  const std::vector<BrdfParams>& vplBrdfs() const;  ///< f(x2) parameters of each VPL
  float clampBound() const;
  int maxDepth() const;

 private:
  std::unique_ptr<VplContext> ctx_;
};

struct VplRenderResult : ProgressiveResult {
  /// Energy removed by the clamp over the VPL (indirect) part: mean(unclamped - clamped) / mean(unclamped), with
  /// luminance averaged over every primary VPL gather of the render, measured in the same pass. 0 without clamp.
  double clampEnergyRemoved = 0.0;
  uint64_t shadowRays = 0;  ///< VPL shadow rays traced (compensation vertices included)
  uint64_t vplEvaluations = 0;  ///< VPL-to-point evaluations (with or without a shadow ray)
  /// Lightcuts: each pixel's mean cut size in light-tree nodes (every channel), for the editor's cut-size view; empty
  /// for the other methods.
  Image cutSize;
};

/// The per-pixel tallies of a render summed into its shadow-ray and evaluation counts and clampEnergyRemoved.
void addTallies(const std::vector<GatherTally>& tallies, VplRenderResult& result);

/// Renders settings.width x settings.height with the given method (Vpl, VplKK or Vsl; Reference is a programmer
/// error). Progressive (one sample per pixel per pass), multithreaded, cancellable through control.
VplRenderResult renderVpl(const OfflineScene& offline, const VplSet& vpls, Method method, const Settings& settings,
                          RenderControl* control = nullptr,
                          std::function<void(const Image& mean, int samplesSoFar)> onPass = {});

}  // namespace vplab
