#include "renderer/offline/media_tracking.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "renderer/core/sampling.h"

namespace vplab {

namespace {

float channelMean(const glm::vec3& v) { return (v.x + v.y + v.z) * (1.0f / 3.0f); }
float maxComponent(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

uint32_t floatBits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

/// The grid's density (densityScale not applied) at a world point of medium m, counted as a majorant violation when it
/// leaves the piece's bounds (beyond float rounding of the lookup's position).
float trackedDensity(const Medium& m, const MediumPiece& piece, const glm::vec3& world) {
  const float d = m.density->lookup(glm::vec3(m.indexFromWorld * glm::vec4(world, 1.0f)));
  const float slack = 1e-4f * m.density->maxValue;
  if (d > piece.densityMax + slack || d < piece.densityMin - slack) majorantViolations().fetch_add(1);
  return d;
}

/// The media's pieces of a ray up to `end`, collected (the forced flight walks them twice).
const std::vector<MediumPiece>& collectPieces(const std::vector<Medium>& media,
                                              const std::vector<MediumInterval>& intervals, const glm::vec3& origin,
                                              const glm::vec3& direction, float end) {
  thread_local std::vector<MediumPiece> pieces;
  pieces.clear();
  walkMediumPieces(media, intervals, origin, direction, end, [](const MediumPiece& p) {
    pieces.push_back(p);
    return true;
  });
  return pieces;
}

/// True when a grid medium's interval starts before tMax.
bool crossesGrid(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals, float tMax) {
  for (const MediumInterval& i : intervals) {
    if (!(i.t0 < tMax)) break;
    if (media[i.medium].density) return true;
  }
  return false;
}

/// A generator for the extra numbers a grid asks for along one ray (null collisions, ratio tracking), seeded from the
/// ray itself and `salt`: deterministic for a given ray whatever thread traces it, and media-free rays draw nothing.
Rng rayRng(const glm::vec3& origin, const glm::vec3& direction, float tMax, uint64_t salt = 0) {
  const uint64_t a = (uint64_t(floatBits(origin.x)) << 32) | floatBits(origin.y);
  const uint64_t b = (uint64_t(floatBits(origin.z)) << 32) | floatBits(direction.x);
  const uint64_t c = (uint64_t(floatBits(direction.y)) << 32) | floatBits(direction.z);
  return Rng(hashKey(a, b, c ^ mixBits((uint64_t(floatBits(tMax)) << 32) ^ salt)));
}

}  // namespace

glm::vec3 transmittanceAlong(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals,
                             const glm::vec3& origin, const glm::vec3& direction, float tMax) {
  if (!crossesGrid(media, intervals, tMax)) return transmittanceOver(media, intervals, tMax);
  Rng rng = rayRng(origin, direction, tMax);
  glm::vec3 control(0.0f);  // optical depth of the minorants: the part known exactly
  glm::vec3 ratio(1.0f);    // the residual's ratio-tracking estimate
  walkMediumPieces(media, intervals, origin, direction, tMax, [&](const MediumPiece& p) {
    // Step 1: the control transmittance exp(-sigma_min length), exact.
    control += opticalDepth(p.sigmaMin, p.t1 - p.t0);
    if (p.exact) return true;
    // Step 2: tentative collisions at the rate of the largest residual majorant over the channels; each multiplies
    // channel c by 1 - (sigma_t,c(x) - sigma_min,c) / mu, in [0, 1] as long as the majorants hold.
    const float mu = maxComponent(p.sigmaMax - p.sigmaMin);
    if (!(mu > 0.0f)) return true;
    const Medium& m = media[p.medium];
    const glm::vec3 perDensity = m.sigmaT() * m.densityScale;
    for (float t = p.t0;;) {
      t -= std::log1p(-rng.next1D()) / mu;
      if (!(t < p.t1)) return true;
      const float d = trackedDensity(m, p, origin + direction * t);
      ratio *= glm::clamp(1.0f - (perDensity * d - p.sigmaMin) / mu, 0.0f, 1.0f);
      // Step 3: Russian roulette once the estimate is low (pbrt-v4 does the same): thick smoke costs a few steps.
      const float level = maxComponent(ratio * glm::exp(-control));
      if (level < 0.05f) {
        if (rng.next1D() < 0.75f) {
          ratio = glm::vec3(0.0f);
          return false;
        }
        ratio /= 0.25f;
      }
    }
  });
  return glm::exp(-control) * ratio;
}

FreeFlight sampleFlight(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals,
                        const glm::vec3& origin, const glm::vec3& direction, float tMax, glm::vec2 u) {
  // Step 1: a channel picked uniformly, an optical depth tau from its exponential distribution.
  const int channel = std::min(2, static_cast<int>(u.x * 3.0f));
  float tau = -std::log1p(-std::min(u.y, kOneMinusEpsilon));
  FreeFlight out;
  glm::vec3 depth(0.0f);  // optical depth of the majorants so far
  glm::vec3 nulls(1.0f);  // the null collisions' channel-dependent factors, normalised to mean 1
  Rng local;
  bool seeded = false;
  // Step 2: walk the pieces in order until the channel's majorant optical depth reaches tau: a tentative collision.
  walkMediumPieces(media, intervals, origin, direction, tMax, [&](const MediumPiece& p) {
    const Medium& m = media[p.medium];
    for (float t = p.t0;;) {
      const float channelDepth = p.sigmaMax[channel] > 0.0f ? p.sigmaMax[channel] * (p.t1 - t) : 0.0f;
      if (!(channelDepth > tau)) {
        tau -= channelDepth;
        depth += opticalDepth(p.sigmaMax, p.t1 - t);
        return true;
      }
      const float tc = t + tau / p.sigmaMax[channel];
      depth += opticalDepth(p.sigmaMax, tc - t);
      // Step 3a: in a homogeneous medium every collision is real: scatter at tc.
      float density = 1.0f;
      if (!p.exact) {
        // Step 3b: in a grid the collision is real with probability sigma_t(x) / mu = d(x) / d_max, the same for
        // every channel (the coefficients share one density), else a null collision and the flight goes on.
        if (!seeded) {
          local = rayRng(origin, direction, tMax, floatBits(u.y));
          seeded = true;
        }
        density = trackedDensity(m, p, origin + direction * tc);
        if (!(local.next1D() * p.densityMax < density)) {
          nulls *= p.sigmaMax / channelMean(p.sigmaMax);
          tau = -std::log1p(-std::min(local.next1D(), kOneMinusEpsilon));
          t = tc;
          continue;
        }
        density *= m.densityScale;
      }
      const glm::vec3 tr = glm::exp(-depth);
      out.scattered = true;
      out.t = tc;
      out.medium = p.medium;
      out.f = m.sigmaS * density * tr * nulls;
      out.p = m.sigmaT() * density * tr * nulls;
      return false;
    }
  });
  // Step 4: no event before the surface (or the end of the ray).
  if (!out.scattered) out.f = out.p = glm::exp(-depth) * nulls;
  return out;
}

bool sampleForcedFlight(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals,
                        const glm::vec3& origin, const glm::vec3& direction, float end, glm::vec2 u, float& tOut,
                        uint32_t& mediumOut, glm::vec3& weightOut) {
  const std::vector<MediumPiece>& pieces = collectPieces(media, intervals, origin, direction, end);
  if (pieces.empty()) return false;
  // Majorant optical depth of each channel over all pieces up to `end`.
  glm::vec3 total(0.0f);
  for (const MediumPiece& p : pieces) total += opticalDepth(p.sigmaMax, p.t1 - p.t0);
  glm::vec3 mass(0.0f);  // probability of a tentative collision before `end`, per channel
  int usable = 0;
  for (int c = 0; c < 3; ++c) {
    mass[c] = std::isinf(total[c]) ? 1.0f : -std::expm1(-total[c]);
    if (mass[c] > 0.0f) ++usable;
  }
  if (usable == 0) return false;
  // Pick one of the channels that can scatter, uniformly.
  const int pick = std::min(usable - 1, static_cast<int>(u.x * static_cast<float>(usable)));
  int channel = 0;
  for (int c = 0, k = 0; c < 3; ++c)
    if (mass[c] > 0.0f && k++ == pick) channel = c;
  float tau = -std::log1p(-u.y * mass[channel]);
  glm::vec3 depth(0.0f);
  bool gridBefore = false;
  for (const MediumPiece& p : pieces) {
    const float len = p.t1 - p.t0;
    const glm::vec3& mu = p.sigmaMax;
    gridBefore = gridBefore || !p.exact;
    const float channelDepth = mu[channel] > 0.0f ? mu[channel] * len : 0.0f;
    if (!(channelDepth > tau) && &p != &pieces.back()) {
      tau -= channelDepth;
      depth += opticalDepth(mu, len);
      continue;
    }
    const float dt = mu[channel] > 0.0f ? std::min(len, tau / mu[channel]) : len;
    depth += opticalDepth(mu, dt);
    const glm::vec3 trMajorant = glm::exp(-depth);
    float pdf = 0.0f;
    for (int c = 0; c < 3; ++c)
      if (mass[c] > 0.0f) pdf += mu[c] * trMajorant[c] / mass[c];
    pdf /= static_cast<float>(usable);
    if (!(pdf > 0.0f)) return false;
    const Medium& m = media[p.medium];
    tOut = p.t0 + dt;
    mediumOut = p.medium;
    if (!gridBefore) {
      // Homogeneous all the way: the majorants are the coefficients, T is the majorant transmittance.
      weightOut = m.sigmaS * trMajorant / pdf;
    } else {
      const glm::vec3 x = origin + direction * tOut;
      weightOut = m.sigmaSAt(x) * transmittanceAlong(media, intervals, origin, direction, tOut) / pdf;
    }
    return true;
  }
  return false;
}

float flightDensity(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals,
                    const glm::vec3& origin, const glm::vec3& direction, float end, float t, bool forced,
                    const glm::vec3& channelWeights) {
  if (!(t >= 0.0f) || !(t < end)) return 0.0f;
  if (forced) {
    // sampleForcedFlight's density: (1 / usable) sum over the channels that can scatter of mu_c T_maj,c(t) / mass_c.
    const std::vector<MediumPiece>& pieces = collectPieces(media, intervals, origin, direction, end);
    glm::vec3 total(0.0f), depth(0.0f), mu(0.0f);
    bool inside = false;
    for (const MediumPiece& p : pieces) {
      total += opticalDepth(p.sigmaMax, p.t1 - p.t0);
      if (t >= p.t1) {
        depth += opticalDepth(p.sigmaMax, p.t1 - p.t0);
      } else if (t >= p.t0 && !inside) {
        depth += opticalDepth(p.sigmaMax, t - p.t0);
        mu = p.sigmaMax;
        inside = true;
      }
    }
    if (!inside) return 0.0f;
    float pdf = 0.0f;
    int usable = 0;
    for (int c = 0; c < 3; ++c) {
      const float mass = std::isinf(total[c]) ? 1.0f : -std::expm1(-total[c]);
      if (!(mass > 0.0f)) continue;
      ++usable;
      pdf += mu[c] * std::exp(-depth[c]) / mass;
    }
    return usable > 0 ? pdf / static_cast<float>(usable) : 0.0f;
  }
  // The path's flight: sigma_t(x(t)) T(t) per channel, mixed by the path's channel probabilities.
  const float sum = channelWeights.x + channelWeights.y + channelWeights.z;
  if (!(sum > 0.0f)) return 0.0f;
  glm::vec3 depth(0.0f);
  float pdf = 0.0f;
  walkMediumPieces(media, intervals, origin, direction, end, [&](const MediumPiece& p) {
    const glm::vec3 sigma = p.exact ? p.sigmaMax : 0.5f * (p.sigmaMax + p.sigmaMin);
    if (t >= p.t1) {
      depth += opticalDepth(sigma, p.t1 - p.t0);
      return true;
    }
    if (t < p.t0) return false;
    depth += opticalDepth(sigma, t - p.t0);
    const Medium& m = media[p.medium];
    const glm::vec3 sigmaT = p.exact ? p.sigmaMax : m.sigmaTAt(origin + direction * t);
    pdf = glm::dot(channelWeights / sum, sigmaT * glm::exp(-depth));
    return false;
  });
  return pdf;
}

}  // namespace vplab
