#pragma once
// The Scene uploaded for rasterisation: vertex and triangle SSBOs (BufferBinding::Scene*, shaders/common/scene.glsl)
// and the base-colour and emissive textures resampled into one texture array (layers share one size, so every texture
// is resampled with Texture::sample, the CPU renderer's own bilinear lookup, at the array's texel centres).

#include "renderer/gl/resources.h"
#include "renderer/scene/scene.h"

namespace vplab {

class GlScene {
 public:
  /// Largest side of the texture array, in texels.
  static constexpr int kMaxTextureSize = 1024;

  explicit GlScene(const Scene& scene);
  /// Binds the buffers and the texture array at their named bindings (renderer/gl/texture_units.h).
  void bind() const;
  int triangleCount() const { return triangleCount_; }
  /// Whether some material has a base-colour or emissive texture.
  bool textured() const { return textured_; }

 private:
  int triangleCount_ = 0;
  bool textured_ = false;
  GlBuffer positions_, normals_, uvs_, triangles_, materials_;
  GlTexture textures_;
};

}  // namespace vplab
