#include "renderer/gl/resources.h"

#include <cstdio>
#include <glad/gl.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

namespace vplab {

namespace {

GLenum internalFormat(TextureFormat f) {
  switch (f) {
    case TextureFormat::Rgba32F: return GL_RGBA32F;
    case TextureFormat::Rgba16F: return GL_RGBA16F;
    case TextureFormat::Rg32F: return GL_RG32F;
    case TextureFormat::R32F: return GL_R32F;
    case TextureFormat::R16: return GL_R16;
    case TextureFormat::Rgba8: return GL_RGBA8;
    case TextureFormat::Rgba32UI: return GL_RGBA32UI;
    case TextureFormat::Depth32F: return GL_DEPTH_COMPONENT32F;
    case TextureFormat::Depth16: return GL_DEPTH_COMPONENT16;
  }
  return GL_RGBA32F;
}

constexpr std::size_t kTexelBytes = 16;  // of a GlBufferTexture's RGBA32F texels

GLuint createName(GlObject::Kind kind, GLenum target = 0) {
  GLuint id = 0;
  switch (kind) {
    case GlObject::Kind::Texture: glCreateTextures(target, 1, &id); break;
    case GlObject::Kind::Framebuffer: glCreateFramebuffers(1, &id); break;
    case GlObject::Kind::Buffer: glCreateBuffers(1, &id); break;
    case GlObject::Kind::VertexArray: glCreateVertexArrays(1, &id); break;
    case GlObject::Kind::Query: glCreateQueries(target, 1, &id); break;
    case GlObject::Kind::Sampler: glCreateSamplers(1, &id); break;
  }
  if (!id) throw GlError("could not create a GL object (is a context current?)");
  return id;
}

// GL's rows run bottom-up; images' top-down. In place: a copy would be another image-sized allocation, which llvmpipe's
// page faults make cost as much as the read itself.
template <typename Pixel>
void flipRows(std::vector<Pixel>& pixels, int width, int height) {
  const auto w = static_cast<std::ptrdiff_t>(width);
  for (int y = 0; y < height / 2; ++y)
    std::swap_ranges(pixels.begin() + y * w, pixels.begin() + (y + 1) * w, pixels.begin() + (height - 1 - y) * w);
}

}  // namespace

void GlObject::reset() {
  if (!id_) return;
  GLuint id = id_;
  switch (kind_) {
    case Kind::Texture: glDeleteTextures(1, &id); break;
    case Kind::Framebuffer: glDeleteFramebuffers(1, &id); break;
    case Kind::Buffer: glDeleteBuffers(1, &id); break;
    case Kind::VertexArray: glDeleteVertexArrays(1, &id); break;
    case Kind::Query: glDeleteQueries(1, &id); break;
    case Kind::Sampler: glDeleteSamplers(1, &id); break;
  }
  id_ = 0;
}

GlTexture::GlTexture(int width, int height, TextureFormat format, int levels, int layers, bool linear)
    : width_(width), height_(height), layers_(layers), format_(format) {
  assert(width > 0 && height > 0 && layers >= 0);
  int full = 1 + static_cast<int>(std::floor(std::log2(static_cast<float>(std::max(width, height)))));
  levels_ = levels <= 0 ? full : std::min(levels, full);
  object_ = GlObject(GlObject::Kind::Texture,
                     createName(GlObject::Kind::Texture, layers > 0 ? GL_TEXTURE_2D_ARRAY : GL_TEXTURE_2D));
  if (layers > 0)
    glTextureStorage3D(id(), levels_, internalFormat(format), width, height, layers);
  else
    glTextureStorage2D(id(), levels_, internalFormat(format), width, height);
  setLinearFiltering(linear, levels_ > 1);
  setRepeat(false);
}

GlTexture GlTexture::cubeArray(int side, int cubes, TextureFormat format) {
  assert(side > 0 && cubes > 0);
  GlTexture t;
  t.width_ = t.height_ = side;
  t.layers_ = 6 * cubes;
  t.levels_ = 1;
  t.format_ = format;
  t.cube_ = true;
  t.object_ = GlObject(GlObject::Kind::Texture, createName(GlObject::Kind::Texture, GL_TEXTURE_CUBE_MAP_ARRAY));
  glTextureStorage3D(t.id(), 1, internalFormat(format), side, side, 6 * cubes);
  t.setLinearFiltering(true, false);
  t.setRepeat(false);
  return t;
}

GlTexture GlTexture::volume(glm::ivec3 size, const std::vector<float>& values) {
  assert(size.x > 0 && size.y > 0 && size.z > 0 &&
         values.size() == static_cast<std::size_t>(size.x) * size.y * static_cast<std::size_t>(size.z));
  GlTexture t;
  t.width_ = size.x;
  t.height_ = size.y;
  t.levels_ = 1;
  t.format_ = TextureFormat::R32F;
  t.object_ = GlObject(GlObject::Kind::Texture, createName(GlObject::Kind::Texture, GL_TEXTURE_3D));
  glTextureStorage3D(t.id(), 1, GL_R32F, size.x, size.y, size.z);
  // Rows of a single float are 4-byte aligned whatever the width: the default unpack alignment fits.
  glTextureSubImage3D(t.id(), 0, 0, 0, 0, size.x, size.y, size.z, GL_RED, GL_FLOAT, values.data());
  t.setLinearFiltering(true, false);
  t.setRepeat(false);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  return t;
}

void GlTexture::uploadLayerRgba(int layer, const std::vector<glm::vec4>& texels) {
  assert(layers_ > 0 && layer < layers_ && texels.size() == static_cast<std::size_t>(width_) * height_);
  glTextureSubImage3D(id(), 0, 0, 0, layer, width_, height_, 1, GL_RGBA, GL_FLOAT, texels.data());
}

void GlTexture::uploadLayerFloat(int layer, const std::vector<float>& texels) {
  assert(layers_ > 0 && layer < layers_ && texels.size() == static_cast<std::size_t>(width_) * height_);
  glTextureSubImage3D(id(), 0, 0, 0, layer, width_, height_, 1, GL_RED, GL_FLOAT, texels.data());
}

void GlTexture::uploadLayerUnorm16(int layer, const std::vector<std::uint16_t>& texels) {
  assert(layers_ > 0 && layer < layers_ && texels.size() == static_cast<std::size_t>(width_) * height_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
  glTextureSubImage3D(id(), 0, 0, 0, layer, width_, height_, 1, GL_RED, GL_UNSIGNED_SHORT, texels.data());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
}

void GlTexture::uploadDepth16(const std::vector<uint16_t>& texels) {
  assert(format_ == TextureFormat::Depth16 && texels.size() == static_cast<std::size_t>(width_) * height_ * std::max(layers_, 1));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
  if (layers_ > 0)
    glTextureSubImage3D(id(), 0, 0, 0, 0, width_, height_, layers_, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT, texels.data());
  else
    glTextureSubImage2D(id(), 0, 0, 0, width_, height_, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT, texels.data());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
}

void GlTexture::uploadDepth16Layers(int first, int count, const uint16_t* texels) {
  assert(format_ == TextureFormat::Depth16 && layers_ > 0 && first >= 0 && first + count <= layers_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
  glTextureSubImage3D(id(), 0, 0, 0, first, width_, height_, count, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT, texels);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
}

std::vector<uint16_t> GlTexture::readDepth16() const {
  assert(format_ == TextureFormat::Depth16);
  std::vector<uint16_t> texels(static_cast<std::size_t>(width_) * height_ * std::max(layers_, 1));
  glPixelStorei(GL_PACK_ALIGNMENT, 2);
  glGetTextureImage(id(), 0, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT, static_cast<GLsizei>(texels.size() * 2),
                    texels.data());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  return texels;
}

void GlTexture::bind(int unit) const {
  glBindTextureUnit(static_cast<GLuint>(unit), id());
}

void GlTexture::uploadRgb(const std::vector<glm::vec3>& texels) {
  assert(layers_ == 0 && texels.size() == static_cast<std::size_t>(width_) * height_);
  glTextureSubImage2D(id(), 0, 0, 0, width_, height_, GL_RGB, GL_FLOAT, texels.data());
}

void GlTexture::copyFrom(const GlTexture& source) {
  assert(layers_ == 0 && source.layers_ == 0 && source.width_ == width_ && source.height_ == height_ &&
         source.format_ == format_);
  glCopyImageSubData(source.id(), GL_TEXTURE_2D, 0, 0, 0, 0, id(), GL_TEXTURE_2D, 0, 0, 0, 0, width_, height_, 1);
}

void GlTexture::setDepthCompare(bool on) {
  glTextureParameteri(id(), GL_TEXTURE_COMPARE_MODE, on ? GL_COMPARE_REF_TO_TEXTURE : GL_NONE);
  glTextureParameteri(id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
}

void GlTexture::setLinearFiltering(bool linear, bool mipmaps) {
  GLint minFilter =
      linear ? (mipmaps ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR) : (mipmaps ? GL_NEAREST_MIPMAP_NEAREST : GL_NEAREST);
  glTextureParameteri(id(), GL_TEXTURE_MIN_FILTER, minFilter);
  glTextureParameteri(id(), GL_TEXTURE_MAG_FILTER, linear ? GL_LINEAR : GL_NEAREST);
}

void GlTexture::setRepeat(bool repeat) {
  GLint wrap = repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE;
  glTextureParameteri(id(), GL_TEXTURE_WRAP_S, wrap);
  glTextureParameteri(id(), GL_TEXTURE_WRAP_T, wrap);
}

GlFramebuffer::GlFramebuffer() : object_(GlObject::Kind::Framebuffer, createName(GlObject::Kind::Framebuffer)) {}

void GlFramebuffer::attachColor(int index, const GlTexture& texture, int level, int layer) {
  GLenum attachment = GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(index);
  if (texture.layers() > 0 && layer >= 0)
    glNamedFramebufferTextureLayer(id(), attachment, texture.id(), level, layer);
  else
    glNamedFramebufferTexture(id(), attachment, texture.id(), level);
}

void GlFramebuffer::attachDepth(const GlTexture& texture, int level, int layer) {
  if (texture.layers() > 0 && layer >= 0)
    glNamedFramebufferTextureLayer(id(), GL_DEPTH_ATTACHMENT, texture.id(), level, layer);
  else
    glNamedFramebufferTexture(id(), GL_DEPTH_ATTACHMENT, texture.id(), level);
}

void GlFramebuffer::finalize(int colorCount) {
  std::vector<GLenum> buffers;
  for (int i = 0; i < colorCount; ++i) buffers.push_back(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
  if (colorCount > 0)
    glNamedFramebufferDrawBuffers(id(), colorCount, buffers.data());
  else
    glNamedFramebufferDrawBuffer(id(), GL_NONE);
  GLenum status = glCheckNamedFramebufferStatus(id(), GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%04X", static_cast<unsigned>(status));
    throw GlError(std::string("incomplete framebuffer (status ") + hex + ")");
  }
}

void GlFramebuffer::bind(int width, int height) const {
  glBindFramebuffer(GL_FRAMEBUFFER, id());
  glViewport(0, 0, width, height);
}

void GlFramebuffer::clearColor(int index, glm::vec4 value) const {
  glClearNamedFramebufferfv(id(), GL_COLOR, index, &value[0]);
}

void GlFramebuffer::clearDepth(float value) const {
  glClearNamedFramebufferfv(id(), GL_DEPTH, 0, &value);
}

GlBuffer::GlBuffer(std::size_t bytes, const void* data) {
  assign(data, bytes);
}

void GlBuffer::assign(const void* data, std::size_t bytes) {
  // Zero-sized buffers cannot be bound as SSBOs: keep at least 16 bytes.
  std::size_t size = std::max<std::size_t>(bytes, 16);
  if (!object_ || size != size_) {
    object_ = GlObject(GlObject::Kind::Buffer, createName(GlObject::Kind::Buffer));
    glNamedBufferData(id(), static_cast<GLsizeiptr>(size), nullptr, GL_DYNAMIC_DRAW);
    size_ = size;
  }
  if (data && bytes) upload(data, bytes);
}

void GlBuffer::upload(const void* data, std::size_t bytes, std::size_t offset) {
  assert(offset + bytes <= size_);
  glNamedBufferSubData(id(), static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
}

void GlBuffer::bindStorage(int binding) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id());
}
void GlBuffer::bindUniform(int binding) const {
  glBindBufferBase(GL_UNIFORM_BUFFER, binding, id());
}
void GlBuffer::bindUniformRange(int binding, std::size_t offset, std::size_t bytes) const {
  assert(offset + bytes <= size_);
  glBindBufferRange(GL_UNIFORM_BUFFER, static_cast<GLuint>(binding), id(), static_cast<GLintptr>(offset),
                    static_cast<GLsizeiptr>(bytes));
}

GlBufferTexture::GlBufferTexture(std::size_t texels) : texels_(texels) {
  GLint maxTexels = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
  if (texels > static_cast<std::size_t>(maxTexels))
    throw GlError("a buffer texture of " + std::to_string(texels) + " texels: this GL holds at most " +
                  std::to_string(maxTexels));
  buffer_.assign(nullptr, std::max<std::size_t>(texels, 1) * kTexelBytes);
  texture_ = GlObject(GlObject::Kind::Texture, createName(GlObject::Kind::Texture, GL_TEXTURE_BUFFER));
  glTextureBuffer(texture_.id(), GL_RGBA32F, buffer_.id());
}

void GlBufferTexture::bind(int unit) const {
  glBindTextureUnit(static_cast<GLuint>(unit), texture_.id());
}

void GlBufferTexture::copyLevel(const GlTexture& texture, int level, std::size_t firstTexel) {
  assert(texture.format() == TextureFormat::Rgba32F && level < texture.levels());
  const std::size_t texels = static_cast<std::size_t>(std::max(1, texture.width() >> level)) *
                             static_cast<std::size_t>(std::max(1, texture.height() >> level));
  assert(firstTexel + texels <= texels_);
  // Into the buffer bound for pixel packing: the driver copies between its own allocations.
  glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer_.id());
  glGetTextureImage(texture.id(), level, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(texels * kTexelBytes),
                    reinterpret_cast<void*>(firstTexel * kTexelBytes));
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
}

GlVertexArray::GlVertexArray() : object_(GlObject::Kind::VertexArray, createName(GlObject::Kind::VertexArray)) {}
void GlVertexArray::bind() const {
  glBindVertexArray(object_.id());
}

GlLinearSampler::GlLinearSampler() : object_(GlObject::Kind::Sampler, createName(GlObject::Kind::Sampler)) {
  glSamplerParameteri(object_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glSamplerParameteri(object_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glSamplerParameteri(object_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(object_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}
void GlLinearSampler::bind(int unit) const {
  glBindSampler(static_cast<GLuint>(unit), object_.id());
}
void GlLinearSampler::unbind(int unit) {
  glBindSampler(static_cast<GLuint>(unit), 0);
}

GlTimerQuery::GlTimerQuery() : object_(GlObject::Kind::Query, createName(GlObject::Kind::Query, GL_TIME_ELAPSED)) {}
void GlTimerQuery::begin() {
  glBeginQuery(GL_TIME_ELAPSED, object_.id());
}
void GlTimerQuery::end() {
  glEndQuery(GL_TIME_ELAPSED);
  ran_ = true;
}
double GlTimerQuery::resultMs() const {
  if (!ran_) return 0.0;
  GLuint64 ns = 0;
  glGetQueryObjectui64v(object_.id(), GL_QUERY_RESULT, &ns);
  return static_cast<double>(ns) * 1e-6;
}

void drawProceduralTriangles(int vertexCount, int instances) {
  // Core profile draws need a bound vertex array even without attributes; its owner (a pass) keeps it alive.
  GLint bound = 0;
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &bound);
  if (!bound) throw GlError("drawProceduralTriangles: no vertex array bound (bind a GlVertexArray first)");
  glDrawArraysInstanced(GL_TRIANGLES, 0, vertexCount, instances);
}

namespace {
// Colour attachment `index` of `framebuffer` as float texels of `format` (GL_RGBA or GL_RGB) into `pixels`, which
// holds width x height of them, rows top-down.
template <typename Pixel>
void readAttachment(const GlFramebuffer& framebuffer, int index, int width, int height, GLenum format,
                    std::vector<Pixel>& pixels) {
  glNamedFramebufferReadBuffer(framebuffer.id(), GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(index));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadnPixels(0, 0, width, height, format, GL_FLOAT, static_cast<GLsizei>(pixels.size() * sizeof(Pixel)),
                pixels.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  flipRows(pixels, width, height);
}
}  // namespace

std::vector<glm::vec4> readFramebufferRgba(const GlFramebuffer& framebuffer, int index, int width, int height) {
  std::vector<glm::vec4> raw(static_cast<std::size_t>(width) * height);
  readAttachment(framebuffer, index, width, height, GL_RGBA, raw);
  return raw;
}

Image readFramebuffer(const GlFramebuffer& framebuffer, int index, int width, int height) {
  // Straight into the image's RGB pixels (12 bytes, rows 4-aligned).
  Image image(width, height);
  readAttachment(framebuffer, index, width, height, GL_RGB, image.pixels);
  return image;
}

Image readTexture(const GlTexture& texture, int level) {
  int w = std::max(1, texture.width() >> level), h = std::max(1, texture.height() >> level);
  Image image(w, h);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(texture.id(), level, GL_RGB, GL_FLOAT, static_cast<GLsizei>(image.size() * sizeof(glm::vec3)),
                    image.pixels.data());
  flipRows(image.pixels, w, h);
  return image;
}

void checkGlError(const char* what) {
  GLenum e = glGetError();
  if (e != GL_NO_ERROR) throw GlError(std::string(what) + ": GL error 0x" + std::to_string(e));
}

void glFinishAll() {
  glFinish();
}

}  // namespace vplab
