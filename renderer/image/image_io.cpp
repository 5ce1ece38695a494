#include "renderer/image/image_io.h"

#include <stb_image.h>
// libtinyexr1d ships the compiled implementation, so only the declarations are included here.
#include <tinyexr.h>
#include <zlib.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "renderer/core/atomic_file.h"
#include "renderer/core/text.h"

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

/// The most an image file may hold: a 16384x16384 RGBA float image and its header.
constexpr std::uint64_t kMaxImageBytes = (std::uint64_t(4) << 30) + (1u << 20);
/// The most a PFM sidecar (a flat JSON object of strings) may hold.
constexpr std::uint64_t kMaxSidecarBytes = 16u << 20;

std::vector<unsigned char> readWholeFile(const std::string& path) {
  try {
    std::string bytes = readInputFile(path, kMaxImageBytes, "an image");
    return {bytes.begin(), bytes.end()};
  } catch (const FileReadError& e) {
    throw ImageIoError(e.what());
  }
}

// The decoders that open the file themselves are given it only when it is a regular file of bounded size: a FIFO
// would hang them, /dev/zero would fill the memory, a folder gives "basic_filebuf::underflow" without the path.
void requireReadable(const std::string& path) {
  try {
    requireInputFile(path, kMaxImageBytes, "an image");
  } catch (const FileReadError& e) {
    throw ImageIoError(e.what());
  }
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
  if (*end != '\0' || v <= 0 || v > (1 << 20)) fail(path, "invalid PFM dimension '" + printable(token) + "'");
  return static_cast<int>(v);
}

// Writes the encoded bytes in place of path; a failure keeps the old file and names the reason.
void writeBytes(const std::string& path, std::string_view bytes) {
  try {
    writeFileAtomically(path, bytes);
  } catch (const FileWriteError& e) {
    throw ImageWriteError(e.what());
  }
}

constexpr const char* kInfoPrefix = "vplab.";

}  // namespace

bool isLinearFormat(ImageFormat format) {
  return format != ImageFormat::Png;
}

std::string pfmSidecarPath(const std::string& path) {
  return path + ".json";
}

ImageInfo readImageInfo(const std::string& path) {
  ImageInfo info;
  switch (imageFormatFromPath(path)) {
    case ImageFormat::Png: return info;
    case ImageFormat::Pfm: {
      const std::string sidecar = pfmSidecarPath(path);
      std::error_code ec;
      if (!std::filesystem::exists(sidecar, ec)) return info;
      std::string text;
      try {
        text = readInputFile(sidecar, kMaxSidecarBytes, "a PFM sidecar");
      } catch (const FileReadError& e) {
        throw ImageIoError(e.what());
      }
      nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
      if (!j.is_object()) fail(pfmSidecarPath(path), "not a JSON object of image information");
      for (const auto& [key, value] : j.items())
        if (value.is_string()) info[key] = value.get<std::string>();
      return info;
    }
    case ImageFormat::Exr: {
      requireReadable(path);
      EXRVersion version;
      if (ParseEXRVersionFromFile(&version, path.c_str()) != TINYEXR_SUCCESS) fail(path, "not an OpenEXR file");
      EXRHeader header;
      InitEXRHeader(&header);
      const char* err = nullptr;
      if (ParseEXRHeaderFromFile(&header, &version, path.c_str(), &err) != TINYEXR_SUCCESS) {
        std::string message = err ? err : "unreadable header";
        if (err) FreeEXRErrorMessage(err);
        fail(path, "cannot read OpenEXR header: " + message);
      }
      const std::string prefix = kInfoPrefix;
      for (int i = 0; i < header.num_custom_attributes; ++i) {
        const EXRAttribute& a = header.custom_attributes[i];
        std::string name = a.name;
        if (name.rfind(prefix, 0) != 0 || std::string(a.type) != "string" || a.size < 0) continue;
        std::string value(reinterpret_cast<const char*>(a.value), static_cast<std::size_t>(a.size));
        while (!value.empty() && value.back() == '\0') value.pop_back();
        info[name.substr(prefix.size())] = value;
      }
      FreeEXRHeader(&header);
      return info;
    }
  }
  return info;
}

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

void writeImage(const std::string& path, const Image& image, float exposure, const ImageInfo& info) {
  switch (imageFormatFromPath(path)) {
    case ImageFormat::Exr: writeExr(path, image, info); return;
    case ImageFormat::Pfm: writePfm(path, image, info); return;
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

void writeExr(const std::string& path, const Image& image, const ImageInfo& info) {
  requireWritable(path, image);
  // Planar channels in B, G, R order, as OpenEXR viewers expect; 32-bit float: half would round radiance to 11 bits
  // and break exact round trips of references.
  const std::size_t n = image.size();
  std::vector<float> planes[3];
  for (int c = 0; c < 3; ++c) {
    planes[c].resize(n);
    for (std::size_t i = 0; i < n; ++i) planes[c][i] = image.pixels[i][2 - c];
  }
  float* planePointers[3] = {planes[0].data(), planes[1].data(), planes[2].data()};
  EXRImage exrImage;
  InitEXRImage(&exrImage);
  exrImage.num_channels = 3;
  exrImage.images = reinterpret_cast<unsigned char**>(planePointers);
  exrImage.width = image.width;
  exrImage.height = image.height;

  EXRHeader header;
  InitEXRHeader(&header);
  // ZIP for all but tiny images, as tinyexr's own SaveEXR does.
  header.compression_type =
      image.width < 16 && image.height < 16 ? TINYEXR_COMPRESSIONTYPE_NONE : TINYEXR_COMPRESSIONTYPE_ZIP;
  EXRChannelInfo channels[3] = {};
  int pixelTypes[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
  int requestedTypes[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
  const char* names[3] = {"B", "G", "R"};
  for (int c = 0; c < 3; ++c) std::strncpy(channels[c].name, names[c], sizeof(channels[c].name) - 1);
  header.num_channels = 3;
  header.channels = channels;
  header.pixel_types = pixelTypes;
  header.requested_pixel_types = requestedTypes;

  std::vector<EXRAttribute> attributes;
  std::vector<std::string> values;
  values.reserve(info.size());
  for (const auto& [key, value] : info) {
    EXRAttribute a = {};
    std::string name = kInfoPrefix + key;
    if (name.size() >= sizeof(a.name)) fail(path, "image information key too long: " + key.substr(0, 40));
    std::strncpy(a.name, name.c_str(), sizeof(a.name) - 1);
    std::strncpy(a.type, "string", sizeof(a.type) - 1);
    values.push_back(value);
    a.value = reinterpret_cast<unsigned char*>(values.back().data());
    a.size = static_cast<int>(values.back().size());
    attributes.push_back(a);
  }
  header.num_custom_attributes = static_cast<int>(attributes.size());
  header.custom_attributes = attributes.empty() ? nullptr : attributes.data();

  unsigned char* memory = nullptr;
  const char* err = nullptr;
  std::size_t size = SaveEXRImageToMemory(&exrImage, &header, &memory, &err);
  if (size == 0) {
    std::string message = err ? err : "tinyexr could not encode the image";
    if (err) FreeEXRErrorMessage(err);
    std::free(memory);
    fail(path, "cannot write OpenEXR: " + message);
  }
  std::string bytes(reinterpret_cast<const char*>(memory), size);
  std::free(memory);
  writeBytes(path, bytes);
}

Image readPfm(const std::string& path) {
  std::vector<unsigned char> bytes = readWholeFile(path);
  std::size_t pos = 0;
  std::string magic = pfmToken(bytes, pos, path);
  int channels = magic == "PF" ? 3 : magic == "Pf" ? 1 : 0;
  if (channels == 0) fail(path, "not a PFM file (magic '" + printable(magic.substr(0, 8)) + "', expected PF or Pf)");
  int width = pfmDimension(pfmToken(bytes, pos, path), path);
  int height = pfmDimension(pfmToken(bytes, pos, path), path);
  std::string scaleToken = pfmToken(bytes, pos, path);
  char* end = nullptr;
  double scale = std::strtod(scaleToken.c_str(), &end);
  if (*end != '\0' || scale == 0.0 || !std::isfinite(scale))
    fail(path, "invalid PFM scale '" + printable(scaleToken) + "'");
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

void writePfm(const std::string& path, const Image& image, const ImageInfo& info) {
  requireWritable(path, image);
  std::string bytes = "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n";
  std::size_t header = bytes.size();
  bytes.resize(header + image.size() * 12);
  char* out = bytes.data() + header;
  for (int y = image.height - 1; y >= 0; --y) {
    for (int x = 0; x < image.width; ++x) {
      const glm::vec3& p = image.at(x, y);
      for (int c = 0; c < 3; ++c) {
        std::uint32_t word;
        std::memcpy(&word, &p[c], 4);
        if constexpr (std::endian::native != std::endian::little) word = __builtin_bswap32(word);
        std::memcpy(out, &word, 4);
        out += 4;
      }
    }
  }
  // The sidecar first: a PFM on disk never carries the information of an older render.
  if (!info.empty())
    writeBytes(pfmSidecarPath(path), nlohmann::json(info).dump(2) + "\n");
  else if (std::filesystem::exists(pfmSidecarPath(path)))
    std::filesystem::remove(pfmSidecarPath(path));
  writeBytes(path, bytes);
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

namespace {

// A PNG chunk: length, type, data and the CRC of type and data (PNG specification, section 5.3).
void appendPngChunk(std::string& out, const char type[4], const unsigned char* data, std::size_t size) {
  const auto be32 = [&](uint32_t v) {
    const char bytes[4] = {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
                           static_cast<char>(v)};
    out.append(bytes, 4);
  };
  be32(static_cast<uint32_t>(size));
  out.append(type, 4);
  uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(type), 4);
  if (size > 0) {
    out.append(reinterpret_cast<const char*>(data), size);
    crc = crc32(crc, data, static_cast<uInt>(size));
  }
  be32(static_cast<uint32_t>(crc));
}

// One row of `rgb` with the PNG Paeth filter (type 4) before it, `previous` the row above or null.
void paethRow(const std::uint8_t* row, const std::uint8_t* previous, std::size_t bytes, std::uint8_t* out) {
  out[0] = 4;
  for (std::size_t x = 0; x < bytes; ++x) {
    const int a = x >= 3 ? row[x - 3] : 0, b = previous ? previous[x] : 0, c = x >= 3 && previous ? previous[x - 3] : 0;
    const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    const int predicted = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
    out[x + 1] = static_cast<std::uint8_t>(row[x] - predicted);
  }
}

}  // namespace

void writePngRgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  assert(rgb.size() == static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  if (width <= 0 || height <= 0) fail(path, "cannot write an empty image");
  // Every row Paeth-filtered and deflated by zlib with run-length matches only (Z_RLE): a 640x480 preview encodes in
  // about 8 ms to 97 kB, where stb_image_write (Paeth, level 5) took 18 ms for 151 kB, and a noisy render in a
  // quarter of stb's time and 80 % of its size (docs/benchmarks.md, "Writing PNG files").
  const std::size_t rowBytes = static_cast<std::size_t>(width) * 3;
  // zlib takes 32-bit sizes, and a PNG chunk holds at most 2^31 - 1 bytes.
  if ((rowBytes + 1) * static_cast<std::size_t>(height) > 0x7fff0000u)
    fail(path, "image too large for PNG (" + std::to_string(width) + "x" + std::to_string(height) +
                   "): write .exr or .pfm");
  std::vector<std::uint8_t> filtered((rowBytes + 1) * static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* row = rgb.data() + rowBytes * static_cast<std::size_t>(y);
    paethRow(row, y > 0 ? row - rowBytes : nullptr, rowBytes, filtered.data() + (rowBytes + 1) * y);
  }
  z_stream z{};
  if (deflateInit2(&z, 1, Z_DEFLATED, 15, 8, Z_RLE) != Z_OK) fail(path, "cannot start the PNG compressor");
  std::vector<unsigned char> compressed(deflateBound(&z, static_cast<uLong>(filtered.size())));
  z.next_in = filtered.data();
  z.avail_in = static_cast<uInt>(filtered.size());
  z.next_out = compressed.data();
  z.avail_out = static_cast<uInt>(compressed.size());
  const int status = deflate(&z, Z_FINISH);
  const std::size_t compressedSize = z.total_out;
  deflateEnd(&z);
  if (status != Z_STREAM_END) fail(path, "cannot encode PNG");

  std::string bytes("\x89PNG\r\n\x1a\n", 8);
  unsigned char header[13] = {};
  for (int i = 0; i < 4; ++i) {
    header[i] = static_cast<unsigned char>(static_cast<uint32_t>(width) >> (24 - 8 * i));
    header[4 + i] = static_cast<unsigned char>(static_cast<uint32_t>(height) >> (24 - 8 * i));
  }
  header[8] = 8;  // bits per channel
  header[9] = 2;  // colour type: RGB (compression, filter and interlace methods 0)
  appendPngChunk(bytes, "IHDR", header, sizeof(header));
  appendPngChunk(bytes, "IDAT", compressed.data(), compressedSize);
  appendPngChunk(bytes, "IEND", nullptr, 0);
  writeBytes(path, bytes);
}

}  // namespace vplab
