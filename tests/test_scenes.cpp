#include "tests/test_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <string>

#include "renderer/core/sampling.h"
#include "renderer/image/metrics.h"
#include "renderer/offline/progressive.h"
#include "renderer/scene/gltf_loader.h"
#include "tests/scene_test_util.h"

namespace vplab::test {

Medium boxMedium(const glm::vec3& centre, const glm::vec3& half, const glm::vec3& sigmaA, const glm::vec3& sigmaS,
                 float g) {
  Medium m;
  m.name = "box";
  m.sigmaA = sigmaA;
  m.sigmaS = sigmaS;
  m.g = g;
  m.worldFromBox = glm::mat4(glm::vec4(half.x, 0, 0, 0), glm::vec4(0, half.y, 0, 0), glm::vec4(0, 0, half.z, 0),
                             glm::vec4(centre, 1));
  m.boxFromWorld = glm::inverse(m.worldFromBox);
  return m;
}

Medium spaceMedium(const glm::vec3& sigmaA, const glm::vec3& sigmaS, float g) {
  Medium m;
  m.name = "scene";
  m.sigmaA = sigmaA;
  m.sigmaS = sigmaS;
  m.g = g;
  m.fillsSpace = true;
  return m;
}

Medium gridMedium(const glm::vec3& lower, const glm::vec3& upper, glm::ivec3 n,
                  const std::function<float(const glm::vec3&)>& density, const glm::vec3& sigmaA,
                  const glm::vec3& sigmaS, float g, int majorantCell) {
  const glm::vec3 h = (upper - lower) / glm::vec3(n);
  std::vector<float> values;
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x) values.push_back(density(lower + (glm::vec3(x, y, z) + 0.5f) * h));
  auto grid = std::make_shared<DensityGrid>(DensityGrid::fromDense(glm::ivec3(0), n, values, majorantCell));
  grid->localFromIndex = glm::dmat4(glm::scale(glm::translate(glm::mat4(1.0f), lower + 0.5f * h), h));
  Medium m;
  m.name = "smoke";
  m.sigmaA = sigmaA;
  m.sigmaS = sigmaS;
  m.g = g;
  m.setDensity(grid, glm::mat4(1.0f));
  return m;
}

Settings smallReferenceSettings(int size, int spp) {
  Settings s;
  s.width = size;
  s.height = size;
  s.samplesPerPixel = spp;
  s.threads = 2;
  return s;
}

Settings smallVplSettings(int size, int vpls) {
  Settings s;
  s.width = size;
  s.height = size;
  s.vplCount = vpls;
  s.samplesPerPixel = 1;
  s.threads = 2;
  return s;
}

std::unique_ptr<OfflineScene> loadAssetScene(const std::string& name) {
  return std::make_unique<OfflineScene>(loadScene(std::string(VPLAB_TEST_ASSETS) + "/scenes/" + name + ".gltf"));
}

void addBumpySphere(Scene& scene, const glm::vec3& centre, float radius, int triangles, uint32_t material) {
  const int rings = std::max(4, static_cast<int>(std::lround(std::sqrt(triangles / 4.0))));
  const int segments = std::max(8, static_cast<int>(std::lround(triangles / (2.0 * rings))));
  auto surface = [&](float theta, float phi) {
    float bump =
        1.0f + 0.06f * std::sin(9.0f * theta) * std::sin(7.0f * phi) + 0.03f * std::sin(23.0f * phi + 3.0f * theta);
    glm::vec3 dir(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
    return centre + radius * bump * dir;
  };
  const auto base = static_cast<uint32_t>(scene.positions.size());
  const float pi = 3.14159265f, eps = 1e-3f;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      float theta = pi * r / rings, phi = 2.0f * pi * s / segments;
      glm::vec3 p = surface(theta, phi);
      glm::vec3 dt = surface(std::min(theta + eps, pi - 1e-4f), phi) - surface(std::max(theta - eps, 1e-4f), phi);
      glm::vec3 dp = surface(theta, phi + eps) - surface(theta, phi - eps);
      glm::vec3 n = glm::cross(dp, dt);
      n = glm::length(n) > 1e-12f ? glm::normalize(n) : glm::normalize(p - centre);
      if (glm::dot(n, p - centre) < 0.0f) n = -n;
      scene.positions.push_back(p);
      scene.normals.push_back(n);
      scene.uvs.emplace_back(0.0f);
    }
  const uint32_t row = static_cast<uint32_t>(segments + 1);
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      uint32_t a = base + static_cast<uint32_t>(r) * row + static_cast<uint32_t>(s), b = a + 1, c = a + row,
               d = b + row;
      // Counter-clockwise seen from outside; the poles' degenerate triangles are left out.
      if (r != 0) {
        scene.triangles.emplace_back(a, b, c);
        scene.triangleMaterials.push_back(material);
      }
      if (r != rings - 1) {
        scene.triangles.emplace_back(b, d, c);
        scene.triangleMaterials.push_back(material);
      }
    }
}

Scene denseCornellScene(int triangles) {
  Scene scene = loadScene(std::string(VPLAB_TEST_ASSETS) + "/scenes/cornell-box.gltf");
  uint32_t white = addLambertMaterial(scene, glm::vec3(0.738f, 0.736f, 0.737f));
  addBumpySphere(scene, glm::vec3(0.37f, 0.47f, 0.35f), 0.14f, triangles, white);
  scene.finalize();
  return scene;
}

std::unique_ptr<OfflineScene> loadDenseCornell(int triangles) {
  return std::make_unique<OfflineScene>(denseCornellScene(triangles));
}

uint32_t addLambertMaterial(Scene& scene, const glm::vec3& albedo, const glm::vec3& emission) {
  Material m;
  m.name = "material" + std::to_string(scene.materials.size());
  m.baseColor = albedo;
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  m.specular = 0.0f;  // pure Lambert: the closed forms below assume it
  m.emission = emission;
  scene.materials.push_back(m);
  return static_cast<uint32_t>(scene.materials.size() - 1);
}

void addQuad(Scene& scene, const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3,
             uint32_t material, const glm::vec3& facing) {
  glm::vec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
  bool flip = glm::dot(n, facing) < 0.0f;
  if (flip) n = -n;
  auto base = static_cast<uint32_t>(scene.positions.size());
  for (const glm::vec3& p : {p0, p1, p2, p3}) {
    scene.positions.push_back(p);
    scene.normals.push_back(n);
    scene.uvs.emplace_back(0.0f);
  }
  if (flip) {
    scene.triangles.emplace_back(base, base + 2, base + 1);
    scene.triangles.emplace_back(base, base + 3, base + 2);
  } else {
    scene.triangles.emplace_back(base, base + 1, base + 2);
    scene.triangles.emplace_back(base, base + 2, base + 3);
  }
  scene.triangleMaterials.push_back(material);
  scene.triangleMaterials.push_back(material);
}

void addCube(Scene& scene, const glm::vec3& center, float half, uint32_t material, bool inward) {
  for (int axis = 0; axis < 3; ++axis)
    for (float side : {-1.0f, 1.0f}) {
      int a = (axis + 1) % 3, b = (axis + 2) % 3;
      glm::vec3 corner[4];
      const float us[4] = {-1, 1, 1, -1}, vs[4] = {-1, -1, 1, 1};
      for (int i = 0; i < 4; ++i) {
        corner[i][axis] = side * half;
        corner[i][a] = us[i] * half;
        corner[i][b] = vs[i] * half;
        corner[i] += center;
      }
      glm::vec3 facing(0.0f);
      facing[axis] = inward ? -side : side;
      addQuad(scene, corner[0], corner[1], corner[2], corner[3], material, facing);
    }
}

Scene makeFurnaceBox(float albedo) {
  Scene s;
  s.sourcePath = "furnace-in-code";
  uint32_t m = addLambertMaterial(s, glm::vec3(albedo), glm::vec3(1.0f));
  addCube(s, glm::vec3(0.0f), 1.0f, m, true);
  s.camera.position = glm::vec3(0.0f);
  s.camera.forward = glm::normalize(glm::vec3(0.3f, -0.2f, 1.0f));
  s.camera.up = glm::normalize(glm::cross(glm::cross(s.camera.forward, glm::vec3(0, 1, 0)), s.camera.forward));
  s.camera.yfov = 1.4f;
  s.finalize();
  return s;
}

namespace {

void addPlane(Scene& s, float half, float albedo = 1.0f) {
  uint32_t white = addLambertMaterial(s, glm::vec3(albedo));
  addQuad(s, {-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}, white, {0, 1, 0});
}

void lookDown(Scene& s, float height) {
  s.camera.position = glm::vec3(0.0f, height, 0.0f);
  s.camera.forward = glm::vec3(0.0f, -1.0f, 0.0f);
  s.camera.up = glm::vec3(0.0f, 0.0f, 1.0f);
}

}  // namespace

Scene makePlaneUnderSquareLight(float planeHalf, float lightHalf, float h, float le) {
  Scene s;
  s.sourcePath = "plane-under-square-light";
  addPlane(s, planeHalf);
  // The light reflects nothing (albedo 0), so the plane's radiance is exactly its direct light.
  uint32_t light = addLambertMaterial(s, glm::vec3(0.0f), glm::vec3(le));
  addQuad(s, {-lightHalf, h, -lightHalf}, {lightHalf, h, -lightHalf}, {lightHalf, h, lightHalf},
          {-lightHalf, h, lightHalf}, light, {0, -1, 0});
  lookDown(s, 0.5f * h);
  s.finalize();
  return s;
}

Scene makePlaneUnderPointLight(float planeHalf, const glm::vec3& position, float intensity) {
  Scene s;
  s.sourcePath = "plane-under-point-light";
  addPlane(s, planeHalf);
  PunctualLight l;
  l.name = "point";
  l.type = PunctualLight::Type::Point;
  l.position = position;
  l.intensity = glm::vec3(intensity);
  s.punctualLights.push_back(l);
  lookDown(s, position.y);
  s.finalize();
  return s;
}

Scene makePlaneUnderDirectionalLight(float planeHalf, const glm::vec3& direction, float irradiance, float albedo) {
  Scene s;
  s.sourcePath = "plane-under-directional-light";
  addPlane(s, planeHalf, albedo);
  PunctualLight l;
  l.name = "sun";
  l.type = PunctualLight::Type::Directional;
  l.direction = glm::normalize(direction);
  l.intensity = glm::vec3(irradiance);
  s.punctualLights.push_back(l);
  lookDown(s, planeHalf);
  s.finalize();
  return s;
}

double polygonIrradiance(const glm::dvec3& x, const glm::dvec3& n, const glm::dvec3* vertices, int count, double le) {
  // Arvo 1994, "The irradiance Jacobian for partially occluded polyhedral sources", eq. 3: the vector irradiance
  // Phi = 1/2 sum_i Theta_i Gamma_i, Theta_i the angle the edge subtends, Gamma_i the unit normal of the plane
  // through x and the edge; E = le * |n . Phi|.
  double sum = 0.0;
  for (int i = 0; i < count; ++i) {
    glm::dvec3 a = glm::normalize(vertices[i] - x);
    glm::dvec3 b = glm::normalize(vertices[(i + 1) % count] - x);
    double theta = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
    glm::dvec3 gamma = glm::normalize(glm::cross(a, b));
    sum += theta * glm::dot(n, gamma);
  }
  return le * 0.5 * std::abs(sum);
}

std::string TexturedPanel::write(const std::string& name) {
  GltfBuilder b;
  b.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_specular"};
  const int floorMaterial =
      b.push("materials", {{"name", "floor"},
                           {"pbrMetallicRoughness",
                            {{"baseColorFactor", {kFloorAlbedo, kFloorAlbedo, kFloorAlbedo, 1.0}},
                             {"metallicFactor", 0.0},
                             {"roughnessFactor", 1.0}}},
                           {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}}});
  // Strength 4 and factor (1, 0.5, 0.25): the product is kPanelRadiance.
  const float strength = kPanelRadiance.r;
  const glm::vec3 factor = kPanelRadiance / strength;
  const int panelMaterial = b.push(
      "materials", {{"name", "panel"},
                    {"pbrMetallicRoughness", {{"baseColorFactor", {0.0, 0.0, 0.0, 1.0}}, {"metallicFactor", 0.0}}},
                    {"emissiveFactor", {factor.r, factor.g, factor.b}},
                    {"emissiveTexture", {{"index", 0}}},
                    {"extensions",
                     {{"KHR_materials_emissive_strength", {{"emissiveStrength", strength}}},
                      {"KHR_materials_specular", {{"specularFactor", 0.0}}}}}});
  const int texels = 256, rows = 4;
  std::vector<glm::u8vec3> image(static_cast<std::size_t>(texels * rows));
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < texels; ++x)
      image[static_cast<std::size_t>(y * texels + x)] = x < texels / 2 ? glm::u8vec3(0) : glm::u8vec3(255);
  std::vector<unsigned char> bytes = bmp(texels, rows, image);
  b.doc["images"] = {{{"bufferView", b.view(bytes.data(), bytes.size())}, {"mimeType", "image/bmp"}}};
  b.doc["textures"] = {{{"source", 0}}};

  const int floorPos = b.vec3({{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}});
  const int floorNormal = b.vec3({{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}});
  const int floorIdx = b.indicesU16({0, 2, 1, 0, 3, 2});
  b.meshNode(b.mesh({GltfBuilder::primitive(floorPos, floorIdx, floorNormal, floorMaterial)}));

  const int cells = 4;
  std::vector<glm::vec3> pos, normal;
  std::vector<glm::vec2> uv;
  std::vector<uint16_t> idx;
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) {
      const float x = -kPanelHalf + 2.0f * kPanelHalf * static_cast<float>(i) / cells;
      const float z = -kPanelHalf + 2.0f * kPanelHalf * static_cast<float>(j) / cells;
      pos.emplace_back(x, kPanelHeight, z);
      normal.emplace_back(0, -1, 0);
      uv.emplace_back(0.25f + 0.5f * (x + kPanelHalf) / (2.0f * kPanelHalf),
                      0.25f + 0.5f * (z + kPanelHalf) / (2.0f * kPanelHalf));
    }
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const auto a = static_cast<uint16_t>(j * (cells + 1) + i), c = static_cast<uint16_t>(a + cells + 1);
      // Counter-clockwise seen from below (the loader also turns triangles to their normals' side).
      idx.insert(idx.end(),
                 {a, static_cast<uint16_t>(a + 1), static_cast<uint16_t>(c + 1), a, static_cast<uint16_t>(c + 1), c});
    }
  nlohmann::json panel = GltfBuilder::primitive(b.vec3(pos), b.indicesU16(idx), b.vec3(normal), panelMaterial);
  panel["attributes"]["TEXCOORD_0"] = b.vec2(uv);
  b.meshNode(b.mesh({panel}));

  b.push("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.01}, {"zfar", 100.0}}}});
  b.node({{"camera", 0}, {"translation", {0.0, 0.15, 1.5}}});

  if (name.size() > 4 && name.substr(name.size() - 4) == ".glb") {
    writeBytes(tmpPath(name), b.glbBytes());
    return tmpPath(name);
  }
  return b.writeGltf(name);
}

glm::vec3 TexturedPanel::panelRadiance(float x) {
  // u = 0.5 + x / 2; texel centres at (i + 0.5) / 256: the last black texel's centre is u = 127.5 / 256 and the first
  // white one's 128.5 / 256, with a linear blend between.
  const double u = 0.25 + 0.5 * (static_cast<double>(x) + kPanelHalf) / (2.0 * kPanelHalf);
  const double t = std::clamp(u * 256.0 - 127.5, 0.0, 1.0);
  return kPanelRadiance * static_cast<float>(t);
}

glm::vec3 TexturedPanel::radianceAlong(const glm::vec3& origin, const glm::vec3& dir) {
  // The panel first (it is the nearer surface where both lie along the ray), seen from below only.
  if (dir.y > 0.0f && origin.y < kPanelHeight) {
    const float t = (kPanelHeight - origin.y) / dir.y;
    const glm::vec3 p = origin + t * dir;
    if (std::abs(p.x) <= kPanelHalf && std::abs(p.z) <= kPanelHalf) return panelRadiance(p.x);
  }
  if (dir.y < 0.0f && origin.y > 0.0f) {
    const float t = -origin.y / dir.y;
    const glm::vec3 p = origin + t * dir;
    if (std::abs(p.x) <= 1.0f && std::abs(p.z) <= 1.0f) {
      const glm::dvec3 white[4] = {{0.0, kPanelHeight, -kPanelHalf},
                                   {kPanelHalf, kPanelHeight, -kPanelHalf},
                                   {kPanelHalf, kPanelHeight, kPanelHalf},
                                   {0.0, kPanelHeight, kPanelHalf}};
      const double e = polygonIrradiance(glm::dvec3(p.x, 0.0, p.z), {0.0, 1.0, 0.0}, white, 4, 1.0);
      return kPanelRadiance * static_cast<float>(kFloorAlbedo * e / kPi);
    }
  }
  return glm::vec3(0.0f);
}

Image TexturedPanel::closedForm(const Camera& camera, int size, int sub) {
  Image image(size, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      glm::vec3 sum(0.0f);
      for (int j = 0; j < sub; ++j)
        for (int i = 0; i < sub; ++i) {
          const float px = static_cast<float>(x) + (static_cast<float>(i) + 0.5f) / static_cast<float>(sub);
          const float py = static_cast<float>(y) + (static_cast<float>(j) + 0.5f) / static_cast<float>(sub);
          sum += radianceAlong(camera.position, cameraRayDirection(camera, px, py, size, size));
        }
      image.at(x, y) = sum / static_cast<float>(sub * sub);
    }
  return image;
}

void TexturedPanel::expectClosedForm(const Image& image, const Camera& camera, double relMseTolerance,
                                     double energyTolerance, double floorHalfTolerance, const char* what) {
  const Image expected = closedForm(camera, image.width);
  const ImageMetrics m = compareImages(image, expected);
  // Pixels that lie wholly on one surface (all four corner rays agree), by surface and by half of the image.
  auto surface = [&](float px, float py) {
    const glm::vec3 dir = cameraRayDirection(camera, px, py, image.width, image.height);
    if (dir.y > 0.0f) {
      const glm::vec3 p = camera.position + (kPanelHeight - camera.position.y) / dir.y * dir;
      return std::abs(p.x) <= kPanelHalf && std::abs(p.z) <= kPanelHalf ? 1 : 0;
    }
    if (dir.y < 0.0f) {
      const glm::vec3 p = camera.position - camera.position.y / dir.y * dir;
      return std::abs(p.x) <= 1.0f && std::abs(p.z) <= 1.0f ? 2 : 0;
    }
    return 0;
  };
  double sum[3][2] = {}, sumExpected[3][2] = {};
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const auto fx = static_cast<float>(x), fy = static_cast<float>(y);
      const int kind = surface(fx, fy);
      if (surface(fx + 1, fy) != kind || surface(fx, fy + 1) != kind || surface(fx + 1, fy + 1) != kind) continue;
      const int half = 2 * x < image.width ? 0 : 1;
      sum[kind][half] += luminance(image.at(x, y));
      sumExpected[kind][half] += luminance(expected.at(x, y));
    }
  const double floorLeft = sum[2][0] / sumExpected[2][0], floorRight = sum[2][1] / sumExpected[2][1];
  const double panelRight = sum[1][1] / sumExpected[1][1];
  // The black half, relative to the white one (the closed form's is the texture's blend in the column at x = 0).
  const double panelLeft = sum[1][0] / sumExpected[1][1], expectedPanelLeft = sumExpected[1][0] / sumExpected[1][1];
  std::printf(
      "[ measured ] %s vs closed form: relMSE %.5f, energy %.4f; floor left half %.4f, right half %.4f; "
      "panel white half %.4f, black half %.2g of the white (closed form %.2g)\n",
      what, m.relMse, m.energyRatioOverall, floorLeft, floorRight, panelRight, panelLeft, expectedPanelLeft);
  EXPECT_EQ(m.nonFinitePixels, 0u) << what;
  EXPECT_LE(m.relMse, relMseTolerance) << what;
  EXPECT_NEAR(m.energyRatioOverall, 1.0, energyTolerance) << what;
  EXPECT_NEAR(floorLeft, 1.0, floorHalfTolerance) << what;
  EXPECT_NEAR(floorRight, 1.0, floorHalfTolerance) << what;
  EXPECT_NEAR(panelRight, 1.0, energyTolerance) << what;
  EXPECT_NEAR(panelLeft, expectedPanelLeft, 0.01) << what;
}

}  // namespace vplab::test
