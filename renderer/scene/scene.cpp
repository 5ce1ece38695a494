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

glm::vec3 Scene::emissionAt(uint32_t material, glm::vec2 uv) const {
  const Material& m = materials[material];
  if (m.emissiveTexture < 0) return m.emission;
  glm::vec2 st = glm::vec2(m.emissiveUvTransform * glm::vec3(uv, 1.0f));
  return m.emission * textures[static_cast<std::size_t>(m.emissiveTexture)].sample(st);
}

glm::vec3 Scene::computeEmissionTextureMean(uint32_t triangle) const {
  const Material& m = materialOf(triangle);
  const Texture& tex = textures[static_cast<std::size_t>(m.emissiveTexture)];
  // The triangle's footprint in texels decides the resolution: the triangle is cut into n^2 equal sub-triangles
  // (n per edge) with about two per texel of footprint, and the texture is averaged at their centroids. Every texel
  // whose bilinear support the triangle covers is then sampled, so a triangle that emits anywhere gets a positive
  // mean (the light sampler never chooses a zero-mean triangle). n is capped at 256 (65536 lookups): beyond that the
  // mean is an estimate, which only shifts the sampling density, never the radiance a sample carries.
  const glm::uvec3& t = triangles[triangle];
  glm::vec2 st[3];
  for (int c = 0; c < 3; ++c) st[c] = glm::vec2(m.emissiveUvTransform * glm::vec3(uvs[t[c]], 1.0f));
  glm::vec2 e1 = st[1] - st[0], e2 = st[2] - st[0];
  double texels = 0.5 * std::abs(static_cast<double>(e1.x) * e2.y - static_cast<double>(e1.y) * e2.x) *
                  static_cast<double>(tex.width) * static_cast<double>(tex.height);
  const int n = static_cast<int>(std::clamp(std::ceil(std::sqrt(2.0 * texels)), 1.0, 256.0));
  glm::dvec3 sum(0.0);
  auto at = [&](double bx, double by) {
    glm::vec2 b(static_cast<float>(bx / n), static_cast<float>(by / n));
    sum += glm::dvec3(tex.sample(b.x * st[0] + b.y * st[1] + (1.0f - b.x - b.y) * st[2]));
  };
  // Sub-triangle (i, j) of the grid, upright ones at barycentric centroid ((i + 1/3) / n, (j + 1/3) / n), the inverted
  // ones between them at ((i + 2/3) / n, (j + 2/3) / n).
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      at(i + 1.0 / 3.0, j + 1.0 / 3.0);
      if (i + j + 1 < n) at(i + 2.0 / 3.0, j + 2.0 / 3.0);
    }
  return glm::vec3(sum / (static_cast<double>(n) * n));
}

void Scene::updateBounds() {
  bounds = geometryBounds;
  for (const PunctualLight& l : punctualLights)
    if (!l.isDirectional()) bounds.extend(l.position);
}

void Scene::finalize() {
  geometryBounds = Bounds{};
  for (const glm::vec3& p : positions) geometryBounds.extend(p);
  updateBounds();
  faceNormals_.resize(triangles.size());
  faceAreas_.resize(triangles.size());
  for (uint32_t i = 0; i < triangles.size(); ++i) {
    faceNormals_[i] = computeGeometricNormal(i);
    faceAreas_[i] = computeTriangleArea(i);
  }
  emissiveTriangles.clear();
  for (uint32_t i = 0; i < triangles.size(); ++i)
    if (materialOf(i).isEmissive() && triangleArea(i) > 0.0f) emissiveTriangles.push_back(i);
  emissionTextureMeans_.clear();
  for (uint32_t i : emissiveTriangles) {
    if (materialOf(i).emissiveTexture < 0) continue;
    if (emissionTextureMeans_.empty()) emissionTextureMeans_.assign(triangles.size(), glm::vec3(1.0f));
    emissionTextureMeans_[i] = computeEmissionTextureMean(i);
  }
}

bool Scene::hasMedia() const {
  for (const Medium& m : media)
    if (!m.isVacuum()) return true;
  return false;
}

}  // namespace vplab
