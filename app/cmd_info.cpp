// vplab info <scene>: what the loader made of a glTF file (counts, bounds, lights, media, materials, camera,
// warnings).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "app/cli.h"
#include "app/commands.h"
#include "renderer/core/sampling.h"
#include "renderer/core/text.h"
#include "renderer/scene/density_grid.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/lights_json.h"
#include "renderer/scene/staging.h"

namespace vplab::app {
namespace {

std::string vec(const glm::vec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.4g, %.4g, %.4g)", v.x, v.y, v.z);
  return buf;
}

/// A density grid: where it came from, its voxels and memory, its world box and voxel size, its density range, and the
/// largest optical depth straight through it along each of its axes (sigma_t's largest channel).
void printDensity(const Medium& m) {
  const DensityGrid& g = *m.density;
  std::printf("  %-20s density grid '%s' of %s, scale %.4g\n", "", printable(g.gridName).c_str(),
              printable(m.densityUri.empty() ? g.source : m.densityUri).c_str(), m.densityScale);
  std::printf("  %-20s %llu active voxels, stored %d x %d x %d (%.3g MiB with the majorants)\n", "",
              static_cast<unsigned long long>(g.activeVoxels), g.size.x, g.size.y, g.size.z,
              static_cast<double>(g.bytes()) / 1048576.0);
  const glm::mat3 worldFromIndex = glm::inverse(glm::mat3(m.indexFromWorld));
  const glm::vec3 voxel(glm::length(worldFromIndex[0]), glm::length(worldFromIndex[1]), glm::length(worldFromIndex[2]));
  Bounds world;
  for (const glm::vec3& c : m.corners()) world.extend(c);
  std::printf("  %-20s world bounds %s to %s m, voxel %s m\n", "", vec(world.lower).c_str(), vec(world.upper).c_str(),
              vec(voxel).c_str());
  std::printf("  %-20s density %.4g to %.4g (x scale: sigma_t up to %s 1/m)\n", "", g.minValue, g.maxValue,
              vec(m.sigmaTMax()).c_str());
  // The densest column along each axis: the sum of its values is the integral of the trilinear density along it
  // (in voxels).
  glm::vec3 column(0.0f);
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int j = 0; j < g.size[v]; ++j)
      for (int i = 0; i < g.size[u]; ++i) {
        double sum = 0.0;
        glm::ivec3 p(0);
        p[u] = i;
        p[v] = j;
        for (p[axis] = 0; p[axis] < g.size[axis]; ++p[axis])
          sum += g.values[(static_cast<std::size_t>(p.z) * g.size.y + p.y) * g.size.x + p.x];
        column[axis] = std::max(column[axis], static_cast<float>(sum));
      }
  }
  const float peak = std::max({m.sigmaT().x, m.sigmaT().y, m.sigmaT().z}) * m.densityScale;
  std::printf("  %-20s largest optical depth through it along x, y, z %s\n", "", vec(column * voxel * peak).c_str());
}

/// The media, one block each: where, the coefficients, and optical depths that say how foggy the scene will look
/// (exp(-depth) of the light gets straight through).
void printMedia(const Scene& scene) {
  std::printf("media:\n");
  if (scene.media.empty()) std::printf("  none\n");
  const float sceneDiagonal = scene.geometryBounds.diagonal();
  for (const Medium& m : scene.media) {
    const glm::vec3 sigmaT = m.sigmaT();
    if (m.fillsSpace) {
      std::printf("  %-20s all space\n", printable(m.name).c_str());
    } else {
      // The box is [-1, 1]^3 under worldFromBox: its centre is the translation, its half sizes the axis lengths.
      const glm::vec3 half = m.halfSizes();
      bool aligned = true;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          if (i != j && std::abs(m.worldFromBox[i][j]) > 1e-6f * half[i]) aligned = false;
      std::printf("  %-20s box centre %s, half sizes %s m%s\n", printable(m.name).c_str(),
                  vec(m.centre()).c_str(), vec(half).c_str(), aligned ? "" : " (rotated)");
    }
    std::printf("  %-20s sigmaA %s, sigmaS %s, sigma_t %s 1/m%s%s\n", "", vec(m.sigmaA).c_str(),
                vec(m.sigmaS).c_str(), vec(sigmaT).c_str(), m.density ? " per unit density" : "",
                m.isVacuum() ? " (vacuum)" : "");
    if (m.density) {
      printDensity(m);
      continue;
    }
    std::printf("  %-20s albedo %s, g %.3g, mean free path %s m\n", "", vec(m.albedo()).c_str(), m.g,
                vec(m.meanFreePath()).c_str());
    std::printf("  %-20s optical depth across the scene (%.4g m) %s", "", sceneDiagonal,
                vec(sigmaT * sceneDiagonal).c_str());
    if (!m.fillsSpace) {
      const glm::vec3 half = m.halfSizes();
      const float longest = 2.0f * std::max({half.x, half.y, half.z});
      std::printf(", along the box's longest edge (%.4g m) %s", longest, vec(sigmaT * longest).c_str());
    }
    std::printf("\n");
  }
}

}  // namespace

int cmdInfo(const Args& args) {
  cli::CommandLine cl("vplab info <scene.gltf|scene.glb> [--stage auto|none|studio]",
                      {{"stage", "auto|none|studio", "staging as the rendering commands apply it (default auto)"}});
  if (!cl.parse(args)) {
    std::printf("%s", cl.help().c_str());
    std::printf("Prints counts, bounds, lights, media, materials, camera and load warnings of a glTF scene.\n");
    return 0;
  }
  cl.requirePositional(1, 1, "one scene file");
  Stage stage = Stage::Auto;
  if (auto st = cl.value("stage"); st && !parseStage(*st, stage))
    throw cli::CliError("option --stage: '" + *st + "' is not auto, none or studio");
  Scene scene = loadScene(cl.positional()[0]);
  stageScene(scene, stage);
  applyLightsSidecar(scene);

  std::printf("scene      %s\n", printable(scene.sourcePath).c_str());
  std::printf("staging    %s\n", scene.staging.empty() ? "none" : printable(scene.staging).c_str());
  std::printf("vertices   %zu\n", scene.positions.size());
  std::printf("triangles  %zu\n", scene.triangles.size());
  std::printf("materials  %zu\n", scene.materials.size());
  std::printf("textures   %zu\n", scene.textures.size());
  std::printf("emissive triangles  %zu\n", scene.emissiveTriangles.size());
  std::printf("punctual lights     %zu\n", scene.punctualLights.size());
  std::printf("media      %zu\n", scene.media.size());
  std::printf("degenerate triangles dropped  %zu\n", scene.degenerateTrianglesDropped);
  std::printf("bounds     %s .. %s  (extent %s, diagonal %.4g)\n", vec(scene.bounds.lower).c_str(),
              vec(scene.bounds.upper).c_str(), vec(scene.bounds.extent()).c_str(), scene.bounds.diagonal());
  // What the preview's `--visibility auto` picks here (resolveVisibility), and b relative to the scene.
  const Settings defaults;
  const auto cubeUpTo = static_cast<long long>(kAutoCubeTriangleVpls / std::max<std::size_t>(scene.triangles.size(), 1));
  std::printf("preview    visibility auto: %s at the default %d VPLs (cube maps up to %lld VPLs here: triangles x "
              "VPLs <= " VPLAB_AUTO_CUBE_LIMIT "); --clamp-bound-relative B is b = B x %.4g (1 / geometry diagonal^2)\n",
              toString(resolveVisibility(VisibilityMethod::Auto, scene.triangles.size(),
                                         static_cast<std::size_t>(defaults.vplCount))),
              defaults.vplCount, cubeUpTo,
              1.0 / std::max(1e-24, static_cast<double>(scene.geometryBounds.diagonal()) *
                                        scene.geometryBounds.diagonal()));

  // A Lambertian emitter of radiance L and area A emits pi * L * A from its front side (L: the mean over the triangle
  // when the emission is textured).
  std::map<uint32_t, std::pair<std::size_t, glm::vec3>> emitters;
  for (uint32_t t : scene.emissiveTriangles) {
    auto& e = emitters[scene.triangleMaterials[t]];
    ++e.first;
    e.second += kPi * scene.meanEmission(t) * scene.triangleArea(t);
  }
  std::printf("area lights (per material):\n");
  if (emitters.empty()) std::printf("  none\n");
  for (const auto& [material, e] : emitters) {
    const Material& m = scene.materials[material];
    std::printf("  %-20s %zu triangles, radiance %s%s, power %s\n", printable(m.name).c_str(), e.first,
                vec(m.emission).c_str(), m.emissiveTexture >= 0 ? " x emissive texture" : "", vec(e.second).c_str());
  }
  std::printf("punctual lights:\n");
  if (scene.punctualLights.empty()) std::printf("  none\n");
  for (const PunctualLight& l : scene.punctualLights) {
    if (l.isDirectional()) {
      std::printf("  %-20s directional along %s, irradiance %s lx\n", printable(l.name).c_str(),
                  vec(l.direction).c_str(), vec(l.intensity).c_str());
      continue;
    }
    bool spot = l.type == PunctualLight::Type::Spot;
    std::printf("  %-20s %s at %s, intensity %s cd", printable(l.name).c_str(), spot ? "spot " : "point",
                vec(l.position).c_str(), vec(l.intensity).c_str());
    if (spot)
      std::printf(", direction %s, cone %.1f..%.1f deg", vec(l.direction).c_str(), l.innerConeAngle * 180.0f / kPi,
                  l.outerConeAngle * 180.0f / kPi);
    std::printf("\n");
  }

  printMedia(scene);

  std::printf("materials:\n");
  for (const Material& m : scene.materials) {
    std::printf("  %-20s base %s", printable(m.name).c_str(), vec(m.baseColor).c_str());
    if (m.baseColorTexture >= 0)
      std::printf(" x texture '%s'",
                  printable(scene.textures[static_cast<std::size_t>(m.baseColorTexture)].name).c_str());
    std::printf(", metallic %.3g, roughness %.3g, specular %.3g", m.metallic, m.roughness, m.specular);
    if (m.isEmissive()) std::printf(", emission %s", vec(m.emission).c_str());
    if (m.isEmissive() && m.emissiveTexture >= 0)
      std::printf(" x texture '%s'",
                  printable(scene.textures[static_cast<std::size_t>(m.emissiveTexture)].name).c_str());
    std::printf("\n");
  }

  const Camera& c = scene.camera;
  std::printf("camera     %s: position %s, forward %s, up %s, yfov %.2f deg\n",
              c.fromFile ? "from file" : "automatic (framing the geometry)", vec(c.position).c_str(),
              vec(c.forward).c_str(), vec(c.up).c_str(), c.yfov * 180.0f / kPi);
  for (const auto& [key, value] : scene.assetExtras)
    std::printf("extras     %s = %.6g\n", printable(key).c_str(), value);
  std::printf("warnings   %zu\n", scene.warnings.size());
  for (const std::string& w : scene.warnings) std::printf("  %s\n", printable(w).c_str());
  return 0;
}

}  // namespace vplab::app
