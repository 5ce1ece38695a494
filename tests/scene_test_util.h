#pragma once
// Builds small glTF files at test time (well-formed or deliberately broken) in the test's own directory
// (tests/test_tmp.h).

#include <cstdint>
#include <cstring>
#include <fstream>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "renderer/scene/gltf_loader.h"
#include "tests/test_tmp.h"

namespace vplab::test {

inline std::string base64(const std::vector<unsigned char>& data) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < data.size(); i += 3) {
    uint32_t v = static_cast<uint32_t>(data[i]) << 16;
    if (i + 1 < data.size()) v |= static_cast<uint32_t>(data[i + 1]) << 8;
    if (i + 2 < data.size()) v |= data[i + 2];
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < data.size() ? table[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? table[v & 63] : '=';
  }
  return out;
}

/// What loadScene() says of a file: its SceneError's message, or "(no error)".
inline std::string loadError(const std::string& path) {
  try {
    loadScene(path);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

inline void writeBytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

/// A glTF document under construction: one binary buffer, accessors appended tightly packed.
struct GltfBuilder {
  nlohmann::json doc = {
      {"asset", {{"version", "2.0"}}}, {"scene", 0}, {"scenes", {{{"nodes", nlohmann::json::array()}}}}};
  std::vector<unsigned char> bin;

  int push(const char* key, nlohmann::json value) {
    doc[key].push_back(std::move(value));
    return static_cast<int>(doc[key].size()) - 1;
  }

  int view(const void* data, std::size_t bytes) {
    while (bin.size() % 4) bin.push_back(0);
    std::size_t offset = bin.size();
    bin.resize(offset + bytes);
    std::memcpy(bin.data() + offset, data, bytes);
    return push("bufferViews", {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
  }

  int accessor(int bufferView, int componentType, std::size_t count, const char* type) {
    return push("accessors",
                {{"bufferView", bufferView}, {"componentType", componentType}, {"count", count}, {"type", type}});
  }

  int vec3(const std::vector<glm::vec3>& v) { return accessor(view(v.data(), v.size() * 12), 5126, v.size(), "VEC3"); }
  int vec2(const std::vector<glm::vec2>& v) { return accessor(view(v.data(), v.size() * 8), 5126, v.size(), "VEC2"); }
  int indicesU8(const std::vector<uint8_t>& i) { return accessor(view(i.data(), i.size()), 5121, i.size(), "SCALAR"); }
  int indicesU16(const std::vector<uint16_t>& i) {
    return accessor(view(i.data(), i.size() * 2), 5123, i.size(), "SCALAR");
  }
  int indicesU32(const std::vector<uint32_t>& i) {
    return accessor(view(i.data(), i.size() * 4), 5125, i.size(), "SCALAR");
  }

  /// A primitive as JSON; add it to a mesh with mesh().
  static nlohmann::json primitive(int position, int indices = -1, int normal = -1, int material = -1, int mode = 4) {
    nlohmann::json p = {{"attributes", {{"POSITION", position}}}, {"mode", mode}};
    if (normal >= 0) p["attributes"]["NORMAL"] = normal;
    if (indices >= 0) p["indices"] = indices;
    if (material >= 0) p["material"] = material;
    return p;
  }
  int mesh(std::vector<nlohmann::json> primitives) { return push("meshes", {{"primitives", primitives}}); }

  /// Adds a node; root nodes are listed in the scene.
  int node(nlohmann::json n, bool root = true) {
    int i = push("nodes", std::move(n));
    if (root) doc["scenes"][0]["nodes"].push_back(i);
    return i;
  }
  int meshNode(int meshIndex) { return node({{"mesh", meshIndex}}); }

  int emissiveMaterial(glm::vec3 radiance = glm::vec3(1.0f)) {
    return push("materials", {{"name", "emitter"}, {"emissiveFactor", {radiance.x, radiance.y, radiance.z}}});
  }

  /// A unit quad emitter far below the test geometry, so scenes are not reported as having no lights.
  void addLightQuad() {
    int pos = vec3({{0, -10, 0}, {1, -10, 0}, {1, -10, 1}, {0, -10, 1}});
    int idx = indicesU16({0, 2, 1, 0, 3, 2});
    meshNode(mesh({primitive(pos, idx, -1, emissiveMaterial())}));
  }

  /// Writes .gltf with the buffer embedded as a data URI (or as an external file when binName is given).
  /// declaredExtra adds to the buffer's byteLength, making the buffer too short for what it claims.
  std::string writeGltf(const std::string& name, const std::string& binName = "", std::size_t declaredExtra = 0) {
    nlohmann::json d = doc;
    if (binName.empty()) {
      d["buffers"] = {
          {{"byteLength", bin.size() + declaredExtra}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
    } else {
      d["buffers"] = {{{"byteLength", bin.size()}, {"uri", binName}}};
      writeBytes(tmpPath(binName), bin);
    }
    writeText(tmpPath(name), d.dump());
    return tmpPath(name);
  }

  /// The same document as a binary .glb (JSON chunk, then BIN chunk).
  std::vector<unsigned char> glbBytes() const {
    nlohmann::json d = doc;
    d["buffers"] = {{{"byteLength", bin.size()}}};
    std::string json = d.dump();
    while (json.size() % 4) json += ' ';
    std::vector<unsigned char> payload = bin;
    while (payload.size() % 4) payload.push_back(0);
    std::vector<unsigned char> out = {'g', 'l', 'T', 'F'};
    auto u32 = [&out](uint32_t v) {
      for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
    };
    u32(2);
    u32(static_cast<uint32_t>(12 + 8 + json.size() + 8 + payload.size()));
    u32(static_cast<uint32_t>(json.size()));
    u32(0x4E4F534A);
    out.insert(out.end(), json.begin(), json.end());
    u32(static_cast<uint32_t>(payload.size()));
    u32(0x004E4942);
    out.insert(out.end(), payload.begin(), payload.end());
    return out;
  }
};

/// 24-bit uncompressed BMP (rows bottom-up, padded to 4 bytes) from sRGB bytes given top row first.
inline std::vector<unsigned char> bmp(int width, int height, const std::vector<glm::u8vec3>& rgbTopDown) {
  int rowBytes = (3 * width + 3) & ~3;
  uint32_t dataSize = static_cast<uint32_t>(rowBytes * height);
  std::vector<unsigned char> out = {'B', 'M'};
  auto u16 = [&out](uint32_t v) {
    for (int i = 0; i < 2; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
  };
  auto u32 = [&out](uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
  };
  u32(54 + dataSize);
  u32(0);
  u32(54);
  u32(40);
  u32(static_cast<uint32_t>(width));
  u32(static_cast<uint32_t>(height));
  u16(1);
  u16(24);
  u32(0);
  u32(dataSize);
  u32(2835);
  u32(2835);
  u32(0);
  u32(0);
  for (int y = height - 1; y >= 0; --y) {
    for (int x = 0; x < width; ++x) {
      const glm::u8vec3& c = rgbTopDown[static_cast<std::size_t>(y * width + x)];
      out.insert(out.end(), {c.b, c.g, c.r});
    }
    for (int p = 3 * width; p < rowBytes; ++p) out.push_back(0);
  }
  return out;
}

}  // namespace vplab::test
