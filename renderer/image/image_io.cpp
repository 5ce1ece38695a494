#include "renderer/image/image_io.h"

#include <stb_image.h>
#include <stb_image_write.h>
// libtinyexr1d ships the compiled implementation, so only the declarations are included here.
#include <tinyexr.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

namespace vplab {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw ImageIoError(path + ": " + what);
}

std::string lowerExtension(const std::string& path) {
  std::size_t slash = path.find_last_of("/\\");
  std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

std::vector<unsigned char> readWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open file for reading");
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) fail(path, "read error");
  return bytes;
}

void requireReadable(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open file for reading");
}

void requireWritable(const std::string& path, const Image& image) {
  assert(image.pixels.size() == static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height));
  if (image.width <= 0 || image.height <= 0) fail(path, "cannot write an empty image");
}

// Header tokens of a PFM are separated by any whitespace; exactly one whitespace byte precedes the raster.
std::string pfmToken(const std::vector<unsigned char>& bytes, std::size_t& pos, const std::string& path) {
  while (pos < bytes.size() && std::isspace(bytes[pos])) ++pos;
  std::size_t start = pos;
  while (pos < bytes.size() && !std::isspace(bytes[pos]) && pos - start < 32) ++pos;
  if (pos == start || pos >= bytes.size()) fail(path, "truncated PFM header");
  return std::string(bytes.begin() + static_cast<std::ptrdiff_t>(start),
                     bytes.begin() + static_cast<std::ptrdiff_t>(pos));
}

int pfmDimension(const std::string& token, const std::string& path) {
  char* end = nullptr;
  long v = std::strtol(token.c_str(), &end, 10);
  if (*end != '\0' || v <= 0 || v > (1 << 20)) fail(path, "invalid PFM dimension '" + token + "'");
  return static_cast<int>(v);
}

}  // namespace

ImageFormat imageFormatFromPath(const std::string& path) {
  std::string ext = lowerExtension(path);
  if (ext == "exr") return ImageFormat::Exr;
  if (ext == "pfm") return ImageFormat::Pfm;
  if (ext == "png") return ImageFormat::Png;
  fail(path, "unknown image extension '" + ext + "' (expected .exr, .pfm or .png)");
}

Image readImage(const std::string& path) {
  switch (imageFormatFromPath(path)) {
    case ImageFormat::Exr: return readExr(path);
    case ImageFormat::Pfm: return readPfm(path);
    case ImageFormat::Png: return readPng(path);
  }
  fail(path, "unhandled image format");
}

void writeImage(const std::string& path, const Image& image, float exposure) {
  switch (imageFormatFromPath(path)) {
    case ImageFormat::Exr: writeExr(path, image); return;
    case ImageFormat::Pfm: writePfm(path, image); return;
    case ImageFormat::Png: writePng(path, image, exposure); return;
  }
}

Image readExr(const std::string& path) {
  requireReadable(path);
  float* rgba = nullptr;
  int width = 0, height = 0;
  const char* err = nullptr;
  int ret = LoadEXR(&rgba, &width, &height, path.c_str(), &err);
  if (ret != TINYEXR_SUCCESS) {
    std::string message = err ? err : "tinyexr error " + std::to_string(ret);
    if (err) FreeEXRErrorMessage(err);
    std::free(rgba);
    fail(path, "cannot read OpenEXR: " + message);
  }
  Image image(width, height);
  for (std::size_t i = 0; i < image.size(); ++i)
    image.pixels[i] = glm::vec3(rgba[4 * i + 0], rgba[4 * i + 1], rgba[4 * i + 2]);
  std::free(rgba);
  return image;
}

void writeExr(const std::string& path, const Image& image) {
  requireWritable(path, image);
  const char* err = nullptr;
  // 32-bit float channels: half would round radiance to 11 bits and break exact round trips of references.
  int ret = SaveEXR(&image.pixels[0].x, image.width, image.height, 3, /*save_as_fp16=*/0, path.c_str(), &err);
  if (ret != TINYEXR_SUCCESS) {
    std::string message = err ? err : "tinyexr error " + std::to_string(ret);
    if (err) FreeEXRErrorMessage(err);
    fail(path, "cannot write OpenEXR: " + message);
  }
}

Image readPfm(const std::string& path) {
  std::vector<unsigned char> bytes = readWholeFile(path);
  std::size_t pos = 0;
  std::string magic = pfmToken(bytes, pos, path);
  int channels = magic == "PF" ? 3 : magic == "Pf" ? 1 : 0;
  if (channels == 0) fail(path, "not a PFM file (magic '" + magic.substr(0, 8) + "', expected PF or Pf)");
  int width = pfmDimension(pfmToken(bytes, pos, path), path);
  int height = pfmDimension(pfmToken(bytes, pos, path), path);
  std::string scaleToken = pfmToken(bytes, pos, path);
  char* end = nullptr;
  double scale = std::strtod(scaleToken.c_str(), &end);
  if (*end != '\0' || scale == 0.0 || !std::isfinite(scale)) fail(path, "invalid PFM scale '" + scaleToken + "'");
  ++pos;  // the single whitespace byte after the scale
  // The sign of the scale is the byte order (negative: little-endian); its magnitude carries no radiance unit here.
  bool fileLittle = scale < 0.0;
  bool swap = fileLittle != (std::endian::native == std::endian::little);

  std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * channels;
  if (bytes.size() < pos || bytes.size() - pos < count * sizeof(float))
    fail(path, "truncated PFM raster (" + std::to_string(width) + "x" + std::to_string(height) + ", " +
                   std::to_string(channels) + " channels)");
  std::vector<float> values(count);
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t word;
    std::memcpy(&word, bytes.data() + pos + 4 * i, 4);
    if (swap) word = __builtin_bswap32(word);
    std::memcpy(&values[i], &word, 4);
  }

  Image image(width, height);
  for (int y = 0; y < height; ++y) {
    // PFM stores the bottom row first.
    const float* row = values.data() + static_cast<std::size_t>(height - 1 - y) * width * channels;
    for (int x = 0; x < width; ++x) {
      const float* p = row + static_cast<std::size_t>(x) * channels;
      image.at(x, y) = channels == 3 ? glm::vec3(p[0], p[1], p[2]) : glm::vec3(p[0]);
    }
  }
  return image;
}

void writePfm(const std::string& path, const Image& image) {
  requireWritable(path, image);
  std::ofstream out(path, std::ios::binary);
  if (!out) fail(path, "cannot open file for writing");
  out << "PF\n" << image.width << " " << image.height << "\n-1.0\n";
  std::vector<std::uint32_t> row(static_cast<std::size_t>(image.width) * 3);
  for (int y = image.height - 1; y >= 0; --y) {
    for (int x = 0; x < image.width; ++x) {
      const glm::vec3& p = image.at(x, y);
      for (int c = 0; c < 3; ++c) {
        std::uint32_t word;
        std::memcpy(&word, &p[c], 4);
        if constexpr (std::endian::native != std::endian::little) word = __builtin_bswap32(word);
        row[static_cast<std::size_t>(x) * 3 + c] = word;
      }
    }
    out.write(reinterpret_cast<const char*>(row.data()), static_cast<std::streamsize>(row.size() * 4));
  }
  if (!out) fail(path, "write error");
}

Image readPng(const std::string& path) {
  requireReadable(path);
  int width = 0, height = 0, channelsInFile = 0;
  Image image;
  if (stbi_is_16_bit(path.c_str())) {
    stbi_us* data = stbi_load_16(path.c_str(), &width, &height, &channelsInFile, 3);
    if (!data) fail(path, std::string("cannot read PNG: ") + stbi_failure_reason());
    image = Image(width, height);
    for (std::size_t i = 0; i < image.size(); ++i)
      image.pixels[i] = linearFromSrgb(glm::vec3(data[3 * i], data[3 * i + 1], data[3 * i + 2]) / 65535.0f);
    stbi_image_free(data);
  } else {
    stbi_uc* data = stbi_load(path.c_str(), &width, &height, &channelsInFile, 3);
    if (!data) fail(path, std::string("cannot read PNG: ") + stbi_failure_reason());
    image = Image(width, height);
    for (std::size_t i = 0; i < image.size(); ++i)
      image.pixels[i] = linearFromSrgb(glm::vec3(data[3 * i], data[3 * i + 1], data[3 * i + 2]) / 255.0f);
    stbi_image_free(data);
  }
  return image;
}

void writePng(const std::string& path, const Image& image, float exposure) {
  requireWritable(path, image);
  writePngRgb8(path, image.width, image.height, tonemapToRgb8(image, exposure));
}

void writePngRgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  assert(rgb.size() == static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  if (width <= 0 || height <= 0) fail(path, "cannot write an empty image");
  if (!stbi_write_png(path.c_str(), width, height, 3, rgb.data(), width * 3))
    fail(path, "cannot write PNG (is the folder there and writable?)");
}

}  // namespace vplab
