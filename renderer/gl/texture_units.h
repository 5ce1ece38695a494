#pragma once
// Texture units of the preview's passes, named once. shaders/common/units.glsl defines the same numbers for GLSL
// (`layout(binding = UNIT_...)`); tests/texture_units_test.cpp checks that the two lists agree.
// The G-buffer units are fixed for every screen pass; PassInput0..7 are the per-pass inputs, whose meaning each pass's
// shader states (the image a filter reads, a light table's shadow maps, ...).

namespace vplab {

enum class TextureUnit : int {
  GPosition = 0,
  GNormal = 1,
  GBaseColor = 2,
  GEmission = 3,
  GGeoNormal = 4,
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
};

constexpr int unit(TextureUnit u) { return static_cast<int>(u); }

}  // namespace vplab
