#include "evaluation/direct_light_cases.h"

#include <algorithm>
#include <functional>
#include <vector>

#include "renderer/core/sampling.h"
#include "renderer/scene/gltf_loader.h"

namespace vplab {
namespace {

bool emissive(const Scene& s, std::size_t t) {
  return s.materials[s.triangleMaterials[t]].emission != glm::vec3(0.0f);
}

// The scene without the triangles `drop` selects.
void dropTriangles(Scene& scene, const std::function<bool(std::size_t)>& drop) {
  std::vector<glm::uvec3> triangles;
  std::vector<uint32_t> materials;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    if (drop(t)) continue;
    triangles.push_back(scene.triangles[t]);
    materials.push_back(scene.triangleMaterials[t]);
  }
  scene.triangles = std::move(triangles);
  scene.triangleMaterials = std::move(materials);
}

}  // namespace

Scene cornellWithLargeEmitter(const std::string& path, float side) {
  Scene s = loadScene(path);
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  std::vector<bool> onEmitter(s.positions.size(), false);
  for (std::size_t t = 0; t < s.triangles.size(); ++t)
    if (emissive(s, t))
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = s.triangles[t][k];
        onEmitter[v] = true;
        lo = glm::min(lo, s.positions[v]);
        hi = glm::max(hi, s.positions[v]);
      }
  const glm::vec3 centre = 0.5f * (lo + hi);
  const glm::vec2 scale(side / (hi.x - lo.x), side / (hi.z - lo.z));
  for (std::size_t v = 0; v < s.positions.size(); ++v)
    if (onEmitter[v]) {
      glm::vec3& p = s.positions[v];
      p.x = centre.x + (p.x - centre.x) * scale.x;
      p.z = centre.z + (p.z - centre.z) * scale.y;
    }
  for (Material& m : s.materials) m.emission /= scale.x * scale.y;
  s.finalize();
  return s;
}

Scene cornellWithSpotLight(const std::string& path) {
  Scene s = loadScene(path);
  dropTriangles(s, [&](std::size_t t) { return emissive(s, t); });
  PunctualLight spot;
  spot.name = "spot";
  spot.type = PunctualLight::Type::Spot;
  spot.position = glm::vec3(0.28f, 0.53f, 0.28f);
  spot.direction = glm::normalize(glm::vec3(0.1f, -1.0f, 0.15f));
  spot.innerConeAngle = 0.4f;
  spot.outerConeAngle = 0.7f;
  spot.intensity = glm::vec3(1.5f);
  s.punctualLights.push_back(spot);
  s.finalize();
  return s;
}

Scene cornellUnderSun(const std::string& path) {
  Scene s = loadScene(path);
  const float ceiling = s.geometryBounds.upper.y - 0.01f;
  dropTriangles(s, [&](std::size_t t) {
    const glm::uvec3& v = s.triangles[t];
    return emissive(s, t) ||
           (s.positions[v.x].y > ceiling && s.positions[v.y].y > ceiling && s.positions[v.z].y > ceiling);
  });
  PunctualLight sun;
  sun.name = "sun";
  sun.type = PunctualLight::Type::Directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.4f));
  sun.intensity = glm::vec3(2.0f);
  s.punctualLights.push_back(sun);
  s.finalize();
  return s;
}

void addPointLightAbove(Scene& scene) {
  const Bounds& b = scene.geometryBounds;
  const float radius = std::max(0.5f * b.diagonal(), 1e-3f);
  PunctualLight l;
  l.name = "point above";
  l.type = PunctualLight::Type::Point;
  l.position = b.center() + glm::vec3(0.0f, 2.0f * radius, 0.0f);
  l.intensity = glm::vec3(kPi * 4.0f * radius * radius);
  scene.punctualLights.push_back(l);
  scene.updateBounds();
}

void makeLambert(Scene& scene) {
  for (Material& m : scene.materials) {
    m.metallic = 0.0f;
    m.specular = 0.0f;
  }
}

}  // namespace vplab
