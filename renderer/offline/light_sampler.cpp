#include "renderer/offline/light_sampler.h"

#include "renderer/core/sampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vplab {

namespace {

/// A point uniform on the triangle's area and the radiance it emits (the emissive texture looked up there).
struct EmitterPoint {
  glm::vec3 position;
  glm::vec3 radiance;
};

EmitterPoint pointOnTriangle(const Scene& scene, uint32_t triangle, glm::vec2 u) {
  glm::vec2 b = sampleUniformTriangle(u);
  const glm::uvec3& t = scene.triangles[triangle];
  return {b.x * scene.positions[t.x] + b.y * scene.positions[t.y] + (1.0f - b.x - b.y) * scene.positions[t.z],
          scene.emissionAt(scene.triangleMaterials[triangle], scene.uvAt(triangle, b))};
}

float selectionWeight(const glm::vec3& power) {
  float w = luminance(power);
  return w > 0.0f ? w : (power.r + power.g + power.b) / 3.0f;
}

}  // namespace

LightSampler::LightSampler(const Scene& scene) : scene_(scene), triangleToLight_(scene.triangles.size(), -1) {
  if (scene.geometryBounds.valid()) {
    sceneCenter_ = scene.geometryBounds.center();
    diskRadius_ = 0.5f * scene.geometryBounds.diagonal();
  }
  if (scene.hasMedia()) {
    // Light paths of a directional light start on its disk: it must cover the media boxes too, or light scattered
    // there would be missing from the VPLs while next-event estimation sees it.
    Bounds b = scene.geometryBounds;
    for (const Medium& m : scene.media)
      for (const glm::vec3& c : m.corners()) b.extend(c);
    if (b.valid()) {
      sceneCenter_ = b.center();
      diskRadius_ = 0.5f * b.diagonal();
    }
  }
  for (uint32_t tri : scene.emissiveTriangles) {
    // A one-sided Lambertian emitter of radiance L and area A emits pi A L; a textured one pi A times its mean L, so
    // that triangles are chosen by the power the texture gives them (a black part of an emitter is never chosen).
    glm::vec3 power = kPi * scene.triangleArea(tri) * scene.meanEmission(tri);
    float w = selectionWeight(power);
    if (!(w > 0.0f)) continue;
    triangleToLight_[tri] = static_cast<int32_t>(lights_.size());
    lights_.push_back({false, tri, w});
    totalPower_ += power;
  }
  for (uint32_t i = 0; i < scene.punctualLights.size(); ++i) {
    const PunctualLight& l = scene.punctualLights[i];
    // A directional light's power is the flux through its emission disk: E pi R^2.
    glm::vec3 power = l.isDirectional() ? kPi * diskRadius_ * diskRadius_ * l.intensity : l.flux();
    float w = selectionWeight(power);
    if (!(w > 0.0f)) continue;
    lights_.push_back({true, i, w});
    totalPower_ += power;
  }
  double sum = 0.0;
  for (const LightRef& l : lights_) sum += l.power;
  if (!(sum > 0.0)) {
    lights_.clear();
    return;
  }
  double running = 0.0;
  cdf_.reserve(lights_.size());
  for (const LightRef& l : lights_) {
    running += l.power;
    cdf_.push_back(static_cast<float>(running / sum));
  }
  cdf_.back() = 1.0f;
  // The point and spot lights by power, for direction sampling toward them; only paths through media use it.
  if (!scene.hasMedia()) return;
  float pointPower = 0.0f;
  for (const LightRef& l : lights_)
    if (l.punctual && !scene.punctualLights[l.index].isDirectional()) pointPower += l.power;
  if (!(pointPower > 0.0f)) return;
  float running2 = 0.0f;
  for (const LightRef& l : lights_) {
    if (!l.punctual || scene.punctualLights[l.index].isDirectional()) continue;
    running2 += l.power / pointPower;
    pointLights_.push_back({scene.punctualLights[l.index].position, running2, l.power / pointPower});
  }
  pointLights_.back().cdf = 1.0f;
  guideRadius_ = 0.1f * std::max(scene.bounds.diagonal(), 1e-6f);
}

namespace {

/// The angles between which direction sampling toward a point light at distance d draws: atan(r / d) outside, and
/// inside atan(r / 1000 / d), so that no line passes closer than r / 1000 to the light (below that, float precision no
/// longer keeps the equiangular density and the light's 1/d^2 in step, and a handful of paths would carry most of
/// the image; the BRDF or phase function still reaches those directions).
struct GuideCone {
  float alphaMin, alphaMax;
  GuideCone(float radius, float d) : alphaMin(std::atan2(1e-3f * radius, d)), alphaMax(std::atan2(radius, d)) {}
  bool valid() const { return alphaMax > alphaMin; }
};

}  // namespace

bool LightSampler::sampleTowardPointLights(const glm::vec3& x, const glm::vec3& u, glm::vec3& wi) const {
  if (pointLights_.empty()) return false;
  const auto it = std::upper_bound(pointLights_.begin(), pointLights_.end(), u.x,
                                   [](float v, const PointLightRef& l) { return v < l.cdf; });
  const PointLightRef& light = it == pointLights_.end() ? pointLights_.back() : *it;
  const glm::vec3 d = light.position - x;
  const float dist = glm::length(d);
  if (!(dist > 0.0f)) return false;
  // alpha linear in [alpha_min, alpha_max]: the density 1 / (2 pi (alpha_max - alpha_min) sin alpha) cancels the 1/h
  // of the segment.
  const GuideCone cone(guideRadius_, dist);
  if (!cone.valid()) return false;
  const float alpha = cone.alphaMin + u.y * (cone.alphaMax - cone.alphaMin), phi = 2.0f * kPi * u.z;
  const float sinA = std::sin(alpha);
  wi = glm::normalize(Frame(d / dist).toWorld({sinA * std::cos(phi), sinA * std::sin(phi), std::cos(alpha)}));
  return true;
}

float LightSampler::pdfTowardPointLights(const glm::vec3& x, const glm::vec3& wi) const {
  float pdf = 0.0f;
  for (const PointLightRef& light : pointLights_) {
    const glm::vec3 d = light.position - x;
    const float dist = glm::length(d);
    if (!(dist > 0.0f)) continue;
    const GuideCone cone(guideRadius_, dist);
    if (!cone.valid()) continue;
    // The angle from the cross product's length: acos loses small angles, where the density is largest.
    const float sinA = glm::length(glm::cross(d / dist, wi));
    const float alpha = std::atan2(sinA, glm::dot(d / dist, wi));
    if (!(alpha >= cone.alphaMin && alpha < cone.alphaMax) || !(sinA > 0.0f)) continue;
    pdf += light.probability / (2.0f * kPi * (cone.alphaMax - cone.alphaMin) * sinA);
  }
  return pdf;
}

std::size_t LightSampler::pick(float u) const {
  // CDF inversion (not an alias table): neighbouring u pick the same light, which keeps QMC strata coherent.
  auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  return std::min<std::size_t>(static_cast<std::size_t>(it - cdf_.begin()), cdf_.size() - 1);
}

LightSampleLi LightSampler::sampleLi(const glm::vec3& x, float uLight, glm::vec2 uPoint) const {
  LightSampleLi s;
  if (empty()) return s;
  std::size_t li = pick(uLight);
  float pLight = choiceProbability(li);
  const LightRef& light = lights_[li];

  if (light.punctual) {
    const PunctualLight& pl = scene_.punctualLights[light.index];
    if (pl.isDirectional()) {
      // Parallel rays from infinity: irradiance E on a surface facing them, E cos on a tilted one.
      s.wi = -pl.direction;
      s.distance = std::numeric_limits<float>::infinity();
      s.position = x;
      if (scene_.hasMedia()) {
        s.mediumDistance = directionalMediumDistance(pl, x);
        if (s.mediumDistance < 0.0f) return LightSampleLi{};
      }
      s.radiance = pl.intensity;
      s.pdf = pLight;
      s.isDelta = true;
      return s;
    }
    glm::vec3 d = pl.position - x;
    float dist2 = glm::dot(d, d);
    if (!(dist2 > 0.0f)) return s;
    s.distance = std::sqrt(dist2);
    s.wi = d / s.distance;
    s.position = pl.position;
    s.radiance = pl.intensityToward(-s.wi) / dist2;
    s.pdf = pLight;
    if (pl.type == PunctualLight::Type::Point) {
      s.emissionPdfDirection = 1.0f / (4.0f * kPi);
    } else {
      float cosOuter = std::cos(pl.outerConeAngle);
      s.emissionPdfDirection = glm::dot(pl.direction, -s.wi) >= cosOuter ? uniformConePdf(cosOuter) : 0.0f;
    }
    s.isDelta = true;
    return s;
  }

  // Uniform point on the triangle: pdf_A = 1/A, turned into solid angle by d^2 / cos_light.
  const EmitterPoint y = pointOnTriangle(scene_, light.index, uPoint);
  s.position = y.position;
  s.normal = scene_.geometricNormal(light.index);
  glm::vec3 d = s.position - x;
  float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return LightSampleLi{};
  s.distance = std::sqrt(dist2);
  s.wi = d / s.distance;
  float cosLight = -glm::dot(s.normal, s.wi);
  if (cosLight <= 0.0f) return LightSampleLi{};  // back of a one-sided emitter
  s.radiance = y.radiance;
  s.pdf = pLight * dist2 / (cosLight * scene_.triangleArea(light.index));
  s.emissionPdfDirection = cosLight * kInvPi;
  return s;
}

bool LightSampler::samplePosition(float uLight, glm::vec2 uPoint, glm::vec3& position, bool* punctual) const {
  if (empty()) return false;
  const LightRef& light = lights_[pick(uLight)];
  if (punctual) *punctual = light.punctual;
  if (light.punctual) {
    const PunctualLight& pl = scene_.punctualLights[light.index];
    if (pl.isDirectional()) return false;
    position = pl.position;
    return true;
  }
  position = pointOnTriangle(scene_, light.index, uPoint).position;
  return true;
}

float LightSampler::pdfLi(const glm::vec3& x, uint32_t triangle, const glm::vec3& y, const glm::vec3& ny) const {
  if (triangle >= triangleToLight_.size()) return 0.0f;
  int32_t li = triangleToLight_[triangle];
  if (li < 0) return 0.0f;
  float pLight = choiceProbability(static_cast<std::size_t>(li));
  glm::vec3 d = y - x;
  float dist2 = glm::dot(d, d);
  float cosLight = -glm::dot(ny, d) / std::sqrt(dist2);
  if (!(cosLight > 0.0f)) return 0.0f;
  return pLight * dist2 / (cosLight * scene_.triangleArea(triangle));
}

glm::vec3 LightSampler::emittedRadiance(uint32_t triangle, const glm::vec3& emitterNormal, glm::vec2 uv,
                                        const glm::vec3& w) const {
  if (glm::dot(emitterNormal, w) <= 0.0f) return glm::vec3(0.0f);
  return scene_.emissionAt(scene_.triangleMaterials[triangle], uv);
}

EmissionSample LightSampler::sampleEmission(float uLight, glm::vec2 uPoint, glm::vec2 uDirection) const {
  EmissionSample s;
  if (empty()) return s;
  std::size_t li = pick(uLight);
  float pLight = choiceProbability(li);
  const LightRef& light = lights_[li];

  if (light.punctual) {
    const PunctualLight& pl = scene_.punctualLights[light.index];
    s.position = pl.position;
    if (pl.isDirectional()) {
      // Uniform on the disk of radius R centred on the light's side of the bounding sphere, perpendicular to the
      // direction: pdf_A = 1 / (pi R^2); the direction is the light's own, so alpha_0 = E pi R^2 / p_light.
      glm::vec2 d = sampleConcentricDisk(uPoint) * diskRadius_;
      Frame frame(pl.direction);
      s.position = emissionDiskCenter(pl) + frame.toWorld(glm::vec3(d, 0.0f));
      s.direction = pl.direction;
      s.weight = pl.intensity * (kPi * diskRadius_ * diskRadius_) / pLight;
      s.valid = true;
      return s;
    }
    if (pl.type == PunctualLight::Type::Point) {
      // Uniform sphere: pdf_dir = 1 / (4 pi).
      float z = 1.0f - 2.0f * uDirection.x;
      float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
      float phi = 2.0f * kPi * uDirection.y;
      s.direction = {r * std::cos(phi), r * std::sin(phi), z};
      s.weight = pl.intensity * (4.0f * kPi) / pLight;
      s.pdfDirection = 1.0f / (4.0f * kPi);
    } else {
      // Uniform inside the outer cone; the falloff goes into the weight.
      float cosOuter = std::cos(pl.outerConeAngle);
      s.direction = Frame(pl.direction).toWorld(sampleUniformCone(uDirection, cosOuter));
      s.weight = pl.intensityToward(s.direction) / (uniformConePdf(cosOuter) * pLight);
      s.pdfDirection = uniformConePdf(cosOuter);
    }
    s.valid = true;
    return s;
  }

  // Area light: uniform point (pdf_A = 1/A), cosine-weighted direction (pdf = cos/pi):
  // alpha_0 = Le(y) cos / (p_light pdf_A pdf_dir) = Le(y) pi A / p_light.
  const EmitterPoint y = pointOnTriangle(scene_, light.index, uPoint);
  s.position = y.position;
  s.normal = scene_.geometricNormal(light.index);
  glm::vec3 local = sampleCosineHemisphere(uDirection);
  if (!(local.z > 0.0f)) return EmissionSample{};
  s.direction = glm::normalize(Frame(s.normal).toWorld(local));
  s.pdfDirection = local.z * kInvPi;
  s.weight = y.radiance * (kPi * scene_.triangleArea(light.index)) / pLight;
  s.valid = true;
  return s;
}

glm::vec3 LightSampler::emissionDiskCenter(const PunctualLight& directional) const {
  // The plane touching the bounding sphere on the side the light comes from, pushed back by a small margin so that
  // no geometry lies on it (a ray starting on a surface would not see that surface).
  return sceneCenter_ - directional.direction * (1.01f * diskRadius_ + 1e-4f);
}

float LightSampler::directionalMediumDistance(const PunctualLight& directional, const glm::vec3& x) const {
  // The light enters the media at its emission disk: the distance from x back to the disk's plane along -direction,
  // provided x lies inside the cylinder the disk sweeps (light tracing covers nothing else).
  glm::vec3 rel = x - emissionDiskCenter(directional);
  float along = glm::dot(rel, directional.direction);
  glm::vec3 lateral = rel - along * directional.direction;
  if (glm::dot(lateral, lateral) > diskRadius_ * diskRadius_) return -1.0f;
  return std::max(0.0f, along);
}

}  // namespace vplab
