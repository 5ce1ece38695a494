#pragma once
// Sampling the scene's lights: emissive triangles (one-sided area lights) and KHR_lights_punctual lights (point,
// spot, directional), chosen in proportion to their power. Used for next-event estimation (sampleLi / pdfLi) and for light tracing when VPLs are
// generated (sampleEmission, docs/theory.md §2).

#include "renderer/scene/scene.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace vplab {

/// A light sample seen from a receiving point x.
struct LightSampleLi {
  glm::vec3 position{0.0f};  ///< point on the light (x itself for a directional light, which has none)
  glm::vec3 normal{0.0f};    ///< emitter normal (zero for punctual lights)
  glm::vec3 wi{0.0f};        ///< unit direction from x toward the light
  float distance = 0.0f;     ///< infinite for a directional light
  /// Length of the shadow ray's part that media attenuate, -1 for all of it: a directional light's light enters the
  /// media at its emission disk (directionalMediumDistance()).
  float mediumDistance = -1.0f;
  /// Incident radiance Le (area), intensity / d^2 (point, spot) or irradiance E (directional), before dividing by
  /// pdf: for the delta lights, the factor that multiplies f cos.
  glm::vec3 radiance{0.0f};
  float pdf = 0.0f;          ///< solid-angle pdf including the light choice; for delta lights the choice probability
  /// Solid-angle pdf with which sampleEmission(), having chosen the same light and point, emits toward x; 0 for a
  /// light whose emission direction is a delta. Bidirectional VPL generation weighs its two strategies with it.
  float emissionPdfDirection = 0.0f;
  bool isDelta = false;
  bool valid() const { return pdf > 0.0f; }
};

/// A point and direction leaving a light, for light tracing.
struct EmissionSample {
  glm::vec3 position{0.0f};   ///< on the light; for a directional light, on its emission disk outside the scene
  glm::vec3 normal{0.0f};     ///< emitter normal (zero for punctual lights)
  glm::vec3 direction{0.0f};  ///< unit
  /// Solid-angle pdf of `direction` given the light and the point (0 for a delta direction: directional lights).
  float pdfDirection = 0.0f;
  /// Le cos / (p_light pdf_A pdf_dir) for area lights, I(dir) / (p_light pdf_dir) for point and spot lights,
  /// E / (p_light pdf_A) for a directional light: the initial path throughput alpha_0 before dividing by the number
  /// of paths.
  glm::vec3 weight{0.0f};
  bool valid = false;
};

class LightSampler {
 public:
  explicit LightSampler(const Scene& scene);

  bool empty() const { return cdf_.empty(); }
  std::size_t lightCount() const { return lights_.size(); }
  /// Total emitted power (luminance-weighted RGB average of every light's flux), for statistics.
  glm::vec3 totalPower() const { return totalPower_; }

  /// Next-event estimation: a light chosen by power (uLight; an emissive triangle by its mean textured radiance), a
  /// point uniform on its area (uPoint) carrying the radiance emitted there.
  LightSampleLi sampleLi(const glm::vec3& x, float uLight, glm::vec2 uPoint) const;
  /// The point on the light that sampleLi() picks with the same numbers, whatever the receiving point (the choice and
  /// the point do not depend on it): false for a directional light, which has none. Equiangular distance sampling
  /// toward the chosen light draws the light first (docs/theory.md §24).
  /// punctual, when given, says whether it is a point or spot light (else a point on an emitting triangle).
  bool samplePosition(float uLight, glm::vec2 uPoint, glm::vec3& position, bool* punctual = nullptr) const;
  /// Direction sampling toward the point and spot lights, for paths through media (docs/theory.md §24): the
  /// equiangular estimate of a segment passing at distance h from a point light is about pi sigma_s f_p I / h, so the
  /// direction that leads to that segment needs a density that grows as 1/h near the light. A light chosen by power
  /// among them, the angle alpha to its direction uniform in [alpha_min, alpha_max] (alpha_max = atan(r / D), D its
  /// distance, r a tenth of the scene's diagonal, alpha_min = atan(r / 1000 / D)), the azimuth uniform: solid-angle
  /// density 1 / (2 pi (alpha_max - alpha_min) sin alpha).
  bool hasPointLights() const { return !pointLights_.empty(); }
  /// A direction from x with u.x picking the light and u.y, u.z the cone (false when x lies within r / 1000 of it).
  bool sampleTowardPointLights(const glm::vec3& x, const glm::vec3& u, glm::vec3& wi) const;
  /// Solid-angle density of sampleTowardPointLights() at x for the unit direction wi.
  float pdfTowardPointLights(const glm::vec3& x, const glm::vec3& wi) const;
  /// The density of a path vertex's direction sampling when it mixes the BRDF or phase function (scatterPdf) with
  /// sampling toward the point lights (probability kTowardPointLights), as the reference does in media; scatterPdf
  /// alone without point lights.
  float mixedScatterPdf(const glm::vec3& x, const glm::vec3& wi, float scatterPdf) const {
    if (pointLights_.empty()) return scatterPdf;
    return (1.0f - kTowardPointLights) * scatterPdf + kTowardPointLights * pdfTowardPointLights(x, wi);
  }
  /// Probability of sampling a direction toward the point lights at a vertex of a path through media.
  static constexpr float kTowardPointLights = 0.25f;
  /// Solid-angle pdf with which sampleLi() returns point y with normal ny on emissive `triangle` as seen from x.
  float pdfLi(const glm::vec3& x, uint32_t triangle, const glm::vec3& y, const glm::vec3& ny) const;
  /// Radiance leaving an emissive triangle at texture coordinates uv toward w (zero on its back side).
  glm::vec3 emittedRadiance(uint32_t triangle, const glm::vec3& emitterNormal, glm::vec2 uv, const glm::vec3& w) const;

  /// Light tracing: light by power, point uniform on the area (its own textured radiance), direction cosine-weighted (area) or uniform over the
  /// sphere / spot cone (point, spot). A directional light starts its paths uniformly on a disk of radius R (the
  /// geometry's bounding sphere) perpendicular to its direction, outside the scene: pdf_A = 1 / (pi R^2), the
  /// direction is fixed (a delta), and the disk's flux E pi R^2 is the light's power (docs/methods.md).
  EmissionSample sampleEmission(float uLight, glm::vec2 uPoint, glm::vec2 uDirection) const;

  /// Centre and radius of the disk directional lights emit from (radius zero for a scene without geometry).
  glm::vec3 emissionDiskCenter(const PunctualLight& directional) const;
  float emissionDiskRadius() const { return diskRadius_; }
  /// In a scene with media, a directional light's light enters them at its emission disk (docs/theory.md §16): the
  /// distance from x back to the disk's plane, along which its light is attenuated, or -1 when x lies outside the
  /// cylinder the disk sweeps (no light reaches there, as no light path does). The disk covers the geometry and the
  /// media boxes, so this matters only in a medium that fills all space.
  float directionalMediumDistance(const PunctualLight& directional, const glm::vec3& x) const;

 private:
  struct LightRef {
    bool punctual = false;
    uint32_t index = 0;  ///< triangle index or punctual light index
    float power = 0.0f;  ///< selection weight (luminance of the flux)
  };
  std::size_t pick(float u) const;
  /// Probability that pick() chooses light li.
  float choiceProbability(std::size_t li) const { return cdf_[li] - (li > 0 ? cdf_[li - 1] : 0.0f); }

  struct PointLightRef {
    glm::vec3 position{0.0f};
    float cdf = 0.0f;  ///< normalised over the point and spot lights
    float probability = 0.0f;
  };
  const Scene& scene_;
  std::vector<LightRef> lights_;
  std::vector<PointLightRef> pointLights_;  ///< the point and spot lights, for paths through media
  float guideRadius_ = 0.0f;
  std::vector<float> cdf_;                     ///< normalised, cdf_.back() == 1
  std::vector<int32_t> triangleToLight_;       ///< scene triangle -> index in lights_ (-1 if not emissive)
  glm::vec3 totalPower_{0.0f};
  glm::vec3 sceneCenter_{0.0f};  ///< geometry bounding sphere
  float diskRadius_ = 0.0f;
};

}  // namespace vplab
