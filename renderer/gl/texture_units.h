#pragma once
// Texture units and buffer binding points of the preview's passes, named once. shaders/common/units.glsl defines the
// same numbers for GLSL (`layout(binding = UNIT_...)`, `layout(std430, binding = BINDING_...)`); a test
// (tests/ism_test.cpp, TextureUnits) checks that the two lists agree.
// The G-buffer units are fixed for every screen pass; PassInput0..7 are the per-pass inputs, whose meaning each pass's
// shader states (the image a filter reads, a light table's shadow maps, ...).

namespace vplab {

enum class TextureUnit : int {
  GPosition = 0,
  GNormal = 1,
  GBaseColor = 2,
  GEmission = 3,
  /// Half of the interleaved passes' packed surface (shaders/common/gbuffer_packing.glsl): shading normal, base colour
  /// and BRDF parameters.
  GShading = 4,
  SceneTextures = 5,
  PassInput0 = 6,
  PassInput1 = 7,
  PassInput2 = 8,
  PassInput3 = 9,
  GMergeKey = 10,
  PassInput4 = 11,
  PassInput5 = 12,
  PassInput6 = 13,
  PassInput7 = 14,
  /// The VPLs' visibility technique (renderer/gl/vpl_visibility.h) in the gather.
  Visibility = 15,
  /// The lights' cube shadow maps (renderer/gl/light_shadows.h) in the direct pass.
  LightShadows = 16,
  /// The directional lights' orthographic shadow maps (renderer/gl/light_shadows.h) in the direct pass.
  DirectionalShadows = 17,
  /// The direct pass's blocker searches of the area emitters, one per k x k block (renderer/gl/direct_pass.h).
  BlockerSearch = 18,
  /// The first of the grid media's density textures (renderer/gl/density_grids_gpu.h, common/medium.glsl), in every
  /// pass that reads the media table: grid g's on unit MediaDensity + g, up to kPreviewMaxDensityGrids (4) units.
  MediaDensity = 19,
  /// The other half: position and geometric normal (after the media's density units).
  GSurface = 23,
};

constexpr int unit(TextureUnit u) {
  return static_cast<int>(u);
}

/// Indexed buffer binding points. Storage and uniform blocks have separate binding spaces in GL; the numbers are
/// distinct anyway, so that one list names them all.
enum class BufferBinding : int {
  /// The scene's storage buffers (renderer/gl/gl_scene.h, common/scene.glsl).
  ScenePositions = 0,
  SceneNormals = 1,
  SceneUvs = 2,
  SceneTriangles = 3,
  SceneMaterials = 4,
  /// The direct-light table (uniform block of preview/direct.frag.glsl).
  DirectLights = 7,
  /// The VPL table (uniform block of common/gather.glsl).
  Vpls = 8,
  /// The scene's participating media (uniform block of common/medium.glsl).
  Media = 9,
  /// The density grids of the scene's grid media that no 3D texture holds, as NanoVDB grids (storage block of
  /// common/medium.glsl, renderer/gl/density_grids_gpu.h).
  MediaDensityGrid = 10,
  /// Each light cube map's distance scale (renderer/gl/light_shadows.h, common/light_maps.glsl).
  LightShadowScales = 11,
};

constexpr int binding(BufferBinding b) {
  return static_cast<int>(b);
}

}  // namespace vplab
