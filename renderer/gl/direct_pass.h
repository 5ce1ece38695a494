#pragma once
// Pass 2 of the preview (docs/methods.md "Direct light in the preview"): the direct light of K area-light samples and
// of the punctual lights, shadowed by one map per light (light_shadows.h) and interleaved over the light samples as the
// gather is over the VPLs.

#include <array>
#include <functional>
#include <vector>

#include "renderer/gl/light_shadows.h"
#include "renderer/gl/light_table.h"
#include "renderer/gl/media_shader_layout.h"
#include "renderer/gl/screen_pass.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"

namespace vplab {

// Texels per side of the lights' shadow maps, from Settings::lightShadowMapSize S (default 1024).
struct LightMapSizes {
  // A point or spot light's cube face: a few lights, not one map per sample, so they can be sharp (at 1024 a texel
  // spans 0.1 degrees: no stair-steps at contact shadows).
  int punctualFace;
  // An area-light cell's faces, S / 2: as accurate as at S (the emitter's own samples filter its shadow) at a quarter
  // of the texels to draw on the CPU and, in a scene without point or spot lights, to allocate (llvmpipe zero-fills a
  // texture's pages on allocation; docs/benchmarks.md "Preview with media"). A point or spot light's map loses 1 % at
  // 512 (its filter is about a texel wide), so with one in the scene the array's faces are punctualFace and a cell's
  // map is repeated over 2x2 texels there: the same values under nearest sampling.
  int areaFace;
  // A directional light's orthographic map over the scene's bounding sphere, 2 S.
  int directional;
  static LightMapSizes of(const Settings& settings) {
    return {settings.lightShadowMapSize, settings.lightShadowMapSize / 2, 2 * settings.lightShadowMapSize};
  }
};

/// An area emitter's blocker-search taps (shaders/preview/blocker_search.frag.glsl): sample y (xyz) and its cell's
/// map (w), the emitter's normal there, the cell's centre.
struct BlockerSearchTaps {
  std::array<glm::vec4, kBlockerSearchTaps> sample;
  std::array<glm::vec3, kBlockerSearchTaps> normal, centre;
};

class DirectLightPass {
 public:
  DirectLightPass();

  /// Chooses the area-light samples (Settings::directLightSamples and seed), uploads the light table and renders the
  /// lights' shadow maps; sceneRadius: what a directional map covers. With outOfTime, stops after a map face once it
  /// says so and returns false; the next call goes on (one face of a 1024^2 cube is what a frame waits for at most).
  /// True when every map is rendered.
  bool renderMaps(const Scene& scene, const Settings& settings, float sceneRadius,
                  const std::function<bool()>& outOfTime = {});
  /// The next renderMaps() starts over (the lights or their samples changed while it was under way).
  void restartMaps() { mapsStarted_ = false; }
  /// Draws the direct light, reading the G-buffer bound at its units: the area-light samples' into the interleaved
  /// layout of `raw` (merged with the gather), the punctual lights' at every pixel of `punctual` (layout's width and
  /// height; added after the merge, deinterleave.frag.glsl; null when hasExactLights() is false). Both are written
  /// whole. With outOfTime, stops after the draw (or band of one) at which it says so and returns false; the next call
  /// goes on from there, and the image is the same as one call's.
  bool draw(bool lambertOnly, const Camera& camera, glm::vec3 sceneCentre, float sceneRadius, Target& raw,
            const InterleavedLayout& layout, Target* punctual, const GlVertexArray& vao,
            const std::function<bool()>& outOfTime = {});
  /// The next draw() starts from its first draw (what it reads changed while it was under way).
  void restartDraw() { drawSlices_.restart(); }
  /// Whether the lights uploaded by the last renderMaps() include area-light samples (else `raw` stays 0).
  bool hasAreaSamples() const { return !runs_.empty() && runs_.front().kind == AreaMap; }
  /// Whether they include point, spot or directional lights, whose light draw() writes per pixel into `punctual`
  /// (which may be null otherwise).
  bool hasExactLights() const { return !runs_.empty() && runs_.back().kind != AreaMap; }
  /// Compiles the passes with the transmittance of the scene's media toward each light (common/medium.glsl; a count
  /// of 0: none).
  void useMedia(const MediaShaderLayout& media);
  /// The light table as the media pass (media_pass.h) reads it, with the lights' maps bound: the area samples come
  /// first, then the point and spot lights, then the directional ones up to `count`.
  struct TableView {
    const GlBuffer* buffer;
    UniformTableLayout layout;
    int areaEnd, punctualEnd, count;
    LightMapSizes sizes;
  };
  TableView bindTable() const;

 private:
  // What a light's shadow map is; each kind has its own program (DIRECT_MAP_KIND of shaders/preview/direct.frag.glsl).
  enum MapKind { AreaMap, PunctualMap, DirectionalMap, MapKinds };
  // Consecutive lights of the table drawn together by the program of their kind of map: an area emitter's samples
  // (its map filtered once per pixel), or all point and spot lights, or all directional lights.
  struct MapRun {
    int begin, end;
    MapKind kind;
  };

  void uploadLights(const Scene& scene, const Settings& settings);
  // Each area emitter's blocker search per k x k block of `layout`, into its layer of searches_, one step of
  // drawSlices_ each; binds searches_ for the direct pass.
  void drawBlockerSearches(const InterleavedLayout& layout, const GlVertexArray& vao);

  UniformTableLayout tableLayout_;
  std::array<BrdfVariants, MapKinds> programs_;
  GlBuffer table_;
  std::vector<MapRun> runs_;
  // Per area run, in the order of runs_.
  std::vector<BlockerSearchTaps> searchTaps_;
  DeferredProgram searchProgram_;  // compiled when a scene with area lights first needs it
  GlTexture searches_;  // RGBA32F, a layer per area emitter: the blockers' point sum (xyz) and count (w)
  GlFramebuffer searchTarget_;
  LightShadowMaps shadows_;
  std::vector<LightShadowCaster> casters_;
  std::vector<glm::vec3> directionalDirections_;
  LightMapSizes sizes_ = LightMapSizes::of(Settings{});
  // The map rendering under way: the next cube face and directional map (-1: done).
  bool mapsStarted_ = false;
  MediaShaderLayout media_;
  int nextFace_ = 0, nextDirectional_ = 0;
  // Where a draw() cut short goes on.
  PassSlices drawSlices_;
};

}  // namespace vplab
