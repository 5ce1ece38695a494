#pragma once
// Scenes for the tests: built in code with a closed-form answer (independent of the glTF loader and the generated
// assets), or loaded from assets/scenes/ together with their BVH and light sampler.

#include <functional>
#include <glm/glm.hpp>
#include <memory>
#include <string>

#include "renderer/image/image.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/scene/density_grid.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"

namespace vplab::test {

/// A homogeneous medium filling the box centre +- half (axis-aligned), and one filling all space
/// (renderer/scene/medium.h).
Medium boxMedium(const glm::vec3& centre, const glm::vec3& half, const glm::vec3& sigmaA, const glm::vec3& sigmaS,
                 float g);
Medium spaceMedium(const glm::vec3& sigmaA, const glm::vec3& sigmaS, float g);
/// A grid medium over the world box [lower, upper] with n voxels per axis, voxel i's centre at lower + (i + 0.5) h: a
/// constant grid then has the optical mass of the homogeneous box [lower, upper] along its axes (its density falls to 0
/// over the half voxel outside the first and last centres on both sides). Named "smoke".
Medium gridMedium(const glm::vec3& lower, const glm::vec3& upper, glm::ivec3 n,
                  const std::function<float(const glm::vec3&)>& density, const glm::vec3& sigmaA,
                  const glm::vec3& sigmaS, float g, int majorantCell = kMajorantCell);

/// Settings for a cheap reference test: size x size pixels, `spp` samples per pixel, 2 threads.
Settings smallReferenceSettings(int size, int spp);

/// Settings for a cheap VPL test: size x size pixels, `vpls` VPLs, 1 sample per pixel, 2 threads.
Settings smallVplSettings(int size, int vpls);

/// Loads assets/scenes/<name>.gltf and builds its BVH and light sampler.
std::unique_ptr<OfflineScene> loadAssetScene(const std::string& name);

/// Index of a new material in scene.materials: Lambertian (specular 0, metallic 0) with the given albedo and
/// emitted radiance.
uint32_t addLambertMaterial(Scene& scene, const glm::vec3& albedo, const glm::vec3& emission = glm::vec3(0.0f));

/// Appends the quad p0 p1 p2 p3 (planar, convex, in order around it) as two triangles whose winding normal points
/// to the side of `facing` (a direction the front must face); per-vertex normals are the face normal.
void addQuad(Scene& scene, const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3,
             uint32_t material, const glm::vec3& facing);

/// The six faces of the cube center +- half, facing inward or outward.
void addCube(Scene& scene, const glm::vec3& center, float half, uint32_t material, bool inward);

/// Appends a bumpy sphere (radius modulated by a few sines, smooth normals) of about `triangles` triangles: a finely
/// tessellated object that shadows itself, like scripts/make_dense_scene.py writes for the benchmarks.
void addBumpySphere(Scene& scene, const glm::vec3& centre, float radius, int triangles, uint32_t material);

/// assets/scenes/cornell-box.gltf with a bumpy sphere of about `triangles` triangles resting on the tall block.
Scene denseCornellScene(int triangles);
/// The same with its BVH and light sampler.
std::unique_ptr<OfflineScene> loadDenseCornell(int triangles);

/// The furnace: a closed cube [-1,1]^3 facing inward, every wall Lambertian with albedo a and emission 1, camera at
/// the centre. Exact radiance everywhere: 1 / (1 - a).
Scene makeFurnaceBox(float albedo);

/// A white Lambert plane (albedo 1, y = 0, facing +y, half size planeHalf) under a square area light of half size
/// lightHalf at height h, centred over the origin, parallel to the plane and emitting radiance le downward.
Scene makePlaneUnderSquareLight(float planeHalf, float lightHalf, float h, float le);

/// The same plane under a point light of intensity `intensity` (candela) at `position`.
Scene makePlaneUnderPointLight(float planeHalf, const glm::vec3& position, float intensity);

/// The same plane (albedo `albedo`) under a directional light whose rays travel along `direction` (normalised
/// here) and deliver irradiance `irradiance` (lux) to a surface facing them.
Scene makePlaneUnderDirectionalLight(float planeHalf, const glm::vec3& direction, float irradiance,
                                     float albedo = 1.0f);

/// A glTF scene with a textured emitter and a closed-form answer (tests/emissive_texture_test.cpp):
/// - a floor [-1,1]^2 at y = 0 facing +y, pure Lambert (albedo 0.5, KHR_materials_specular 0);
/// - a panel x, z in [-0.5, 0.5] at y = 0.5 facing down, a 4 x 4 grid of quads (32 triangles), base colour 0,
///   emissiveFactor x KHR_materials_emissive_strength = kPanelRadiance times an emissive texture of 256 x 4 texels,
///   black for u < 0.5 and white above; the panel's u runs from 0.25 at x = -0.5 to 0.75 at x = 0.5, so the half
///   x < 0 is black and x > 0 emits kPanelRadiance (the bilinear lookup blends the two over |u - 0.5| < 1/512);
/// - the file's camera at (0, 0.15, 1.5) looking down -z (yfov 0.9), seeing the panel's underside and the floor.
struct TexturedPanel {
  static constexpr float kFloorAlbedo = 0.5f;
  static constexpr float kPanelHeight = 0.5f;
  static constexpr float kPanelHalf = 0.5f;
  static inline const glm::vec3 kPanelRadiance{4.0f, 2.0f, 1.0f};
  /// Writes the scene as <name> (.gltf, or .glb with everything embedded) in the test's own directory
  /// (tests/test_tmp.h) and returns the path.
  static std::string write(const std::string& name);
  /// Emitted radiance at panel point x (the texture's bilinear ramp included).
  static glm::vec3 panelRadiance(float x);
  /// Radiance toward the camera along the ray from `origin` along `dir`: the panel's front (textured Le), the floor
  /// (albedo / pi x the white half's polygon irradiance), or 0.
  static glm::vec3 radianceAlong(const glm::vec3& origin, const glm::vec3& dir);
  /// The closed-form image for `camera`: each pixel the mean of radianceAlong() over sub x sub positions in it.
  static Image closedForm(const Camera& camera, int size, int sub = 64);
  /// Expects (gtest) `image` (square, seen by `camera`) to match closedForm(): relMSE at most relMseTolerance, the
  /// energy of the whole image and of the panel's white half (pixels wholly on it) within energyTolerance, the black
  /// half as dark as the closed form (within 1 % of the white half), and the floor's light under each half (pixels
  /// wholly on the floor, left and right of the image's centre) within floorHalfTolerance. Prints the figures, labelled
  /// `what`.
  static void expectClosedForm(const Image& image, const Camera& camera, double relMseTolerance, double energyTolerance,
                               double floorHalfTolerance, const char* what);
};

/// Irradiance at point x with unit normal n from a one-sided Lambertian polygon of uniform radiance le
/// (Lambert 1760; Arvo 1994, eq. 3): E = le/2 sum_i Theta_i (n . Gamma_i), unoccluded, polygon fully above x.
double polygonIrradiance(const glm::dvec3& x, const glm::dvec3& n, const glm::dvec3* vertices, int count, double le);

}  // namespace vplab::test
