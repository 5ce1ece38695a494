#pragma once
// Virtual point lights: the value both the GL preview and the Embree pass consume unchanged.

#include <glm/glm.hpp>

#include "renderer/core/object_id.h"

#include <cstdint>
#include <string>
#include <vector>

#include "renderer/settings.h"

namespace vplab {

/// One VPL: light that arrived at a surface point after `bounce` reflections and will be reflected from there.
/// It carries indirect light only (bounce >= 1); its contribution at x1 is f(x1) G V f(x2) flux, where f(x2) is
/// evaluated from the stored incoming direction (docs/methods.md, "The two passes").
struct Vpl {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};    ///< unit shading normal at the VPL
  /// Unit geometric normal (winding order): surfaces are one-sided, so a VPL lights only the side this faces.
  glm::vec3 geometricNormal{0.0f, 0.0f, 1.0f};
  glm::vec3 incoming{0.0f, 0.0f, 1.0f};  ///< unit direction from the VPL back toward where the light came from
  glm::vec3 flux{0.0f};                  ///< path throughput alpha (already divided by the path count and p_accept)
  glm::vec2 uv{0.0f};                    ///< texture coordinates, so f(x2) sees the textured base colour
  uint32_t material = 0;                 ///< index into Scene::materials
  uint32_t bounce = 1;                   ///< number of surface interactions since the light, >= 1
  float radius = 0.0f;                   ///< VSL radius for this light (0 = point VPL)
  /// A medium VPL (docs/theory.md §17): light that scattered at `position` inside Scene::media[medium]. It has no
  /// normal; its "BRDF" is the medium's phase function, evaluated from `incoming`, and it lights every direction.
  bool inMedium = false;
  uint32_t medium = 0;  ///< index into Scene::media when inMedium
};

/// A virtual ray light (Novak et al. 2012a, docs/theory.md §19): the part of a light path's segment that lies in
/// medium `medium`, start + t direction for t in [t0, t1). The segment leaves a light, surface or medium vertex with
/// path throughput `flux` (already divided by the path count); light scatters out of it all along [t0, t1), attenuated
/// by the media's transmittance from `start`. It spans the whole segment up to the next surface, whatever the free
/// flight that continued the path sampled.
struct Vrl {
  glm::vec3 start{0.0f};
  glm::vec3 direction{0.0f, 0.0f, 1.0f};  ///< unit
  float t0 = 0.0f;
  float t1 = 0.0f;
  glm::vec3 flux{0.0f};
  uint32_t medium = 0;
  uint32_t bounce = 0;  ///< interactions before the segment (0: straight from the light)
};

struct VplStats {
  /// The method that produced the set: Settings::generation, or Light after a fallback (see warnings).
  VplGeneration generation = VplGeneration::Light;
  uint64_t pathsTraced = 0;         ///< light paths started (N_paths in the flux normalisation), pilots excluded
  uint64_t candidates = 0;          ///< VPL candidates produced before rejection or resampling
  uint64_t accepted = 0;            ///< VPLs kept
  double acceptanceRate = 1.0;      ///< accepted / candidates
  /// Rejection: the acceptance rate the pilot predicts, and its standard error from the pilot alone (the spread
  /// to expect between seeds: the error of Phi_v and of the mean acceptance probability). 0 without rejection.
  double predictedAcceptance = 0.0;
  double acceptanceSpread = 0.0;
  bool candidateCapReached = false; ///< rejection stopped at Settings::rejectionMaxCandidateFactor
  uint64_t cameraCandidates = 0;    ///< bidirectional: pool candidates that started from a camera point
  uint64_t chainSteps = 0;          ///< Metropolis: recorded mutations over all chains (burn-in excluded)
  double mutationAcceptance = 0.0;  ///< Metropolis: share of recorded mutations accepted
  double generationSeconds = 0.0;   ///< wall time of generateVpls, pilot included
  std::vector<std::string> warnings;  ///< e.g. a fallback to light tracing, with the reason
};

struct VplSet {
  std::vector<Vpl> vpls;
  /// The media segments of the same light paths as virtual ray lights (scenes with media only; the `vrl` and `vbl`
  /// methods light with these instead of the medium VPLs).
  std::vector<Vrl> vrls;
  std::vector<Vpl> rejected;  ///< rejected candidates (kept for display and teaching only)
  VplStats stats;
  /// Every set made has its own (copies keep it): with its address, how a renderer tells another set from the one it
  /// uploaded, also when a new set is assigned to the same variable. Edits in place keep it (the renderers' invalidate
  /// calls say so).
  std::uint64_t id = newObjectId();
};

}  // namespace vplab
