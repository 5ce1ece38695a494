#pragma once
// Lightcuts (Walter et al. 2005; docs/methods.md "Lightcuts"): the bounded VPL sum of Method::Vpl,
//   sum_i f(x1; wo, w_i) min(G(x1, x2_i), b) V(x1, x2_i) f(x2_i; w_in, -w_i) Phi_i,
// over the same VplSet, evaluated through a cut of the light tree (light_tree.h) instead of every VPL.
//
// Per camera sample, at the first hit x1:
//   1. the cut starts as the root; a node C with representative r is estimated as
//        E_C = f(x1; wo, w_r) min(G_r, b) V_r s_r(w_r) I_C        (s_r = f(x2_r; w_in, -w_r) Phi_r / I_r, luminance)
//      and a single VPL exactly as in the exact sum (its own contribution times V);
//   2. the node of largest error bound B_C I_C (lightcut_bound.h) is replaced by its two children (the child that
//      keeps the parent's representative reuses its shadow ray), until every node's bound is at most
//      Settings::lightcutError times the luminance of the current estimate sum_C E_C, or the cut holds
//      Settings::lightcutMax nodes;
//   3. the estimate is sum over the cut of E_C.
// With lightcutError = 0 and lightcutMax >= the VPL count every node with a non-zero bound is refined down to its
// VPLs: the exact sum of Method::Vpl (nodes of bound 0 hold only VPLs whose contribution is 0).
// The rest of the camera sample (emission, the direct light) is renderVpl's, with the same random numbers: the cut
// draws none. Method::LightcutsKK adds Kollig & Keller's compensation of the residual, exactly as vpl-kk computes it
// (its own gathers at the compensation vertices use every VPL; docs/methods.md says where the time goes).
// Refused (requireLightcutsApply): scenes with participating media and medium VPLs (no orientation cone to bound the
// phase function's VPLs, nor a bound for receivers in a medium), and VSLs (a VSL radius > 0: the sphere's integral is
// not bounded by 1 / d_min^2).

#include <cstdint>
#include <vector>

#include "renderer/offline/light_tree.h"
#include "renderer/offline/render_methods.h"
#include "renderer/vpl/vpl_contribution.h"

namespace vplab {

/// One receiver's cut.
struct Lightcut {
  glm::vec3 radiance{0.0f};   ///< sum over the cut of E_C
  glm::vec3 unclamped{0.0f};  ///< the same with G instead of G_b (for the energy the bound removes)
  float errorBound = 0.0f;    ///< sum of B_C luminance(I_C) over the cut's inner nodes: |estimate - exact| (luminance)
  uint32_t nodes = 0;         ///< nodes in the cut
  uint32_t shadowRays = 0;
  bool maxReached = false;  ///< stopped by lightcutMax before every bound fell below the threshold
};

/// The cut at one surface point, for a tree over `vpls` (brdfs: the VPLs' f(x2) parameters).
class LightcutGather {
 public:
  LightcutGather(const EmbreeScene& embree, const std::vector<Vpl>& vpls, const std::vector<BrdfParams>& brdfs,
                 const LightTree& tree, float clampBound, float relativeError, int maxCut);
  Lightcut gather(const ShadingPoint& sp) const;

 private:
  const EmbreeScene& embree_;
  const std::vector<Vpl>& vpls_;
  const std::vector<BrdfParams>& brdfs_;
  const LightTree& tree_;
  float clampBound_;
  float relativeError_;
  uint32_t maxCut_;
};

struct LightcutsRenderResult : VplRenderResult {
  double treeSeconds = 0.0;  ///< light tree build (inside `seconds`)
  std::size_t treeNodes = 0;
  std::size_t treeBytes = 0;    ///< nodes x sizeof(LightTreeNode)
  double meanCut = 0.0;         ///< nodes per cut, over every camera sample that hit a lit surface
  double meanShadowRays = 0.0;  ///< shadow rays per such cut
  uint64_t cuts = 0;
  uint64_t cutsAtMax = 0;  ///< cuts stopped by lightcutMax
};

/// What a cut-size image (VplRenderResult::cutSize) says over the pixels whose cuts hold a node (lit surfaces).
struct CutSizeSummary {
  std::size_t pixels = 0;  ///< pixels with a cut
  double mean = 0.0, p95 = 0.0, max = 0.0;
  double atMax = 0.0;  ///< share of those pixels whose mean cut reached maxCut
};
CutSizeSummary summarizeCutSizes(const Image& cutSize, int maxCut);

/// Throws SceneError for a scene with media and std::invalid_argument for VSLs (see above), each saying what to use;
/// `method` names the method refusing (lightcuts, or mrcs, which refuses the same).
void requireLightcutsApply(const Scene& scene, const Settings& settings, Method method);

/// Renders settings.width x settings.height with lightcuts (method Lightcuts or LightcutsKK), after
/// requireLightcutsApply.
LightcutsRenderResult renderLightcuts(const OfflineScene& offline, const VplSet& vpls, Method method,
                                      const Settings& settings, RenderControl* control = nullptr, OnPass onPass = {});

}  // namespace vplab
