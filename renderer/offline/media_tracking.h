#pragma once
// Light along one ray through media, for homogeneous boxes and density grids alike (docs/theory.md §16, §22). A ray's
// media intervals (mediumIntervals) are cut into pieces of constant majorant: a homogeneous interval is one exact
// piece (its majorant is its sigma_t), a grid's interval is cut at the cells of its majorant grid. Every estimator
// that needs a distance or a transmittance walks those pieces, so it does not ask whether a medium is a box or a
// grid, and on rays that cross no grid it computes exactly what the closed forms of homogeneous media give, with the
// same random numbers.

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/scene/density_grid.h"
#include "renderer/scene/medium.h"

namespace vplab {

/// A part [t0, t1) of a ray in one medium with one majorant.
struct MediumPiece {
  float t0 = 0.0f, t1 = 0.0f;
  uint32_t medium = 0;
  glm::vec3 sigmaMax{0.0f};    ///< majorant of sigma_t per channel over the piece
  glm::vec3 sigmaMin{0.0f};    ///< minorant (the control of residual ratio tracking)
  float densityMax = 1.0f;     ///< the grid's bounds over the piece (densityScale not applied); 1 when exact
  float densityMin = 1.0f;
  bool exact = true;           ///< homogeneous: sigma_t is sigmaMax everywhere on the piece
};

/// Calls visit(piece) for the pieces of origin + t * direction, t in [0, tMax), in order, from the intervals
/// mediumIntervals() gave for that ray; visit returns false to stop.
template <class Visit>
void walkMediumPieces(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals,
                      const glm::vec3& origin, const glm::vec3& direction, float tMax, Visit&& visit) {
  for (const MediumInterval& i : intervals) {
    const float t1 = std::min(i.t1, tMax);
    if (t1 <= i.t0) return;
    const Medium& m = media[i.medium];
    if (!m.density) {
      if (!visit(MediumPiece{i.t0, t1, i.medium, m.sigmaT(), m.sigmaT(), 1.0f, 1.0f, true})) return;
      continue;
    }
    const glm::vec3 o = glm::vec3(m.indexFromWorld * glm::vec4(origin, 1.0f));
    const glm::vec3 d = glm::vec3(m.indexFromWorld * glm::vec4(direction, 0.0f));
    const glm::vec3 perDensity = m.sigmaT() * m.densityScale;
    bool more = true;
    walkMajorants(*m.density, o, d, i.t0, t1, [&](const MajorantPiece& p) {
      more = visit(MediumPiece{p.t0, p.t1, i.medium, perDensity * p.densityMax, perDensity * p.densityMin,
                               p.densityMax, p.densityMin, false});
      return more;
    });
    if (!more) return;
  }
}

/// sigma_t * length per channel, 0 where sigma_t is 0 (an infinite piece of a channel that does not interact).
inline glm::vec3 opticalDepth(const glm::vec3& sigmaT, float length) {
  return {sigmaT.x > 0.0f ? sigmaT.x * length : 0.0f, sigmaT.y > 0.0f ? sigmaT.y * length : 0.0f,
          sigmaT.z > 0.0f ? sigmaT.z * length : 0.0f};
}

/// Transmittance of the media along origin + t * direction, t in [0, tMax): exact (transmittanceOver) on rays that
/// cross no grid; through grids an unbiased estimate by residual ratio tracking over the majorant grid (Novak et al.
/// 2014: the cell's minorant as control, its residual ratio-tracked, Russian roulette once the estimate is low).
glm::vec3 transmittanceAlong(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals,
                             const glm::vec3& origin, const glm::vec3& direction, float tMax);

/// A free flight along a ray (delta tracking, Woodcock et al. 1965, through grids; the closed form through homogeneous
/// media), sampled for one channel and weighted by spectral MIS over the three (docs/theory.md §16).
struct FreeFlight {
  bool scattered = false;
  float t = 0.0f;           ///< where it scattered
  uint32_t medium = 0;
  /// The channel-dependent parts of the path measure (f) and of the density channel c's sampling would give the same
  /// flight (p), for spectral MIS: f / mean(p) is the flight's weight. A scattering event: f = T_maj sigma_s(x) N,
  /// p = T_maj sigma_t(x) N; no event: f = p = T_maj N (T_maj the majorant transmittance, N the null collisions'
  /// majorants). Exactly sigma_s T, sigma_t T or T in homogeneous media.
  glm::vec3 f{1.0f};
  glm::vec3 p{1.0f};
};
/// Samples the flight with the channel u.x picks (uniformly) and the exponential draw u.y.
FreeFlight sampleFlight(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals,
                        const glm::vec3& origin, const glm::vec3& direction, float tMax, glm::vec2 u);

/// A distance along the camera ray, inside the media intervals before `end`, with density proportional to
/// mean_c mu_c(t) T_maj,c(t) (the free flight through the majorants, conditioned on a tentative collision before
/// `end`; the true free flight in homogeneous media): returns false when no channel can scatter there.
/// tOut, mediumOut, weightOut = T(t) sigma_s(t) / pdf(t), T estimated by ratio tracking where a grid lies before t.
bool sampleForcedFlight(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals,
                        const glm::vec3& origin, const glm::vec3& direction, float end, glm::vec2 u, float& tOut,
                        uint32_t& mediumOut, glm::vec3& weightOut);

/// The density with which a free flight along origin + t * direction scatters at t, for the MIS weights of distance
/// sampling toward the lights (docs/theory.md §24); 0 outside the media intervals before `end`.
/// forced = true: sampleForcedFlight()'s density, exact (it draws from the majorants).
/// forced = false: sampleFlight()'s, the path's flight: sum_c w_c sigma_t,c(t) T_c(t) with w = channelWeights / their
/// sum (the path's spectral MIS channel probabilities). Exact in homogeneous media; through a grid T_c is taken as
/// exp(-(sigma_max + sigma_min) / 2 length) per majorant piece, a deterministic approximation (an MIS weight may use
/// any density that is a fixed function of the path: the weights still sum to one).
float flightDensity(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals,
                    const glm::vec3& origin, const glm::vec3& direction, float end, float t, bool forced,
                    const glm::vec3& channelWeights = glm::vec3(1.0f));

}  // namespace vplab
