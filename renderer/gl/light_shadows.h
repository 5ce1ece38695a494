#pragma once
// Shadows of the preview's direct light (docs/methods.md "Direct light in the preview"): one cube shadow map per
// light, not per light sample, so that the cost is lights x triangles, not K x triangles.
//  - A punctual light: its cube map, filtered over about a texel (no stair-steps at shadow edges).
//  - An area light: the emissive triangles are grouped into at most kMaxAreaGroups emitters, and each emitter's K
//    samples into up to kAreaShadowCells cells of nearby samples (direct_pass.cpp), kMaxAreaGroups maps in all. Each
//    cell has a cube map from its samples' centroid; each sample's shadow is read from its cell's map in the direction
//    where a blocker at the mean blocker distance would cross the segment from the sample to the receiver
//    (shaders/common/light_shadow.glsl, percentage-closer soft shadows with the emitter's own samples as the filter).
//    The K area samples still give the unshadowed light (unbiased); only the visibility is approximated, the less
//    the smaller a cell is against the distances to the blockers.
// Maps store the radial distance to the light in a colour cube map (one value serves every face and the filter taps,
// which cross faces), as 16-bit fractions of the cube's scale, a little more than the distance from its caster to the
// farthest corner of the scene's bounds (steps of 1/65535 of it: a twentieth of a texel's footprint at 512 texels a
// face for a receiver a third of that distance away; half the memory and page faults of 32-bit floats), 1 where no
// triangle lies, drawn on the CPU (distance_raster.h) and uploaded; each texel's distance is pushed away from the
// light by a slope-scaled bias and the receiver is offset along its normal by a texel's footprint, which together
// remove acne on grazing surfaces without a large constant bias.
//  - A directional light: an orthographic map over the scene's bounding sphere, filtered over about a texel.

#include <functional>
#include <vector>

#include "renderer/gl/distance_raster.h"
#include "renderer/gl/resources.h"
#include "renderer/scene/scene.h"

namespace vplab {

/// A point a light's cube map is rendered from (a punctual light, or the centre of an area-light cell).
struct LightShadowCaster {
  glm::vec3 position;
  /// Texels per side its faces are drawn with. The array's faces are the largest caster's, a whole multiple of every
  /// other's: a smaller map is repeated over blocks of texels there, which nearest sampling reads as the map itself.
  int faceSize;
};

/// An emitter made of emissive triangles: a connected group (triangles sharing vertices), merged into the nearest of
/// the kMaxAreaGroups most powerful groups when there are more.
struct AreaLightGroup {
  std::vector<uint32_t> triangles;
  /// Power-weighted centre (luminance(Le) x area): where weaker groups join the nearest.
  glm::vec3 centre{0.0f};
  float power = 0.0f;
};

inline constexpr int kMaxAreaGroups = 8;
/// Cells (each with its own map) an emitter's samples are split into, while the maps stay within kMaxAreaGroups: one
/// map per emitter left the Debian 2CylinderEngine's fins under its studio light 5 % too dark, four 1 % (docs/methods.md
/// "Direct light in the preview").
inline constexpr int kAreaShadowCells = 4;
/// Taps of an area emitter's blocker search (shaders/preview/blocker_search.frag.glsl): with 8 instead of 16 the
/// studio case of vplab_bench_direct_bench moved from relMSE 0.013 to 0.021 (docs/benchmarks.md "Direct light in the
/// preview").
inline constexpr int kBlockerSearchTaps = 16;
std::vector<AreaLightGroup> groupAreaLights(const Scene& scene);

class LightShadowMaps {
 public:
  /// Renders one cube per caster (radial distance), face 6 c + f of caster c, from face `first` on, on `threads`
  /// threads (Settings::threads). With outOfTime, stops after a face once it says so and returns the first face not
  /// rendered (the next call's `first`); -1 when every face is rendered. The maps do not depend on where it stopped.
  int render(const Scene& scene, const std::vector<LightShadowCaster>& casters, int threads, int first = 0,
             const std::function<bool()>& outOfTime = {});
  /// Renders one orthographic map of size^2 texels per directional light (unit direction of travel), over the disc of
  /// `radius` around `centre` perpendicular to it (the scene's bounding sphere), from map `first` on; stops and
  /// returns as render() does.
  int renderDirectional(const Scene& scene, const std::vector<glm::vec3>& directions, glm::vec3 centre, float radius,
                        int size, int threads, int first = 0, const std::function<bool()>& outOfTime = {});
  /// Binds the cube-map array and the directional maps (TextureUnit::LightShadows, DirectionalShadows).
  void bind() const;
  int count() const { return count_; }

 private:
  GlTexture cubes_, planes_;
  DistanceRasterizer rasterizer_;
  // The cube rasterizer_ last binned (null: none, or a directional map).
  const Scene* binnedScene_ = nullptr;
  glm::vec3 binnedOrigin_{0.0f};
  // A face as drawn, quantised, and repeated up to the array's faces.
  std::vector<float> texels_;
  std::vector<std::uint16_t> quantized_, repeated_;
  // Each cube's scale, and the buffer that holds it (LightShadowScales).
  std::vector<float> scales_;
  GlBuffer scalesBuffer_;
  int count_ = 0, directionalCount_ = 0;
};

}  // namespace vplab
