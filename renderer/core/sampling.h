#pragma once
// Random numbers, warping functions and orthonormal frames shared by every CPU estimator.
// Determinism rule: every random stream is derived from (settings seed, pixel or path index, pass), never from a
// thread id or a global counter, so images do not depend on the thread count.

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>

namespace vplab {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 1.0f / kPi;
inline constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

/// 64-bit mix (SplitMix64 finaliser): turns structured keys (seed, pixel, pass) into independent stream seeds.
inline uint64_t mixBits(uint64_t v) {
  v ^= v >> 31;
  v *= 0x7fb5d329728ea185ull;
  v ^= v >> 27;
  v *= 0x81dadef4bc2dd44dull;
  v ^= v >> 33;
  return v;
}

inline uint64_t hashKey(uint64_t a, uint64_t b = 0, uint64_t c = 0) {
  return mixBits(a ^ mixBits(b ^ mixBits(c + 0x9e3779b97f4a7c15ull)));
}

/// PCG32 (O'Neill 2014): small state, good statistics, cheap to seed per pixel.
class Rng {
 public:
  Rng() = default;
  explicit Rng(uint64_t seed, uint64_t stream = 0x853c49e6748fea9bull) { seedWith(seed, stream); }

  void seedWith(uint64_t seed, uint64_t stream) {
    state_ = 0;
    inc_ = (stream << 1u) | 1u;
    nextUint();
    state_ += seed;
    nextUint();
  }

  uint32_t nextUint() {
    uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
  }

  /// Uniform in [0, 1).
  float next1D() { return std::fmin(static_cast<float>(nextUint()) * 0x1p-32f, kOneMinusEpsilon); }
  glm::vec2 next2D() {
    float a = next1D();
    return {a, next1D()};
  }

 private:
  uint64_t state_ = 0x853c49e6748fea9bull;
  uint64_t inc_ = 0xda3e39cb94b95bdbull;
};

/// Orthonormal basis around a unit normal (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
struct Frame {
  glm::vec3 s, t, n;
  Frame() = default;
  explicit Frame(const glm::vec3& normal) : n(normal) {
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    s = glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t = glm::vec3(b, sign + n.y * n.y * a, -n.y);
  }
  glm::vec3 toLocal(const glm::vec3& v) const { return {glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)}; }
  glm::vec3 toWorld(const glm::vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

/// Concentric disk mapping (Shirley & Chiu 1997): keeps strata intact, which the QMC VPL sequence relies on.
inline glm::vec2 sampleConcentricDisk(glm::vec2 u) {
  glm::vec2 o = 2.0f * u - glm::vec2(1.0f);
  if (o.x == 0.0f && o.y == 0.0f) return {0.0f, 0.0f};
  float r, theta;
  if (std::abs(o.x) > std::abs(o.y)) {
    r = o.x;
    theta = (kPi / 4.0f) * (o.y / o.x);
  } else {
    r = o.y;
    theta = (kPi / 2.0f) - (kPi / 4.0f) * (o.x / o.y);
  }
  return r * glm::vec2(std::cos(theta), std::sin(theta));
}

/// Cosine-weighted direction around +z; pdf = cos(theta) / pi.
inline glm::vec3 sampleCosineHemisphere(glm::vec2 u) {
  glm::vec2 d = sampleConcentricDisk(u);
  float z = std::sqrt(std::fmax(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}
inline float cosineHemispherePdf(float cosTheta) { return cosTheta > 0.0f ? cosTheta * kInvPi : 0.0f; }

/// Uniform direction inside the cone of half-angle acos(cosThetaMax) around +z; pdf = 1 / (2 pi (1 - cosThetaMax)).
inline glm::vec3 sampleUniformCone(glm::vec2 u, float cosThetaMax) {
  float cosTheta = (1.0f - u.x) + u.x * cosThetaMax;
  float sinTheta = std::sqrt(std::fmax(0.0f, 1.0f - cosTheta * cosTheta));
  float phi = 2.0f * kPi * u.y;
  return {std::cos(phi) * sinTheta, std::sin(phi) * sinTheta, cosTheta};
}
inline float uniformConePdf(float cosThetaMax) { return 1.0f / (2.0f * kPi * (1.0f - cosThetaMax)); }

/// Uniform point on a triangle as barycentrics (b0, b1); b2 = 1 - b0 - b1 (Heitz 2019 low-distortion map).
inline glm::vec2 sampleUniformTriangle(glm::vec2 u) {
  float b0, b1;
  if (u.x < u.y) {
    b0 = u.x / 2.0f;
    b1 = u.y - b0;
  } else {
    b1 = u.y / 2.0f;
    b0 = u.x - b1;
  }
  return {b0, b1};
}

/// The radical inverse of `index` in `base` (the Halton sequence's coordinate for that base), in [0, 1).
inline float radicalInverse(uint32_t base, uint64_t index) {
  const double invBase = 1.0 / base;
  double factor = invBase, result = 0.0;
  while (index > 0) {
    result += factor * static_cast<double>(index % base);
    index /= base;
    factor *= invBase;
  }
  return std::fmin(static_cast<float>(result), kOneMinusEpsilon);
}

/// u shifted by `offset` modulo 1 (a Cranley-Patterson rotation: a seed moves a low-discrepancy set without
/// breaking its stratification), in [0, 1).
inline float rotateUnit(float u, float offset) {
  u += offset;
  if (u >= 1.0f) u -= 1.0f;
  return std::fmin(u, kOneMinusEpsilon);
}

/// Veach's power heuristic with beta = 2.
inline float powerHeuristic(float pdfA, float pdfB) {
  float a = pdfA * pdfA, b = pdfB * pdfB;
  if (!(a + b > 0.0f)) return 0.0f;
  if (std::isinf(a)) return 1.0f;
  return a / (a + b);
}

inline float luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

}  // namespace vplab
