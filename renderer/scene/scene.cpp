#include "renderer/scene/scene.h"

#include "renderer/core/sampling.h"

#include <algorithm>
#include <cmath>

namespace vplab {

glm::vec3 Texture::sample(glm::vec2 uv) const {
  if (width <= 0 || height <= 0 || texels.empty()) return glm::vec3(1.0f);
  // Texel centres sit at half-integers; wrap with repeat (first into [0, 1), so that coordinates far outside it
  // cannot overflow the integer texel index).
  uv -= glm::floor(uv);
  float x = uv.x * static_cast<float>(width) - 0.5f;
  float y = uv.y * static_cast<float>(height) - 0.5f;
  float fx = std::floor(x), fy = std::floor(y);
  float tx = x - fx, ty = y - fy;
  auto wrap = [](int i, int n) { return ((i % n) + n) % n; };
  int x0 = wrap(static_cast<int>(fx), width), x1 = wrap(static_cast<int>(fx) + 1, width);
  int y0 = wrap(static_cast<int>(fy), height), y1 = wrap(static_cast<int>(fy) + 1, height);
  auto at = [&](int i, int j) { return texels[static_cast<std::size_t>(j) * width + i]; };
  return (1 - tx) * (1 - ty) * at(x0, y0) + tx * (1 - ty) * at(x1, y0) + (1 - tx) * ty * at(x0, y1) +
         tx * ty * at(x1, y1);
}

namespace {

/// The spot's angular attenuation as the KHR_lights_punctual specification's reference code computes it: a linear
/// ramp in cos(angle) from 0 at the outer cone to 1 at the inner cone, squared. The 0.001 floor on the ramp's width
/// is part of that code (it keeps inner == outer finite).
float spotRampScale(const PunctualLight& l) {
  return 1.0f / std::max(0.001f, std::cos(l.innerConeAngle) - std::cos(l.outerConeAngle));
}

}  // namespace

glm::vec3 PunctualLight::intensityToward(const glm::vec3& dirFromLight) const {
  if (type != Type::Spot) return intensity;
  float cd = glm::dot(direction, dirFromLight);
  float t = std::clamp((cd - std::cos(outerConeAngle)) * spotRampScale(*this), 0.0f, 1.0f);
  return intensity * (t * t);
}

glm::vec3 PunctualLight::flux() const {
  if (type != Type::Spot) return 4.0f * kPi * intensity;
  // Over the sphere, dw = 2 pi dc with c = cos(angle). The ramp t = (c - cos_outer) s reaches 1 at
  // c1 = cos_outer + 1/s: the integral of t^2 from cos_outer to c1 is 1/(3s), and full intensity from c1 to 1 adds
  // 1 - c1. Together 2 pi (1 - cos_outer - 2/(3s)).
  float cosOuter = std::cos(outerConeAngle);
  float width = 1.0f / spotRampScale(*this);
  float c1 = std::min(1.0f, cosOuter + width);
  float rampPart = width > 0.0f ? (c1 - cosOuter) * (c1 - cosOuter) * (c1 - cosOuter) / (3.0f * width * width) : 0.0f;
  return 2.0f * kPi * (rampPart + (1.0f - c1)) * intensity;
}

glm::vec3 Camera::rayDirection(glm::vec2 ndc, float aspect) const {
  float tanHalf = std::tan(0.5f * yfov);
  glm::vec3 r = right();
  return glm::normalize(forward + r * (ndc.x * tanHalf * aspect) + up * (ndc.y * tanHalf));
}

glm::vec3 Scene::computeGeometricNormal(uint32_t triangle) const {
  const glm::uvec3& t = triangles[triangle];
  glm::vec3 n = glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x]);
  float len = glm::length(n);
  return len > 0.0f ? n / len : glm::vec3(0.0f, 0.0f, 1.0f);
}

float Scene::computeTriangleArea(uint32_t triangle) const {
  const glm::uvec3& t = triangles[triangle];
  return 0.5f * glm::length(glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x]));
}

glm::vec3 Scene::baseColorAt(uint32_t material, glm::vec2 uv) const {
  const Material& m = materials[material];
  if (m.baseColorTexture < 0) return m.baseColor;
  return m.baseColor * textures[static_cast<std::size_t>(m.baseColorTexture)].sample(uv);
}

void Scene::finalize() {
  geometryBounds = Bounds{};
  for (const glm::vec3& p : positions) geometryBounds.extend(p);
  bounds = geometryBounds;
  for (const PunctualLight& l : punctualLights)
    if (!l.isDirectional()) bounds.extend(l.position);
  faceNormals_.resize(triangles.size());
  faceAreas_.resize(triangles.size());
  for (uint32_t i = 0; i < triangles.size(); ++i) {
    faceNormals_[i] = computeGeometricNormal(i);
    faceAreas_[i] = computeTriangleArea(i);
  }
  emissiveTriangles.clear();
  for (uint32_t i = 0; i < triangles.size(); ++i)
    if (materialOf(i).isEmissive() && triangleArea(i) > 0.0f) emissiveTriangles.push_back(i);
}

}  // namespace vplab
