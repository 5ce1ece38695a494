#include "renderer/scene/medium.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "renderer/core/sampling.h"
#include "renderer/core/text.h"
#include "renderer/scene/density_grid.h"

namespace vplab {

glm::vec3 Medium::albedo() const {
  glm::vec3 t = sigmaT();
  return {t.x > 0.0f ? sigmaS.x / t.x : 0.0f, t.y > 0.0f ? sigmaS.y / t.y : 0.0f, t.z > 0.0f ? sigmaS.z / t.z : 0.0f};
}

bool Medium::isVacuum() const {
  glm::vec3 t = sigmaTMax();
  return !(t.x > 0.0f || t.y > 0.0f || t.z > 0.0f);
}

std::vector<glm::vec3> Medium::corners() const {
  std::vector<glm::vec3> out;
  if (fillsSpace) return out;
  for (int i = 0; i < 8; ++i) {
    glm::vec4 c((i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? 1.0f : -1.0f, 1.0f);
    out.push_back(glm::vec3(worldFromBox * c));
  }
  return out;
}

glm::vec3 Medium::meanFreePath() const {
  const glm::vec3 t = sigmaT();
  const float inf = std::numeric_limits<float>::infinity();
  return {t.x > 0.0f ? 1.0f / t.x : inf, t.y > 0.0f ? 1.0f / t.y : inf, t.z > 0.0f ? 1.0f / t.z : inf};
}

glm::vec3 Medium::halfSizes() const {
  return {glm::length(glm::vec3(worldFromBox[0])), glm::length(glm::vec3(worldFromBox[1])),
          glm::length(glm::vec3(worldFromBox[2]))};
}

void Medium::setBox(const glm::mat4& world) {
  worldFromBox = world;
  boxFromWorld = glm::inverse(world);
  indexFromWorld = indexFromBox * boxFromWorld;
}

void Medium::setDensity(std::shared_ptr<const DensityGrid> grid, const glm::mat4& worldFromLocal) {
  // The box in index coordinates is [lower, upper]: index = lower + (q + 1) / 2 (upper - lower) for q in [-1, 1]^3.
  const glm::vec3 lower = grid->boxLower(), upper = grid->boxUpper();
  glm::mat4 indexFromBoxMap(1.0f);
  for (int a = 0; a < 3; ++a) {
    indexFromBoxMap[a][a] = 0.5f * (upper[a] - lower[a]);
    indexFromBoxMap[3][a] = 0.5f * (upper[a] + lower[a]);
  }
  indexFromBox = indexFromBoxMap;
  density = std::move(grid);
  setBox(worldFromLocal * glm::mat4(density->localFromIndex) * indexFromBox);
}

float Medium::densityAt(const glm::vec3& world) const {
  if (!density) return 1.0f;
  return densityScale * density->lookup(glm::vec3(indexFromWorld * glm::vec4(world, 1.0f)));
}

glm::vec3 Medium::sigmaTMax() const {
  return density ? sigmaT() * (densityScale * density->maxValue) : sigmaT();
}

std::string mediumProblem(const Medium& m) {
  const std::string who = "medium '" + m.name + "': ";
  const char* channel[3] = {"r", "g", "b"};
  for (int c = 0; c < 3; ++c) {
    if (!(m.sigmaA[c] >= 0.0f && m.sigmaA[c] <= kMaxMediumSigma))
      return who + "sigmaA." + channel[c] + " must lie in [0, " + numberText(kMaxMediumSigma) + "] 1/m (got " +
             numberText(m.sigmaA[c]) + ")";
    if (!(m.sigmaS[c] >= 0.0f && m.sigmaS[c] <= kMaxMediumSigma))
      return who + "sigmaS." + channel[c] + " must lie in [0, " + numberText(kMaxMediumSigma) + "] 1/m (got " +
             numberText(m.sigmaS[c]) + ")";
  }
  // |g| = 1 is a delta phase function, which no sampler here can evaluate.
  if (!(std::abs(m.g) < 1.0f)) return who + "g must lie in (-1, 1) (got " + numberText(m.g) + ")";
  if (!(m.densityScale >= 0.0f && m.densityScale <= kMaxMediumSigma))
    return who + "density scale must lie in [0, " + numberText(kMaxMediumSigma) + "] (got " +
           numberText(m.densityScale) + ")";
  if (m.density) {
    const glm::vec3 peak = m.sigmaTMax();
    for (int c = 0; c < 3; ++c)
      if (!(peak[c] <= kMaxMediumSigma))
        return who + "scale x largest density x sigma_t." + channel[c] + " = " + numberText(peak[c]) + " exceeds " +
               numberText(kMaxMediumSigma) + " 1/m";
  }
  if (m.fillsSpace) return {};
  double lengths = 1.0;
  for (int i = 0; i < 3; ++i) lengths *= glm::length(glm::dvec3(glm::vec3(m.worldFromBox[i])));
  const double det = glm::determinant(glm::dmat3(glm::mat3(m.worldFromBox)));
  if (!(lengths > 0.0) || !std::isfinite(lengths) || !(std::abs(det) > kMinMediumBoxSquareness * lengths))
    return who + "the box has no volume (a zero size, or axes in one plane)";
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!std::isfinite(m.boxFromWorld[i][j]) || !std::isfinite(m.worldFromBox[i][j]))
        return who + "the box is too small or too large to invert in float";
  return {};
}

std::string mediaProblem(const std::vector<Medium>& media) {
  for (const Medium& m : media)
    if (std::string problem = mediumProblem(m); !problem.empty()) return problem;
  for (std::size_t a = 0; a < media.size(); ++a)
    for (std::size_t b = a + 1; b < media.size(); ++b)
      if (boxesOverlap(media[a], media[b]))
        return "'" + media[b].name + "' and '" + media[a].name + "': " +
               (media[a].fillsSpace || media[b].fillsSpace
                    ? "a medium box cannot lie inside the medium that fills all space"
                    : "medium boxes overlap") +
               "; media must be disjoint";
  return {};
}

void mediumIntervals(const std::vector<Medium>& media, const glm::vec3& origin, const glm::vec3& direction, float tMax,
                     std::vector<MediumInterval>& out) {
  out.clear();
  for (std::size_t m = 0; m < media.size(); ++m) {
    const Medium& medium = media[m];
    if (medium.isVacuum()) continue;
    if (medium.fillsSpace) {
      if (tMax > 0.0f) out.push_back({0.0f, tMax, static_cast<uint32_t>(m)});
      continue;
    }
    // Slab test in the box's own space, where the box is [-1, 1]^3: the map is affine, so the ray parameter t is the
    // same on both sides.
    glm::vec3 o = glm::vec3(medium.boxFromWorld * glm::vec4(origin, 1.0f));
    glm::vec3 d = glm::vec3(medium.boxFromWorld * glm::vec4(direction, 0.0f));
    float t0 = 0.0f, t1 = tMax;
    bool miss = false;
    for (int a = 0; a < 3 && !miss; ++a) {
      if (d[a] == 0.0f) {
        if (o[a] < -1.0f || o[a] > 1.0f) miss = true;
        continue;
      }
      float inv = 1.0f / d[a];
      float tn = (-1.0f - o[a]) * inv, tf = (1.0f - o[a]) * inv;
      if (tn > tf) std::swap(tn, tf);
      t0 = std::max(t0, tn);
      t1 = std::min(t1, tf);
      if (!(t0 < t1)) miss = true;
    }
    if (!miss) out.push_back({t0, t1, static_cast<uint32_t>(m)});
  }
  if (out.size() > 1)
    std::sort(out.begin(), out.end(), [](const MediumInterval& a, const MediumInterval& b) { return a.t0 < b.t0; });
}

int mediumAt(const std::vector<Medium>& media, const glm::vec3& p) {
  for (std::size_t m = 0; m < media.size(); ++m) {
    const Medium& medium = media[m];
    if (medium.fillsSpace) return static_cast<int>(m);
    glm::vec3 q = glm::vec3(medium.boxFromWorld * glm::vec4(p, 1.0f));
    if (std::abs(q.x) <= 1.0f && std::abs(q.y) <= 1.0f && std::abs(q.z) <= 1.0f) return static_cast<int>(m);
  }
  return -1;
}

bool boxesOverlap(const Medium& a, const Medium& b) {
  if (a.fillsSpace || b.fillsSpace) return true;
  // Separating-axis theorem (Gottschalk et al. 1996): two convex boxes are disjoint iff their projections on one of
  // the 15 axes (3 + 3 face normals, 9 edge cross products) do not overlap. Touching faces count as disjoint.
  auto axesOf = [](const Medium& m) {
    std::array<glm::vec3, 3> e;
    for (int i = 0; i < 3; ++i) e[i] = glm::vec3(m.worldFromBox[i]);
    return e;
  };
  const std::array<glm::vec3, 3> ea = axesOf(a), eb = axesOf(b);
  const glm::vec3 ca(a.worldFromBox[3]), cb(b.worldFromBox[3]);
  auto radius = [](const std::array<glm::vec3, 3>& e, const glm::vec3& axis) {
    return std::abs(glm::dot(e[0], axis)) + std::abs(glm::dot(e[1], axis)) + std::abs(glm::dot(e[2], axis));
  };
  std::vector<glm::vec3> axes(ea.begin(), ea.end());
  axes.insert(axes.end(), eb.begin(), eb.end());
  for (const glm::vec3& x : ea)
    for (const glm::vec3& y : eb) axes.push_back(glm::cross(x, y));
  for (const glm::vec3& axis : axes) {
    float len2 = glm::dot(axis, axis);
    if (!(len2 > 1e-12f * (glm::dot(ea[0], ea[0]) + glm::dot(eb[0], eb[0])))) continue;  // parallel edges
    float gap = std::abs(glm::dot(cb - ca, axis)) - radius(ea, axis) - radius(eb, axis);
    // A relative tolerance: boxes that share a face are placed side by side on purpose.
    if (gap >= -1e-5f * (radius(ea, axis) + radius(eb, axis))) return false;
  }
  return true;
}

glm::vec3 transmittanceOver(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals,
                            float tMax) {
  glm::vec3 depth(0.0f);
  for (const MediumInterval& i : intervals) {
    float t1 = std::min(i.t1, tMax);
    if (t1 <= i.t0) break;
    const glm::vec3 sigmaT = media[i.medium].sigmaT();
    const float length = t1 - i.t0;
    // A channel that does not interact stays at depth 0 over an infinite interval (0 * inf would be NaN).
    depth += glm::vec3(sigmaT.x > 0.0f ? sigmaT.x * length : 0.0f, sigmaT.y > 0.0f ? sigmaT.y * length : 0.0f,
                       sigmaT.z > 0.0f ? sigmaT.z * length : 0.0f);
  }
  return glm::exp(-depth);
}

float phaseHG(float cosTheta, float g) {
  // 1 + g^2 - 2 g cos written as a sum of two non-negative terms, (1 - |g|)^2 + 2 |g| (1 - |cos| on the peak's side):
  // the plain form loses the peak to cancellation in float (4e-5 relative at g = 0.95, 1e-3 at g = 0.99).
  float denom = g >= 0.0f ? (1.0f - g) * (1.0f - g) + 2.0f * g * (1.0f - cosTheta)
                          : (1.0f + g) * (1.0f + g) - 2.0f * g * (1.0f + cosTheta);
  return (1.0f - g * g) / (4.0f * kPi * denom * std::sqrt(std::max(denom, 1e-30f)));
}

PhaseSample samplePhaseHG(const glm::vec3& wo, float g, glm::vec2 u) {
  // Invert the HG cdf in cos t (as pbrt-v3 §15.2.3 does, with its opposite sign convention): the direction light
  // travelled before scattering is dIn with cos t = dot(dIn, wo), and wi = -dIn points back toward it.
  float cosTheta;
  if (std::abs(g) < 1e-3f) {
    cosTheta = 1.0f - 2.0f * u.x;
  } else {
    float s = (1.0f - g * g) / (1.0f - g + 2.0f * g * u.x);
    cosTheta = (1.0f + g * g - s * s) / (2.0f * g);
  }
  cosTheta = std::clamp(cosTheta, -1.0f, 1.0f);
  float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
  float phi = 2.0f * kPi * u.y;
  Frame frame(wo);
  glm::vec3 dIn = frame.toWorld(glm::vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta));
  PhaseSample s;
  s.wi = -dIn;
  s.pdf = phaseHG(cosTheta, g);
  return s;
}

}  // namespace vplab
