#include "renderer/scene/staging.h"

#include "renderer/core/sampling.h"
#include "renderer/scene/gltf_loader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace vplab {
namespace {

// Studio proportions, in units of the model's bounding-sphere radius R: every length scales with R, so the same
// studio fits a 1 cm part and a 100 m building.
constexpr float kGroundHalfWidth = 6.0f;   ///< ground extent sideways and toward the camera
constexpr float kBackdropDistance = 2.0f;  ///< backdrop plane behind the model's centre
constexpr float kBackdropHeight = 5.0f;    ///< above the ground
constexpr float kLightSide = 1.5f;         ///< side of the square key light
/// Key light position relative to the model's centre: above, toward the camera and a little to the side, so that
/// faces toward the camera are lit and shadows fall visibly on the ground.
constexpr float kLightUp = 3.0f, kLightFront = 2.0f, kLightSideways = 1.0f;
constexpr float kStudioAlbedo = 0.8f;
/// Elevation of the automatic camera above the horizon (radians, 20 degrees): the ground shows in front of the model.
constexpr float kCameraElevation = 0.349f;
/// Room around the model in the automatic view, so its contact shadow on the ground shows.
constexpr float kCameraMargin = 1.4f;
/// Irradiance the key light delivers to the model's centre (lux). Pi makes a white Lambert surface facing it reflect
/// radiance about 1, which the tonemapper shows well at exposure 0.
constexpr float kKeyIrradiance = kPi;

uint32_t addMaterial(Scene& s, const std::string& name, float albedo, glm::vec3 emission) {
  Material m;
  m.name = name;
  m.baseColor = glm::vec3(albedo);
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  m.specular = 0.0f;  // Lambert: the studio should not add highlights of its own
  m.emission = emission;
  s.materials.push_back(m);
  return static_cast<uint32_t>(s.materials.size() - 1);
}

/// The quad with corners center +- u +- v as two triangles; its front faces the side u x v points to.
void addQuad(Scene& s, glm::vec3 center, glm::vec3 u, glm::vec3 v, uint32_t material) {
  glm::vec3 n = glm::normalize(glm::cross(u, v));
  auto base = static_cast<uint32_t>(s.positions.size());
  const glm::vec2 uvs[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const glm::vec3 corners[4] = {center - u - v, center + u - v, center + u + v, center - u + v};
  for (int i = 0; i < 4; ++i) {
    s.positions.push_back(corners[i]);
    s.normals.push_back(n);
    s.uvs.push_back(uvs[i]);
  }
  s.triangles.emplace_back(base, base + 1, base + 2);
  s.triangles.emplace_back(base, base + 2, base + 3);
  s.triangleMaterials.push_back(material);
  s.triangleMaterials.push_back(material);
}

/// Looks at the model's bounding sphere from the front (+z, as the loader's automatic camera) and kCameraElevation
/// above, from kCameraMargin times the distance at which the sphere just fits the vertical field of view.
Camera framedCamera(glm::vec3 center, float radius, float reach) {
  Camera c;
  float distance = kCameraMargin * radius / std::sin(0.5f * c.yfov);
  glm::vec3 toCamera(0.0f, std::sin(kCameraElevation), std::cos(kCameraElevation));
  c.position = center + toCamera * distance;
  c.forward = -toCamera;
  glm::vec3 up(0.0f, 1.0f, 0.0f);
  c.up = glm::normalize(up - glm::dot(up, c.forward) * c.forward);
  c.znear = std::max(1e-4f, 0.01f * (distance - radius));
  c.zfar = distance + reach;
  c.fromFile = false;
  return c;
}

std::string vec(const glm::vec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.3g, %.3g, %.3g)", v.x, v.y, v.z);
  return buf;
}

}  // namespace

uint32_t addSquareLight(Scene& scene, const glm::vec3& center, const glm::vec3& target, float side, float irradiance,
                        const std::string& name) {
  // A square of half side a seen face-on from distance d on its axis gives E = 4 L q atan(q) with
  // q = a / sqrt(a^2 + d^2) (the rectangle's form factor), so L follows exactly from the wanted E.
  const glm::vec3 toTarget = glm::normalize(target - center);
  const float half = 0.5f * side;
  Frame frame(toTarget);
  glm::vec3 u = frame.s * half, v = frame.t * half;
  if (glm::dot(glm::cross(u, v), toTarget) < 0.0f) std::swap(u, v);
  const float distance2 = glm::dot(target - center, target - center);
  const float q = half / std::sqrt(half * half + distance2);
  uint32_t material = addMaterial(scene, name, 0.0f, glm::vec3(irradiance / (4.0f * q * std::atan(q))));
  addQuad(scene, center, u, v, material);
  return material;
}

void stageScene(Scene& scene, Stage stage) {
  scene.staging.clear();
  bool wanted = stage == Stage::Studio || (stage == Stage::Auto && !scene.hasLights());
  if (!wanted || !scene.geometryBounds.valid()) return;
  const glm::vec3 center = scene.geometryBounds.center();
  const float radius = std::max(0.5f * scene.geometryBounds.diagonal(), 1e-4f);
  const float floorY = scene.geometryBounds.lower.y;  // glTF is y-up: the model stands on its lowest point
  if (!scene.camera.fromFile)
    scene.camera = framedCamera(center, radius, (kGroundHalfWidth + kBackdropDistance + 2.0f) * radius);

  // "Front" is the horizontal direction from the model toward the camera; the backdrop stands opposite it.
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  glm::vec3 front = scene.camera.position - center;
  front.y = 0.0f;
  front = glm::length(front) > 1e-3f * radius ? glm::normalize(front) : glm::vec3(0.0f, 0.0f, 1.0f);
  const glm::vec3 side = glm::cross(up, front);
  const glm::vec3 base(center.x, floorY, center.z);

  uint32_t studio = addMaterial(scene, "studio", kStudioAlbedo, glm::vec3(0.0f));
  // Ground from the backdrop to kGroundHalfWidth R toward the camera (front x side = up: it faces up).
  const float ahead = kGroundHalfWidth * radius, behind = kBackdropDistance * radius;
  addQuad(scene, base + front * (0.5f * (ahead - behind)), front * (0.5f * (ahead + behind)),
          side * (kGroundHalfWidth * radius), studio);
  // Backdrop facing the camera (side x up = front).
  const float height = kBackdropHeight * radius;
  addQuad(scene, base - front * behind + up * (0.5f * height), side * (kGroundHalfWidth * radius), up * (0.5f * height),
          studio);

  // Key light above, in front and to the side, giving the model's centre an irradiance of kKeyIrradiance.
  const glm::vec3 lightCenter = center + up * (kLightUp * radius) + front * (kLightFront * radius) +
                                side * (kLightSideways * radius);
  uint32_t light = addSquareLight(scene, lightCenter, center, kLightSide * radius, kKeyIrradiance, "studio light");
  const float radiance = scene.materials[light].emission.g;
  const float half = 0.5f * kLightSide * radius;
  scene.finalize();

  scene.warnings.erase(std::remove(scene.warnings.begin(), scene.warnings.end(), std::string(kNoLightsWarning)),
                       scene.warnings.end());
  char size[64];
  std::snprintf(size, sizeof size, "%.3g x %.3g", 2.0f * half, 2.0f * half);
  scene.staging = std::string(stage == Stage::Auto ? "auto (the file has no lights)" : "studio") +
                  ": ground and backdrop (albedo " + std::to_string(kStudioAlbedo).substr(0, 3) + "), a " + size +
                  " area light of radiance " + std::to_string(static_cast<int>(std::lround(radiance))) + " at " +
                  vec(lightCenter) + (scene.camera.fromFile ? "; the file's camera" : "; camera framed on the model");
}

}  // namespace vplab
