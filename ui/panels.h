#pragma once
// Editor panels as free functions over data the editor owns (plain data in, a bool out): each returns true when it changed a
// value, and the caller marks exactly the dependent work stale with renderer/invalidation.h.

#include "renderer/scene/scene.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"

#include <string>
#include <vector>

namespace vplab::ui {

/// VPL generation method with its parameters, VPL count, bounces, seed; rejection with epsilon; what the last
/// generation did (acceptance with the pilot's predicted spread, warnings); clamp bound b (log slider, with the
/// fraction of energy it removes); VSL radius r (log slider, 0 = off); SSBC steps; interleave k; shadow-map size
/// and bias; direct-light samples; exposure. `clampEnergyRemoved` < 0 means "not measured yet".
/// visibilityInUse: what `auto` picked; sceneDiagonal: shows the clamp bound relative to the scene.
bool drawManyLightPanel(Settings& settings, const VplStats& stats, double clampEnergyRemoved,
                        VisibilityMethod visibilityInUse, float sceneDiagonal);

/// Image size, samples per pixel and path depth of the offline pass.
bool drawOfflineSettingsPanel(Settings& settings);

/// One editable light: a punctual light, or the emissive material of an area light.
struct LightHandle {
  enum class Kind { Punctual, AreaMaterial } kind = Kind::Punctual;
  uint32_t index = 0;  ///< into Scene::punctualLights or Scene::materials
  std::string name;
};

/// The lights the editor can move and scale: punctual lights first, then emissive materials.
std::vector<LightHandle> editableLights(const Scene& scene);

/// What a light edit changed, and so what must be rebuilt: the punctual lights only (their shadow maps and the light
/// sampler; OfflineScene::punctualLightsChanged, PreviewRenderer::invalidateLights), or the geometry or materials
/// (an area light's emissive triangles: the BVH and the GL scene).
enum class LightEdit { None, Punctual, Geometry };
/// The larger of two edits (Geometry includes Punctual).
inline LightEdit combine(LightEdit a, LightEdit b) { return a > b ? a : b; }

/// Moves a light by `offset` (an area light's triangles are translated; a directional light has no position and
/// does not move). The scene's bounds follow.
LightEdit moveLight(Scene& scene, const LightHandle& light, const glm::vec3& offset);
/// Multiplies a light's intensity (or an emissive material's radiance) by `scale`.
LightEdit scaleLight(Scene& scene, const LightHandle& light, float scale);
/// Points a spot or directional light along `direction` (normalised here; a zero vector is ignored).
LightEdit aimLight(Scene& scene, const LightHandle& light, const glm::vec3& direction);

/// The kinds of light the editor adds.
enum class NewLight { Point, Area, Directional };
/// Adds a light sized from the geometry's bounds that gives the model's centre an irradiance of pi (a white surface
/// there reflects radiance 1): a point light or a square area light above the model, or a directional light from
/// above and in front. The scene is finalized.
LightEdit addLight(Scene& scene, NewLight kind);
/// Removes a light: a punctual light from the list, an area light's triangles from the scene (finalized after).
LightEdit deleteLight(Scene& scene, const LightHandle& light);

/// Every editable light with its position offset, intensity scale, direction (spot, directional) and a delete
/// button, and buttons that add a point, area or directional light. Returns what changed (None when nothing did),
/// with the change already applied to the scene; offsets and scales follow added and deleted lights.
LightEdit drawLightsPanel(Scene& scene, std::vector<glm::vec3>& offsets, std::vector<float>& scales);

/// Triangles, lights, materials, staging, warnings.
void drawSceneInfo(const Scene& scene);

}  // namespace vplab::ui
