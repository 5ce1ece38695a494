#include "renderer/scene/scene.h"

#include <algorithm>
#include <cmath>

namespace vplab {

glm::vec3 Texture::sample(glm::vec2 uv) const {
  if (width <= 0 || height <= 0 || texels.empty()) return glm::vec3(1.0f);
  // Texel centres sit at half-integers; wrap with repeat.
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

glm::vec3 PunctualLight::intensityToward(const glm::vec3& dirFromLight) const {
  if (type == Type::Point) return intensity;
  // KHR_lights_punctual reference falloff: a squared linear ramp in cos between the outer and inner cone.
  float cd = glm::dot(direction, dirFromLight);
  float cosOuter = std::cos(outerConeAngle);
  float cosInner = std::cos(innerConeAngle);
  float scale = 1.0f / std::max(0.001f, cosInner - cosOuter);
  float t = std::clamp((cd - cosOuter) * scale, 0.0f, 1.0f);
  return intensity * (t * t);
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
  bounds = Bounds{};
  for (const glm::vec3& p : positions) bounds.extend(p);
  for (const PunctualLight& l : punctualLights) bounds.extend(l.position);
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
