#pragma once
// Scenes for the tests: built in code with a closed-form answer (independent of the glTF loader and the generated
// assets), or loaded from assets/scenes/ together with their BVH and light sampler.

#include "renderer/offline/offline_scene.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"

#include <glm/glm.hpp>

#include <memory>
#include <string>

namespace vplab::test {


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

/// Irradiance at point x with unit normal n from a one-sided Lambertian polygon of uniform radiance le
/// (Lambert 1760; Arvo 1994, eq. 3): E = le/2 sum_i Theta_i (n . Gamma_i), unoccluded, polygon fully above x.
double polygonIrradiance(const glm::dvec3& x, const glm::dvec3& n, const glm::dvec3* vertices, int count, double le);

}  // namespace vplab::test
