#pragma once
// A VPL's importance: how much it contributes to what the camera sees (docs/methods.md, "Importance"). Rejection,
// bidirectional resampling and the Metropolis target all measure it the same way:
//
//   Phi_i = 1/M sum_k lum( f(x1_k) min(G, b_imp) V f(x2_i) Phi )   over M fixed camera-visible points x1_k
//
// with visibility and a geometry term bounded by b_imp = 1 / (kImportanceDistanceFraction D)^2, D the scene
// diagonal. The bound belongs to the importance only: the user's clamp bound never changes the VPL set, and a VPL
// next to an importance point no longer dominates a mean (the 1/d^2 singularity is what made Phi_v swing with the
// seed).

#include "renderer/offline/embree_scene.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"
#include "renderer/vpl/vpl_contribution.h"

#include <vector>

namespace vplab {

/// The importance bound's distance 1/sqrt(b_imp) as a fraction of the scene diagonal. At a tenth of the diagonal a
/// VPL closer than that to a point counts as if it were that far: near-field peaks are capped at about ten times
/// the typical contribution from a third of the scene away.
inline constexpr float kImportanceDistanceFraction = 0.1f;

/// Camera-visible points: primary hits through the centres of a coarse grid of about settings.importancePoints
/// cells over the image (deterministic; misses and back faces are dropped).
std::vector<ShadingPoint> importancePoints(const OfflineScene& offline, const Settings& settings);
/// The same for `count` points of a width x height image seen by `camera`.
std::vector<ShadingPoint> importancePoints(const OfflineScene& offline, const Camera& camera, int count, int width,
                                           int height);

class ImportanceEstimator {
 public:
  ImportanceEstimator(const OfflineScene& offline, const Settings& settings);

  /// True when no importance point sees a surface (camera inside a wall, black frame): every importance is 0.
  bool empty() const { return points_.empty(); }
  const std::vector<ShadingPoint>& points() const { return points_; }
  float bound() const { return bound_; }

  /// Phi_i of `vpl` with its flux as stored. Thread-safe.
  double operator()(const Vpl& vpl) const;

 private:
  const Scene& scene_;
  const EmbreeScene& embree_;
  std::vector<ShadingPoint> points_;
  float bound_;
};

}  // namespace vplab
