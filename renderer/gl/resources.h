#pragma once
// Small RAII owners of GL objects (DSA, GL 4.5) and FBO readback into vplab::Image. Names only: no GL types leak
// into this header, so callers do not need the loader. Every function needs a current context.

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <utility>
#include <vector>

#include "renderer/gl/context.h"
#include "renderer/image/image.h"

namespace vplab {

enum class TextureFormat { Rgba32F, Rgba16F, Rg32F, R32F, R16, Rgba8, Rgba32UI, Depth32F, Depth16 };

/// Owns one GL name and deletes it with the matching glDelete* call.
class GlObject {
 public:
  enum class Kind { Texture, Framebuffer, Buffer, VertexArray, Query, Sampler };
  GlObject() = default;
  GlObject(Kind kind, uint32_t id) : kind_(kind), id_(id) {}
  ~GlObject() { reset(); }
  GlObject(GlObject&& o) noexcept : kind_(o.kind_), id_(std::exchange(o.id_, 0u)) {}
  GlObject& operator=(GlObject&& o) noexcept {
    if (this != &o) {
      reset();
      kind_ = o.kind_;
      id_ = std::exchange(o.id_, 0u);
    }
    return *this;
  }
  GlObject(const GlObject&) = delete;
  GlObject& operator=(const GlObject&) = delete;

  uint32_t id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset();

 private:
  Kind kind_ = Kind::Texture;
  uint32_t id_ = 0;
};

/// A 2D texture or 2D texture array (layers > 0) with immutable storage.
class GlTexture {
 public:
  GlTexture() = default;
  /// levels = 0 allocates the full mip chain. Filtering is nearest (G-buffers, depth) unless linear is set.
  GlTexture(int width, int height, TextureFormat format, int levels = 1, int layers = 0, bool linear = false);
  /// A cube-map array of `cubes` cubes (6 * cubes layer-faces), side x side texels, linear filtering.
  static GlTexture cubeArray(int side, int cubes, TextureFormat format);
  /// A 3D R32F texture of size.x * size.y * size.z `values` (x fastest), linear filtering, clamped to the edge on every
  /// axis (a density grid, renderer/gl/media_pass.h).
  static GlTexture volume(glm::ivec3 size, const std::vector<float>& values);
  uint32_t id() const { return object_.id(); }
  int width() const { return width_; }
  int height() const { return height_; }
  int levels() const { return levels_; }
  int layers() const { return layers_; }
  bool isCubeArray() const { return cube_; }
  TextureFormat format() const { return format_; }
  explicit operator bool() const { return static_cast<bool>(object_); }

  void bind(int unit) const;
  /// Uploads RGB float texels (row 0 first) into level 0 of a 2D texture.
  void uploadRgb(const std::vector<glm::vec3>& texels);
  /// Uploads RGBA float texels (row 0 first) into one layer of level 0 of a texture array.
  void uploadLayerRgba(int layer, const std::vector<glm::vec4>& texels);
  /// Uploads single-channel float texels (row 0 first) into one layer (a layer-face of a cube-map array) of level 0.
  void uploadLayerFloat(int layer, const std::vector<float>& texels);
  /// Uploads 16-bit normalised texels (0..65535 = 0..1, row 0 first) into one layer of level 0 of an R16 texture.
  void uploadLayerUnorm16(int layer, const std::vector<std::uint16_t>& texels);
  /// Uploads 16-bit depth texels (0..65535 = 0..1, layer by layer, row 0 first) into level 0 of every layer of a
  /// Depth16 texture array.
  void uploadDepth16(const std::vector<uint16_t>& texels);
  /// Writes `count` whole layers from layer `first` on (a Depth16 array), width x height texels each, row 0 first.
  void uploadDepth16Layers(int first, int count, const uint16_t* texels);
  /// Every layer of a Depth16 texture, row 0 first (tests and diagnostics).
  std::vector<uint16_t> readDepth16() const;
  /// Copies level 0 of `source`, a 2D texture of the same size and format, into level 0 of this one.
  void copyFrom(const GlTexture& source);
  /// Sets depth-comparison sampling (sampler2DShadow / sampler2DArrayShadow).
  void setDepthCompare(bool on);
  void setLinearFiltering(bool linear, bool mipmaps = false);
  void setRepeat(bool repeat);

 private:
  GlObject object_;
  int width_ = 0, height_ = 0, levels_ = 1, layers_ = 0;
  bool cube_ = false;
  TextureFormat format_ = TextureFormat::Rgba32F;
};

/// A framebuffer object over textures it does not own.
class GlFramebuffer {
 public:
  GlFramebuffer();
  /// Attaches level `level` (and `layer` of an array, -1 = all layers, layered rendering) as colour `index`.
  void attachColor(int index, const GlTexture& texture, int level = 0, int layer = -1);
  void attachDepth(const GlTexture& texture, int level = 0, int layer = -1);
  /// Sets glNamedFramebufferDrawBuffers to colour attachments 0..count-1 and checks completeness (throws GlError).
  void finalize(int colorCount);
  /// Binds for drawing and sets the viewport.
  void bind(int width, int height) const;
  void clearColor(int index, glm::vec4 value) const;
  void clearDepth(float value = 1.0f) const;
  uint32_t id() const { return object_.id(); }

 private:
  GlObject object_;
};

/// A buffer object (SSBO, UBO) with dynamic storage.
class GlBuffer {
 public:
  GlBuffer() = default;
  explicit GlBuffer(std::size_t bytes, const void* data = nullptr);
  void upload(const void* data, std::size_t bytes, std::size_t offset = 0);
  /// Reallocates when the size changes.
  void assign(const void* data, std::size_t bytes);
  void bindStorage(int binding) const;
  void bindUniform(int binding) const;
  /// Binds bytes [offset, offset + bytes) as a uniform block; offset must be a multiple of
  /// GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT.
  void bindUniformRange(int binding, std::size_t offset, std::size_t bytes) const;
  std::size_t size() const { return size_; }
  uint32_t id() const { return object_.id(); }

 private:
  GlObject object_;
  std::size_t size_ = 0;
};

/// A buffer read as a one-dimensional texture (GL_TEXTURE_BUFFER, texelFetch from a samplerBuffer) of `texels` RGBA32F
/// texels, filled by copies of 2D textures' levels. llvmpipe fetches a texel from it for about half of what a 2D
/// texture's texel costs (docs/benchmarks.md, "The compensation's taps from buffer textures").
class GlBufferTexture {
 public:
  GlBufferTexture() = default;
  explicit GlBufferTexture(std::size_t texels);
  void bind(int unit) const;
  /// Copies level `level` of an RGBA32F 2D texture, row 0 first, to texels firstTexel on.
  void copyLevel(const GlTexture& texture, int level, std::size_t firstTexel);

 private:
  GlBuffer buffer_;
  GlObject texture_;
  std::size_t texels_ = 0;
};

/// A vertex array: empty for the passes that fetch their vertices from SSBOs by gl_VertexID, or positions + indices.
class GlVertexArray {
 public:
  GlVertexArray();
  void bind() const;

 private:
  GlObject object_;
};

/// Sampler state bound to a texture unit over the texture's own: bilinear filtering of level 0, clamped to the edge.
class GlLinearSampler {
 public:
  GlLinearSampler();
  /// Binds to `unit` (the textures bound there are then filtered by it), or unbinds from it.
  void bind(int unit) const;
  static void unbind(int unit);

 private:
  GlObject object_;
};

/// GL_TIME_ELAPSED query; result() waits for the GPU.
class GlTimerQuery {
 public:
  GlTimerQuery();
  void begin();
  void end();
  /// Milliseconds of GPU time between begin() and end(); 0 when never run.
  double resultMs() const;

 private:
  GlObject object_;
  bool ran_ = false;
};

/// Draws `vertexCount` vertices as triangles with no attributes (the shader builds them from gl_VertexID).
void drawProceduralTriangles(int vertexCount, int instances = 1);

/// Reads colour attachment `index` of `framebuffer` (RGBA32F) into an Image (alpha dropped), flipping rows so that
/// row 0 is the top of the picture.
Image readFramebuffer(const GlFramebuffer& framebuffer, int index, int width, int height);
/// Same, with alpha kept (row 0 at the top).
std::vector<glm::vec4> readFramebufferRgba(const GlFramebuffer& framebuffer, int index, int width, int height);
/// Reads level `level` of a 2D colour texture (RGBA32F), rows flipped so that row 0 is the top.
Image readTexture(const GlTexture& texture, int level = 0);

/// Throws GlError with `what` when glGetError reports an error (use at pass boundaries, not per call).
void checkGlError(const char* what);
/// glFinish: waits for all submitted work (timing and readback boundaries).
void glFinishAll();

}  // namespace vplab
