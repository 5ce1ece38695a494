#include "renderer/scene/gltf_loader.h"

#include "renderer/core/atomic_file.h"
#include "renderer/core/sampling.h"
#include "renderer/core/text.h"
#include "renderer/scene/media_gltf.h"

#include <nlohmann/json.hpp>
#include <stb/stb_image.h>
#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

namespace vplab {
namespace {

constexpr int kModePoints = 0;
constexpr int kModeTriangles = 4;
constexpr int kModeTriangleStrip = 5;
constexpr int kModeTriangleFan = 6;

/// The glTF spelling of an accessor type ("VEC2"), not tinygltf's code.
std::string accessorTypeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
  }
  return "unknown (" + std::to_string(type) + ")";
}

std::string accessorTypeNames(const std::vector<int>& types) {
  std::string out;
  for (std::size_t i = 0; i < types.size(); ++i)
    out += (i == 0 ? "" : i + 1 == types.size() ? " or " : ", ") + accessorTypeName(types[i]);
  return out;
}

/// The most a buffer or image referenced by a scene may hold (tinygltf keeps each whole in memory).
constexpr std::uint64_t kMaxReferencedBytes = std::uint64_t(4) << 30;

std::string firstLine(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos)
      return line.size() > 200 ? line.substr(0, 200) + "..." : line;  // tinygltf may quote a whole data URI
  return "unknown error";
}

std::string directoryOf(const std::string& path) {
  std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  return std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// Deepest nesting of JSON arrays and objects accepted; glTF itself needs fewer than 10 levels, and the JSON parsers
/// recurse once per level.
constexpr int kMaxJsonDepth = 256;


/// Extensions the loader implements, and what it does with some it does not (used in the warning).
bool isSupportedExtension(const std::string& name) {
  return name == "KHR_lights_punctual" || name == "KHR_materials_emissive_strength" ||
         name == "KHR_materials_specular" || name == "KHR_texture_transform" || name == kMediaExtension;
}

std::string unsupportedExtensionEffect(const std::string& name) {
  if (name == "KHR_materials_pbrSpecularGlossiness") return "the metallic-roughness fallback (if any) is used";
  if (name == "KHR_materials_clearcoat") return "the clear-coat layer is left out";
  if (name == "KHR_materials_transmission" || name == "KHR_materials_volume") return "surfaces are opaque";
  return "ignored";
}

/// Depth of JSON nesting, scanning brackets outside strings; stops counting at kMaxJsonDepth + 1.
int jsonDepth(const char* json, std::size_t size) {
  int depth = 0, deepest = 0;
  bool inString = false;
  for (std::size_t i = 0; i < size; ++i) {
    char c = json[i];
    if (inString) {
      if (c == '\\') ++i;
      else if (c == '"') inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
      if (deepest > kMaxJsonDepth) return deepest;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

/// Image bytes captured by the custom image loader. Decoding is deferred until the loader has validated the
/// references itself, so a missing or corrupt image degrades to a warning instead of failing the whole file.
struct CapturedImages {
  std::vector<std::vector<unsigned char>> bytes;  ///< per image index; empty when nothing was read
};

bool captureImage(tinygltf::Image* image, const int imageIndex, std::string*, std::string*, int, int,
                  const unsigned char* bytes, int size, void* user) {
  // Images in a bufferView are read later from the validated buffer: tinygltf hands us a pointer computed from an
  // unchecked byteOffset here, so it must not be dereferenced.
  if (image->bufferView >= 0 || imageIndex < 0 || size <= 0 || bytes == nullptr) return true;
  auto* captured = static_cast<CapturedImages*>(user);
  if (captured->bytes.size() <= static_cast<std::size_t>(imageIndex))
    captured->bytes.resize(static_cast<std::size_t>(imageIndex) + 1);
  captured->bytes[static_cast<std::size_t>(imageIndex)].assign(bytes, bytes + size);
  return true;
}

float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

/// A validated window onto an accessor's bytes.
struct AccessorView {
  const unsigned char* base = nullptr;  ///< nullptr: no bufferView, every element reads as zero (glTF 3.6.2.3)
  std::size_t stride = 0;
  std::size_t count = 0;
  int componentType = 0;
  int components = 0;
  bool normalized = false;
};

class Loader {
 public:
  Loader(std::string file, const tinygltf::Model& model, CapturedImages& images, Scene& scene)
      : file_(std::move(file)), model_(model), images_(images), scene_(scene) {}

  void run();

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw SceneError(file_ + ": " + where + ": " + what);
  }
  void warn(const std::string& where, const std::string& what) { scene_.warnings.push_back(where + ": " + what); }
  /// The folder the file's relative references (buffers, images, density grids) start from.
  std::string baseDir() const { return directoryOf(file_); }

  AccessorView view(int accessorIndex, const std::string& where, const std::vector<int>& types);
  std::vector<glm::vec3> readVec3(int accessorIndex, const std::string& where);
  std::vector<glm::vec2> readUv(int accessorIndex, const std::string& where);
  std::vector<uint32_t> readIndices(int accessorIndex, const std::string& where);

  glm::mat4 localTransform(int nodeIndex) const;
  void visitNode(int nodeIndex, const glm::mat4& world);
  void addPrimitive(int meshIndex, int primitiveIndex, const glm::mat4& world);
  uint32_t materialIndex(int gltfMaterial, const std::string& where);
  int textureIndex(int gltfTexture, const std::string& where);
  glm::mat3 textureTransform(const tinygltf::ExtensionMap& extensions, const std::string& where);
  void addLight(int nodeIndex, const glm::mat4& world);
  void addCamera(int nodeIndex, const glm::mat4& world);
  void addMediumBox(int nodeIndex, const glm::mat4& world);
  void frameBounds();
  void readAssetExtras();

  std::string file_;
  const tinygltf::Model& model_;
  CapturedImages& images_;
  Scene& scene_;
  std::vector<int> materialMap_;  ///< glTF material -> Scene material, -1 until first use
  /// glTF material -> KHR_texture_transform of its base colour texture (identity without one), set by materialIndex()
  std::vector<glm::mat3> uvTransforms_;
  int defaultMaterial_ = -1;
  std::vector<int> imageTextures_;  ///< glTF image -> Scene texture, -1 unloadable, -2 not tried yet
  bool haveCamera_ = false;
  std::vector<std::string> mediumPaths_;  ///< glTF path of each scene_.media entry, for error messages
};

AccessorView Loader::view(int accessorIndex, const std::string& where, const std::vector<int>& types) {
  if (accessorIndex < 0 || static_cast<std::size_t>(accessorIndex) >= model_.accessors.size())
    fail(where, "accessor " + std::to_string(accessorIndex) + " out of range (" +
                    std::to_string(model_.accessors.size()) + " accessors)");
  const tinygltf::Accessor& a = model_.accessors[static_cast<std::size_t>(accessorIndex)];
  std::string at = where + " (accessors[" + std::to_string(accessorIndex) + "])";
  if (std::find(types.begin(), types.end(), a.type) == types.end())
    fail(at, "accessor type " + accessorTypeName(a.type) + ", expected " + accessorTypeNames(types));
  if (a.sparse.isSparse) fail(at, "sparse accessors are not supported");
  AccessorView v;
  v.componentType = a.componentType;
  v.components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
  v.count = a.count;
  v.normalized = a.normalized;
  int componentSize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
  if (componentSize <= 0 || v.components <= 0) fail(at, "invalid componentType " + std::to_string(a.componentType));
  std::size_t elementSize = static_cast<std::size_t>(componentSize) * static_cast<std::size_t>(v.components);
  if (a.bufferView < 0) return v;  // all zeros
  if (static_cast<std::size_t>(a.bufferView) >= model_.bufferViews.size())
    fail(at, "bufferView " + std::to_string(a.bufferView) + " out of range (" +
                 std::to_string(model_.bufferViews.size()) + " bufferViews)");
  const tinygltf::BufferView& bv = model_.bufferViews[static_cast<std::size_t>(a.bufferView)];
  std::string bvAt = "bufferViews[" + std::to_string(a.bufferView) + "]";
  if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= model_.buffers.size())
    fail(bvAt, "buffer " + std::to_string(bv.buffer) + " out of range (" + std::to_string(model_.buffers.size()) +
                   " buffers)");
  const tinygltf::Buffer& buffer = model_.buffers[static_cast<std::size_t>(bv.buffer)];
  // Sizes are compared by subtraction so that huge offsets in a hostile file cannot overflow.
  if (bv.byteOffset > buffer.data.size() || bv.byteLength > buffer.data.size() - bv.byteOffset)
    fail(bvAt, "bytes [" + std::to_string(bv.byteOffset) + ", " + std::to_string(bv.byteOffset + bv.byteLength) +
                   ") exceed buffers[" + std::to_string(bv.buffer) + "] (" + std::to_string(buffer.data.size()) +
                   " bytes)");
  v.stride = bv.byteStride == 0 ? elementSize : bv.byteStride;
  if (v.stride < elementSize) fail(bvAt, "byteStride " + std::to_string(bv.byteStride) + " smaller than an element");
  if (v.count > 0) {
    std::size_t needed = a.byteOffset;
    bool overflow = (v.count - 1) > (std::numeric_limits<std::size_t>::max() - elementSize) / v.stride;
    if (!overflow) needed += (v.count - 1) * v.stride + elementSize;
    if (overflow || a.byteOffset > bv.byteLength || needed > bv.byteLength)
      fail(at, std::to_string(v.count) + " elements from byteOffset " + std::to_string(a.byteOffset) +
                   " exceed bufferViews[" + std::to_string(a.bufferView) + "] (" + std::to_string(bv.byteLength) +
                   " bytes)");
  }
  v.base = buffer.data.data() + bv.byteOffset + a.byteOffset;
  return v;
}

/// Component c of element i as a float, applying the normalisation rules of glTF 3.11 for integer types.
float readComponent(const AccessorView& v, std::size_t i, int c) {
  if (v.base == nullptr) return 0.0f;
  const unsigned char* p = v.base + i * v.stride;
  switch (v.componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p + 4 * c, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      float f = static_cast<float>(p[c]);
      return v.normalized ? f / 255.0f : f;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      float f = static_cast<float>(static_cast<int8_t>(p[c]));
      return v.normalized ? std::max(f / 127.0f, -1.0f) : f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t u;
      std::memcpy(&u, p + 2 * c, 2);
      return v.normalized ? static_cast<float>(u) / 65535.0f : static_cast<float>(u);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t s;
      std::memcpy(&s, p + 2 * c, 2);
      return v.normalized ? std::max(static_cast<float>(s) / 32767.0f, -1.0f) : static_cast<float>(s);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t u;
      std::memcpy(&u, p + 4 * c, 4);
      return static_cast<float>(u);
    }
    default: return 0.0f;
  }
}

std::vector<glm::vec3> Loader::readVec3(int accessorIndex, const std::string& where) {
  AccessorView v = view(accessorIndex, where, {TINYGLTF_TYPE_VEC3});
  if (v.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
    fail(where, "componentType " + std::to_string(v.componentType) + " is not FLOAT");
  std::vector<glm::vec3> out(v.count);
  for (std::size_t i = 0; i < v.count; ++i)
    out[i] = {readComponent(v, i, 0), readComponent(v, i, 1), readComponent(v, i, 2)};
  return out;
}

std::vector<glm::vec2> Loader::readUv(int accessorIndex, const std::string& where) {
  AccessorView v = view(accessorIndex, where, {TINYGLTF_TYPE_VEC2});
  bool ok = v.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
            (v.normalized && (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                              v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
  if (!ok) fail(where, "componentType " + std::to_string(v.componentType) + " is not FLOAT or normalized u8/u16");
  std::vector<glm::vec2> out(v.count);
  for (std::size_t i = 0; i < v.count; ++i) {
    out[i] = {readComponent(v, i, 0), readComponent(v, i, 1)};
    if (!std::isfinite(out[i].x) || !std::isfinite(out[i].y))
      fail(where, "element " + std::to_string(i) + " is not finite");
  }
  return out;
}

std::vector<uint32_t> Loader::readIndices(int accessorIndex, const std::string& where) {
  AccessorView v = view(accessorIndex, where, {TINYGLTF_TYPE_SCALAR});
  if (v.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      v.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      v.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    fail(where, "componentType " + std::to_string(v.componentType) + " is not an unsigned integer type");
  std::vector<uint32_t> out(v.count);
  for (std::size_t i = 0; i < v.count; ++i) {
    if (v.base == nullptr) {
      out[i] = 0;
      continue;
    }
    const unsigned char* p = v.base + i * v.stride;
    if (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
      out[i] = p[0];
    } else if (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
      uint16_t u;
      std::memcpy(&u, p, 2);
      out[i] = u;
    } else {
      std::memcpy(&out[i], p, 4);
    }
  }
  return out;
}

glm::mat4 Loader::localTransform(int nodeIndex) const {
  const tinygltf::Node& node = model_.nodes[static_cast<std::size_t>(nodeIndex)];
  std::string at = "nodes[" + std::to_string(nodeIndex) + "]";
  auto allFinite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double d) { return std::isfinite(d); });
  };
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16 || !allFinite(node.matrix)) fail(at + ".matrix", "needs 16 finite numbers");
    glm::mat4 m;
    for (int i = 0; i < 16; ++i) glm::value_ptr(m)[i] = static_cast<float>(node.matrix[static_cast<std::size_t>(i)]);
    return m;  // glTF matrices are column-major, as glm's storage
  }
  glm::mat4 m(1.0f);
  if (!node.translation.empty()) {
    if (node.translation.size() != 3 || !allFinite(node.translation))
      fail(at + ".translation", "needs 3 finite numbers");
    m = glm::translate(m, glm::vec3(node.translation[0], node.translation[1], node.translation[2]));
  }
  if (!node.rotation.empty()) {
    if (node.rotation.size() != 4 || !allFinite(node.rotation)) fail(at + ".rotation", "needs 4 finite numbers");
    // glTF stores quaternions as (x, y, z, w); glm's constructor takes w first.
    glm::quat q(static_cast<float>(node.rotation[3]), static_cast<float>(node.rotation[0]),
                static_cast<float>(node.rotation[1]), static_cast<float>(node.rotation[2]));
    float len = glm::length(q);
    if (!(len > 0.0f)) fail(at + ".rotation", "zero quaternion");
    m = m * glm::mat4_cast(q / len);
  }
  if (!node.scale.empty()) {
    if (node.scale.size() != 3 || !allFinite(node.scale)) fail(at + ".scale", "needs 3 finite numbers");
    m = glm::scale(m, glm::vec3(node.scale[0], node.scale[1], node.scale[2]));
  }
  return m;
}

void Loader::run() {
  materialMap_.assign(model_.materials.size(), -1);
  uvTransforms_.assign(model_.materials.size(), glm::mat3(1.0f));
  imageTextures_.assign(model_.images.size(), -2);
  readAssetExtras();
  // Required extensions were checked before parsing (checkReferences); the others are named once each.
  for (const std::string& name : model_.extensionsUsed)
    if (!isSupportedExtension(name))
      warn("extensionsUsed", "'" + name + "' is not supported; " + unsupportedExtensionEffect(name));

  // Roots: the default scene's nodes; without scenes, every node that is nobody's child.
  std::vector<int> roots;
  if (!model_.scenes.empty()) {
    int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    if (static_cast<std::size_t>(s) >= model_.scenes.size())
      fail("scene",
           "scene " + std::to_string(s) + " out of range (" + std::to_string(model_.scenes.size()) + " scenes)");
    const tinygltf::Scene& gscene = model_.scenes[static_cast<std::size_t>(s)];
    roots = gscene.nodes;
    if (auto ext = gscene.extensions.find(kMediaExtension); ext != gscene.extensions.end()) {
      std::string at = "scenes[" + std::to_string(s) + "].extensions." + kMediaExtension;
      Medium m = readMediumExtension(ext->second, true, glm::mat4(1.0f), file_, baseDir(), at);
      m.name = "scene";
      scene_.media.push_back(m);
      mediumPaths_.push_back(at);
    }
    for (std::size_t i = 0; i < roots.size(); ++i)
      if (roots[i] < 0 || static_cast<std::size_t>(roots[i]) >= model_.nodes.size())
        fail("scenes[" + std::to_string(s) + "].nodes[" + std::to_string(i) + "]",
             "node " + std::to_string(roots[i]) + " out of range (" + std::to_string(model_.nodes.size()) + " nodes)");
  } else {
    std::vector<bool> isChild(model_.nodes.size(), false);
    for (const tinygltf::Node& n : model_.nodes)
      for (int c : n.children)
        if (c >= 0 && static_cast<std::size_t>(c) < isChild.size()) isChild[static_cast<std::size_t>(c)] = true;
    for (std::size_t i = 0; i < model_.nodes.size(); ++i)
      if (!isChild[i]) roots.push_back(static_cast<int>(i));
  }

  // Depth-first in document order with an explicit stack, so deep hierarchies cannot overflow the call stack; a
  // node reached twice means a cycle or a shared child, both invalid glTF (3.5.2).
  std::vector<bool> visited(model_.nodes.size(), false);
  std::vector<std::pair<int, glm::mat4>> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, glm::mat4(1.0f));
  while (!stack.empty()) {
    auto [nodeIndex, parent] = stack.back();
    stack.pop_back();
    std::string at = "nodes[" + std::to_string(nodeIndex) + "]";
    if (visited[static_cast<std::size_t>(nodeIndex)]) fail(at, "reached twice (cycle or shared node in the hierarchy)");
    visited[static_cast<std::size_t>(nodeIndex)] = true;
    glm::mat4 world = parent * localTransform(nodeIndex);
    visitNode(nodeIndex, world);
    const std::vector<int>& children = model_.nodes[static_cast<std::size_t>(nodeIndex)].children;
    for (std::size_t k = children.size(); k-- > 0;) {
      int c = children[k];
      if (c < 0 || static_cast<std::size_t>(c) >= model_.nodes.size())
        fail(at + ".children[" + std::to_string(k) + "]",
             "node " + std::to_string(c) + " out of range (" + std::to_string(model_.nodes.size()) + " nodes)");
      stack.emplace_back(c, world);
    }
  }

  if (scene_.triangles.empty()) fail("meshes", "no triangles to render");
  checkMediaDisjoint(scene_.media, mediumPaths_, file_);
  scene_.finalize();
  if (!haveCamera_) frameBounds();
  if (!scene_.hasLights()) scene_.warnings.push_back(kNoLightsWarning);
}

void Loader::visitNode(int nodeIndex, const glm::mat4& world) {
  const tinygltf::Node& node = model_.nodes[static_cast<std::size_t>(nodeIndex)];
  std::string at = "nodes[" + std::to_string(nodeIndex) + "]";
  if (node.mesh >= 0) {
    if (static_cast<std::size_t>(node.mesh) >= model_.meshes.size())
      fail(at + ".mesh",
           "mesh " + std::to_string(node.mesh) + " out of range (" + std::to_string(model_.meshes.size()) + " meshes)");
    const tinygltf::Mesh& mesh = model_.meshes[static_cast<std::size_t>(node.mesh)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) addPrimitive(node.mesh, static_cast<int>(p), world);
  }
  if (node.camera >= 0) {
    if (static_cast<std::size_t>(node.camera) >= model_.cameras.size())
      fail(at + ".camera", "camera " + std::to_string(node.camera) + " out of range (" +
                               std::to_string(model_.cameras.size()) + " cameras)");
    addCamera(nodeIndex, world);
  }
  auto ext = node.extensions.find("KHR_lights_punctual");
  if (ext != node.extensions.end()) addLight(nodeIndex, world);
  if (node.extensions.count(kMediaExtension) != 0) {
    // The box is the node's own [-1, 1]^3; a mesh on the same node would suggest the mesh is the boundary, which it
    // is not (surfaces are not interfaces).
    if (node.mesh >= 0)
      fail(at + ".extensions." + kMediaExtension,
           "the extension belongs on a node without a mesh (its box is the node's [-1, 1]^3, not the mesh)");
    addMediumBox(nodeIndex, world);
  }
}

void Loader::addPrimitive(int meshIndex, int primitiveIndex, const glm::mat4& world) {
  const tinygltf::Primitive& prim =
      model_.meshes[static_cast<std::size_t>(meshIndex)].primitives[static_cast<std::size_t>(primitiveIndex)];
  std::string at = "meshes[" + std::to_string(meshIndex) + "].primitives[" + std::to_string(primitiveIndex) + "]";
  int mode = prim.mode < 0 ? kModeTriangles : prim.mode;
  if (mode < kModeTriangles || mode > kModeTriangleFan) {
    static const char* names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
    std::string name = mode >= kModePoints && mode < kModeTriangles ? names[mode] : std::to_string(mode);
    warn(at, "mode " + name + " is not triangles; primitive skipped");
    return;
  }

  auto attribute = [&](const char* name) {
    auto it = prim.attributes.find(name);
    return it == prim.attributes.end() ? -1 : it->second;
  };
  int posAccessor = attribute("POSITION");
  if (posAccessor < 0) fail(at + ".attributes", "no POSITION");
  std::vector<glm::vec3> positions = readVec3(posAccessor, at + ".attributes.POSITION");
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!finite(positions[i])) fail(at + ".attributes.POSITION", "element " + std::to_string(i) + " is not finite");
  const std::size_t vertexCount = positions.size();

  std::vector<glm::vec3> normals;
  if (int a = attribute("NORMAL"); a >= 0) {
    normals = readVec3(a, at + ".attributes.NORMAL");
    if (normals.size() != vertexCount)
      fail(at + ".attributes.NORMAL",
           std::to_string(normals.size()) + " elements, POSITION has " + std::to_string(vertexCount));
  }
  std::vector<glm::vec2> uvs;
  if (int a = attribute("TEXCOORD_0"); a >= 0) {
    uvs = readUv(a, at + ".attributes.TEXCOORD_0");
    if (uvs.size() != vertexCount)
      fail(at + ".attributes.TEXCOORD_0",
           std::to_string(uvs.size()) + " elements, POSITION has " + std::to_string(vertexCount));
  }

  std::vector<uint32_t> indices;
  if (prim.indices >= 0) {
    indices = readIndices(prim.indices, at + ".indices");
    for (std::size_t i = 0; i < indices.size(); ++i)
      if (indices[i] >= vertexCount)
        fail(at + ".indices", "index " + std::to_string(indices[i]) + " at element " + std::to_string(i) +
                                  " out of range (" + std::to_string(vertexCount) + " vertices)");
  } else {
    indices.resize(vertexCount);
    for (std::size_t i = 0; i < vertexCount; ++i) indices[i] = static_cast<uint32_t>(i);
  }

  // Strips and fans become lists, keeping every triangle's orientation consistent with the first (glTF 3.7.2.1).
  std::vector<glm::uvec3> tris;
  if (mode == kModeTriangles) {
    if (indices.size() % 3 != 0)
      warn(at, std::to_string(indices.size() % 3) + " trailing indices ignored (count not a multiple of 3)");
    for (std::size_t i = 0; i + 2 < indices.size(); i += 3)
      tris.emplace_back(indices[i], indices[i + 1], indices[i + 2]);
  } else if (mode == kModeTriangleStrip) {
    for (std::size_t i = 0; i + 2 < indices.size(); ++i)
      tris.push_back(i % 2 == 0 ? glm::uvec3(indices[i], indices[i + 1], indices[i + 2])
                                : glm::uvec3(indices[i + 1], indices[i], indices[i + 2]));
  } else {
    for (std::size_t i = 1; i + 1 < indices.size(); ++i) tris.emplace_back(indices[i], indices[i + 1], indices[0]);
  }

  uint32_t material = materialIndex(prim.material, at + ".material");
  // TEXCOORD_0 feeds only the base colour texture, so its KHR_texture_transform is applied to the coordinates here
  // (an affine map commutes with interpolation across the triangle).
  if (prim.material >= 0 && uvTransforms_[static_cast<std::size_t>(prim.material)] != glm::mat3(1.0f))
    for (glm::vec2& uv : uvs) uv = glm::vec2(uvTransforms_[static_cast<std::size_t>(prim.material)] * glm::vec3(uv, 1.0f));

  // Positions move with the world matrix, normals with its inverse transpose; a mirroring transform (negative
  // determinant) turns counter-clockwise faces clockwise, so winding is flipped back.
  glm::mat3 linear(world);
  glm::mat3 normalMatrix = glm::transpose(glm::inverse(linear));
  bool mirrored = glm::determinant(linear) < 0.0f;
  std::vector<glm::vec3> worldPos(vertexCount);
  for (std::size_t i = 0; i < vertexCount; ++i) {
    worldPos[i] = glm::vec3(world * glm::vec4(positions[i], 1.0f));
    if (!withinCoordinateBound(worldPos[i]))
      fail(at + ".attributes.POSITION", "element " + std::to_string(i) + " lies beyond +-" +
                                            numberText(kMaxCoordinate) + " m (or is not finite) in world space");
  }
  bool haveNormals = !normals.empty();
  std::vector<glm::vec3> worldNormal(haveNormals ? vertexCount : 0);
  for (std::size_t i = 0; haveNormals && i < vertexCount; ++i) {
    glm::vec3 n = normalMatrix * normals[i];
    float len = glm::length(n);
    if (!(len > 0.0f) || !std::isfinite(len)) {
      warn(at + ".attributes.NORMAL", "element " + std::to_string(i) + " is zero or not finite; face normals used");
      haveNormals = false;
      break;
    }
    worldNormal[i] = n / len;
  }

  const uint32_t base = static_cast<uint32_t>(scene_.positions.size());
  if (haveNormals) {
    scene_.positions.insert(scene_.positions.end(), worldPos.begin(), worldPos.end());
    scene_.normals.insert(scene_.normals.end(), worldNormal.begin(), worldNormal.end());
    if (uvs.empty())
      scene_.uvs.resize(scene_.positions.size(), glm::vec2(0.0f));
    else
      scene_.uvs.insert(scene_.uvs.end(), uvs.begin(), uvs.end());
  }
  for (glm::uvec3 t : tris) {
    const glm::vec3 &p0 = worldPos[t.x], &p1 = worldPos[t.y], &p2 = worldPos[t.z];
    glm::vec3 e1 = p1 - p0, e2 = p2 - p0;
    glm::vec3 n = glm::cross(e1, e2);
    float len = glm::length(n);
    // Zero area, or so thin that its normal is numerically meaningless: no renderer can use it.
    if (!(len > 1e-7f * glm::length(e1) * glm::length(e2)) || !(len > 0.0f)) {
      ++scene_.degenerateTrianglesDropped;
      continue;
    }
    if (mirrored) {
      std::swap(t.y, t.z);
      n = -n;
    }
    if (haveNormals) {
      // Scene::geometricNormal() must lie on the shading normals' side: swap two corners when it does not.
      glm::vec3 summed = worldNormal[t.x] + worldNormal[t.y] + worldNormal[t.z];
      if (glm::dot(n, summed) < 0.0f) std::swap(t.y, t.z);
      scene_.triangles.emplace_back(base + t.x, base + t.y, base + t.z);
    } else {
      // Flat shading: three vertices of its own per triangle carrying the face normal.
      uint32_t first = static_cast<uint32_t>(scene_.positions.size());
      glm::vec3 fn = n / len;
      for (uint32_t corner : {t.x, t.y, t.z}) {
        scene_.positions.push_back(worldPos[corner]);
        scene_.normals.push_back(fn);
        scene_.uvs.push_back(uvs.empty() ? glm::vec2(0.0f) : uvs[corner]);
      }
      scene_.triangles.emplace_back(first, first + 1, first + 2);
    }
    scene_.triangleMaterials.push_back(material);
  }
}

uint32_t Loader::materialIndex(int gltfMaterial, const std::string& where) {
  if (gltfMaterial < 0) {
    if (defaultMaterial_ < 0) {
      Material m;
      m.name = "default";
      defaultMaterial_ = static_cast<int>(scene_.materials.size());
      scene_.materials.push_back(m);
    }
    return static_cast<uint32_t>(defaultMaterial_);
  }
  if (static_cast<std::size_t>(gltfMaterial) >= model_.materials.size())
    fail(where, "material " + std::to_string(gltfMaterial) + " out of range (" +
                    std::to_string(model_.materials.size()) + " materials)");
  int& mapped = materialMap_[static_cast<std::size_t>(gltfMaterial)];
  if (mapped >= 0) return static_cast<uint32_t>(mapped);

  const tinygltf::Material& g = model_.materials[static_cast<std::size_t>(gltfMaterial)];
  std::string at = "materials[" + std::to_string(gltfMaterial) + "]";
  auto num = [&](const std::vector<double>& v, std::size_t n, const std::string& field) {
    if (v.size() < n) fail(at + "." + field, "needs " + std::to_string(n) + " numbers");
    for (std::size_t i = 0; i < n; ++i)
      if (!std::isfinite(v[i])) fail(at + "." + field, "is not finite");
  };
  Material m;
  m.name = g.name.empty() ? "material" + std::to_string(gltfMaterial) : g.name;
  const auto& pbr = g.pbrMetallicRoughness;
  num(pbr.baseColorFactor, 3, "pbrMetallicRoughness.baseColorFactor");
  m.baseColor =
      glm::clamp(glm::vec3(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2]), 0.0f, 1.0f);
  if (!std::isfinite(pbr.metallicFactor) || !std::isfinite(pbr.roughnessFactor))
    fail(at + ".pbrMetallicRoughness", "metallicFactor or roughnessFactor is not finite");
  m.metallic = std::clamp(static_cast<float>(pbr.metallicFactor), 0.0f, 1.0f);
  m.roughness = std::clamp(static_cast<float>(pbr.roughnessFactor), 0.0f, 1.0f);
  if (pbr.baseColorTexture.index >= 0) {
    std::string texAt = at + ".pbrMetallicRoughness.baseColorTexture";
    if (pbr.baseColorTexture.texCoord != 0) warn(texAt, "texCoord other than 0 not supported; TEXCOORD_0 used");
    m.baseColorTexture = textureIndex(pbr.baseColorTexture.index, texAt);
    uvTransforms_[static_cast<std::size_t>(gltfMaterial)] = textureTransform(pbr.baseColorTexture.extensions, texAt);
  }
  if (pbr.metallicRoughnessTexture.index >= 0)
    warn(at + ".pbrMetallicRoughness.metallicRoughnessTexture", "ignored; the factors are used");
  if (g.emissiveTexture.index >= 0) {
    std::string texAt = at + ".emissiveTexture";
    if (g.emissiveTexture.texCoord != 0) warn(texAt, "texCoord other than 0 not supported; TEXCOORD_0 used");
    m.emissiveTexture = textureIndex(g.emissiveTexture.index, texAt);
    // The UVs will carry the base colour's transform (baked at load); the emissive lookup undoes it first.
    const glm::mat3& base = uvTransforms_[static_cast<std::size_t>(gltfMaterial)];
    glm::mat3 own = textureTransform(g.emissiveTexture.extensions, texAt);
    if (std::abs(glm::determinant(base)) > 1e-12f) {
      m.emissiveUvTransform = own * glm::inverse(base);
    } else {
      warn(texAt, "the base colour's KHR_texture_transform is singular; the emissive texture uses its coordinates");
      m.emissiveUvTransform = glm::mat3(1.0f);
    }
  }

  // Emitted radiance = emissiveFactor x KHR_materials_emissive_strength (default 1).
  num(g.emissiveFactor, 3, "emissiveFactor");
  glm::vec3 emissive(g.emissiveFactor[0], g.emissiveFactor[1], g.emissiveFactor[2]);
  float strength = 1.0f;
  auto extNumber = [&](const char* ext, const char* key, float fallback) {
    auto it = g.extensions.find(ext);
    if (it == g.extensions.end() || !it->second.IsObject() || !it->second.Has(key)) return fallback;
    const tinygltf::Value& v = it->second.Get(key);
    if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()) || v.GetNumberAsDouble() < 0.0 ||
        v.GetNumberAsDouble() > kMaxEmission)
      fail(at + ".extensions." + ext + "." + key, "is not a number in [0, " + numberText(kMaxEmission) + "]");
    return static_cast<float>(v.GetNumberAsDouble());
  };
  strength = extNumber("KHR_materials_emissive_strength", "emissiveStrength", 1.0f);
  // The product in double: factor and strength may each fit a float while their product does not.
  for (int c = 0; c < 3; ++c)
    if (std::max(g.emissiveFactor[static_cast<std::size_t>(c)], 0.0) * static_cast<double>(strength) > kMaxEmission)
      fail(at + ".emissiveFactor", "emitted radiance (times emissiveStrength) exceeds " + numberText(kMaxEmission) +
                                       " cd/m^2");
  m.emission = glm::max(emissive, glm::vec3(0.0f)) * strength;
  m.specular = std::clamp(extNumber("KHR_materials_specular", "specularFactor", 1.0f), 0.0f, 1.0f);

  mapped = static_cast<int>(scene_.materials.size());
  scene_.materials.push_back(m);
  return static_cast<uint32_t>(mapped);
}

glm::mat3 Loader::textureTransform(const tinygltf::ExtensionMap& extensions, const std::string& where) {
  auto it = extensions.find("KHR_texture_transform");
  if (it == extensions.end() || !it->second.IsObject()) return glm::mat3(1.0f);
  const tinygltf::Value& ext = it->second;
  std::string at = where + ".extensions.KHR_texture_transform";
  auto number = [&](const tinygltf::Value& v, const std::string& field) {
    if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()) || std::abs(v.GetNumberAsDouble()) > kMaxCoordinate)
      fail(at + "." + field, "is not a finite number within +-" + numberText(kMaxCoordinate));
    return static_cast<float>(v.GetNumberAsDouble());
  };
  auto pair = [&](const char* field, glm::vec2 fallback) {
    if (!ext.Has(field)) return fallback;
    const tinygltf::Value& v = ext.Get(field);
    if (!v.IsArray() || v.ArrayLen() != 2) fail(at + "." + field, "needs 2 numbers");
    return glm::vec2(number(v.Get(0), field), number(v.Get(1), field));
  };
  glm::vec2 offset = pair("offset", glm::vec2(0.0f)), scale = pair("scale", glm::vec2(1.0f));
  float rotation = ext.Has("rotation") ? number(ext.Get("rotation"), "rotation") : 0.0f;
  if (ext.Has("texCoord") && ext.Get("texCoord").IsNumber() && ext.Get("texCoord").GetNumberAsInt() != 0)
    warn(at + ".texCoord", "texCoord other than 0 not supported; TEXCOORD_0 used");
  // uv' = T(offset) R(rotation) S(scale) uv. R turns the UVs counter-clockwise in glTF's v-down texture space:
  // columns (cos, -sin) and (sin, cos). The extension's GLSL listing has the transpose, a known error in it
  // (KhronosGroup/glTF issue 1563); this is what its TextureTransformTest sample and the common viewers show.
  float c = std::cos(rotation), sn = std::sin(rotation);
  glm::mat3 translation(1.0f), rotate(1.0f), scaling(1.0f);
  translation[2] = glm::vec3(offset, 1.0f);
  rotate[0] = glm::vec3(c, -sn, 0.0f);
  rotate[1] = glm::vec3(sn, c, 0.0f);
  scaling[0][0] = scale.x;
  scaling[1][1] = scale.y;
  return translation * rotate * scaling;
}

int Loader::textureIndex(int gltfTexture, const std::string& where) {
  if (static_cast<std::size_t>(gltfTexture) >= model_.textures.size())
    fail(where, "texture " + std::to_string(gltfTexture) + " out of range (" + std::to_string(model_.textures.size()) +
                    " textures)");
  int source = model_.textures[static_cast<std::size_t>(gltfTexture)].source;
  std::string texAt = "textures[" + std::to_string(gltfTexture) + "]";
  if (source < 0) {
    warn(where, texAt + " has no image source; the factor is used alone");
    return -1;
  }
  if (static_cast<std::size_t>(source) >= model_.images.size())
    fail(texAt + ".source",
         "image " + std::to_string(source) + " out of range (" + std::to_string(model_.images.size()) + " images)");
  int& cached = imageTextures_[static_cast<std::size_t>(source)];
  if (cached != -2) return cached;

  const tinygltf::Image& image = model_.images[static_cast<std::size_t>(source)];
  std::string imgAt = "images[" + std::to_string(source) + "]";
  std::string label = image.uri.empty() ? (image.name.empty() ? imgAt : image.name) : image.uri;
  const unsigned char* bytes = nullptr;
  std::size_t size = 0;
  if (image.bufferView >= 0) {
    // Same range checks as for accessors: the bufferView must lie inside its buffer.
    if (static_cast<std::size_t>(image.bufferView) >= model_.bufferViews.size())
      fail(imgAt + ".bufferView", "bufferView " + std::to_string(image.bufferView) + " out of range");
    const tinygltf::BufferView& bv = model_.bufferViews[static_cast<std::size_t>(image.bufferView)];
    if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= model_.buffers.size())
      fail("bufferViews[" + std::to_string(image.bufferView) + "]", "buffer out of range");
    const std::vector<unsigned char>& data = model_.buffers[static_cast<std::size_t>(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
      fail("bufferViews[" + std::to_string(image.bufferView) + "]", "exceeds its buffer");
    bytes = data.data() + bv.byteOffset;
    size = bv.byteLength;
  } else if (static_cast<std::size_t>(source) < images_.bytes.size()) {
    bytes = images_.bytes[static_cast<std::size_t>(source)].data();
    size = images_.bytes[static_cast<std::size_t>(source)].size();
  }
  if (size == 0 || size > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    warn(where, "image '" + label + "' could not be read; the factor is used alone");
    cached = -1;
    return cached;
  }
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load_from_memory(bytes, static_cast<int>(size), &w, &h, &channels, 3);
  if (pixels == nullptr) {
    const char* reason = stbi_failure_reason();
    warn(where, "image '" + label + "' could not be decoded (" + (reason ? reason : "unknown") +
                    "); the factor is used alone");
    cached = -1;
    return cached;
  }
  // Base-colour textures are sRGB-encoded (glTF 3.9.2); shading needs linear values.
  std::array<float, 256> lut;
  for (int i = 0; i < 256; ++i) lut[static_cast<std::size_t>(i)] = srgbToLinear(static_cast<float>(i) / 255.0f);
  Texture tex;
  tex.name = label;
  tex.width = w;
  tex.height = h;
  tex.texels.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  for (std::size_t i = 0; i < tex.texels.size(); ++i)
    tex.texels[i] = {lut[pixels[3 * i]], lut[pixels[3 * i + 1]], lut[pixels[3 * i + 2]]};
  stbi_image_free(pixels);
  cached = static_cast<int>(scene_.textures.size());
  scene_.textures.push_back(std::move(tex));
  return cached;
}

void Loader::addLight(int nodeIndex, const glm::mat4& world) {
  const tinygltf::Value& ext = model_.nodes[static_cast<std::size_t>(nodeIndex)].extensions.at("KHR_lights_punctual");
  std::string at = "nodes[" + std::to_string(nodeIndex) + "].extensions.KHR_lights_punctual";
  if (!ext.IsObject() || !ext.Has("light") || !ext.Get("light").IsNumber()) fail(at, "no light index");
  int index = ext.Get("light").GetNumberAsInt();
  if (index < 0 || static_cast<std::size_t>(index) >= model_.lights.size())
    fail(at + ".light",
         "light " + std::to_string(index) + " out of range (" + std::to_string(model_.lights.size()) + " lights)");
  const tinygltf::Light& g = model_.lights[static_cast<std::size_t>(index)];
  std::string lightAt = "extensions.KHR_lights_punctual.lights[" + std::to_string(index) + "]";
  PunctualLight l;
  l.name = g.name.empty() ? "light" + std::to_string(index) : g.name;
  if (g.type == "point") {
    l.type = PunctualLight::Type::Point;
  } else if (g.type == "spot") {
    l.type = PunctualLight::Type::Spot;
    l.innerConeAngle = static_cast<float>(g.spot.innerConeAngle);
    l.outerConeAngle = static_cast<float>(g.spot.outerConeAngle);
    if (!(l.innerConeAngle >= 0.0f && l.innerConeAngle < l.outerConeAngle && l.outerConeAngle <= 0.5f * kPi))
      fail(lightAt + ".spot", "needs 0 <= innerConeAngle < outerConeAngle <= pi/2");
  } else if (g.type == "directional") {
    l.type = PunctualLight::Type::Directional;
  } else {
    warn(lightAt, "type '" + g.type + "' not supported; light skipped");
    return;
  }
  glm::vec3 color(1.0f);
  if (!g.color.empty()) {
    if (g.color.size() != 3 || !std::all_of(g.color.begin(), g.color.end(), [](double c) { return std::isfinite(c) && std::abs(c) <= kMaxEmission; }))
      fail(lightAt + ".color", "needs 3 finite numbers");
    color = glm::vec3(g.color[0], g.color[1], g.color[2]);
  }
  for (int c = 0; c < 3; ++c) {
    double v = static_cast<double>(color[c]) * g.intensity;
    if (!std::isfinite(v) || v < 0.0 || v > kMaxEmission)
      fail(lightAt, "intensity x color must lie in [0, " + numberText(kMaxEmission) + "]");
  }
  l.intensity = color * static_cast<float>(g.intensity);
  // Punctual lights sit at their node's origin and shine down its local -Z (KHR_lights_punctual); a directional
  // light keeps only the direction (its node's translation does not matter).
  l.position = l.isDirectional() ? glm::vec3(0.0f) : glm::vec3(world * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
  glm::vec3 dir = glm::mat3(world) * glm::vec3(0.0f, 0.0f, -1.0f);
  if (!withinCoordinateBound(l.position) || !finite(dir) || !(glm::length(dir) > 0.0f))
    fail("nodes[" + std::to_string(nodeIndex) + "]", "degenerate transform for a light (or beyond +-" +
                                                         numberText(kMaxCoordinate) + " m)");
  l.direction = glm::normalize(dir);
  scene_.punctualLights.push_back(l);
}

void Loader::addCamera(int nodeIndex, const glm::mat4& world) {
  const tinygltf::Camera& g =
      model_.cameras[static_cast<std::size_t>(model_.nodes[static_cast<std::size_t>(nodeIndex)].camera)];
  if (haveCamera_) return;
  if (g.type != "perspective") {
    warn("nodes[" + std::to_string(nodeIndex) + "].camera", "'" + g.type + "' camera ignored (perspective only)");
    return;
  }
  std::string at = "cameras[" + std::to_string(model_.nodes[static_cast<std::size_t>(nodeIndex)].camera) + "]";
  // glTF cameras look down their local -Z with +Y up.
  glm::mat3 r(world);
  glm::vec3 forward = r * glm::vec3(0.0f, 0.0f, -1.0f);
  glm::vec3 up = r * glm::vec3(0.0f, 1.0f, 0.0f);
  if (!(glm::length(forward) > 0.0f) || !(glm::length(glm::cross(forward, up)) > 0.0f))
    fail("nodes[" + std::to_string(nodeIndex) + "]", "degenerate transform for a camera");
  Camera c;
  c.position = glm::vec3(world * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
  if (!withinCoordinateBound(c.position) || !finite(forward) || !finite(up))
    fail("nodes[" + std::to_string(nodeIndex) + "]",
         "camera beyond +-" + numberText(kMaxCoordinate) + " m or with a non-finite transform");
  c.forward = glm::normalize(forward);
  c.up = glm::normalize(up - glm::dot(up, c.forward) * c.forward);
  c.yfov = static_cast<float>(g.perspective.yfov);
  if (!(c.yfov > 0.0f && c.yfov < kPi)) fail(at + ".perspective.yfov", "must lie in (0, pi)");
  // Clip planes that do not fit the coordinate bound are left at their defaults.
  if (g.perspective.znear > 0.0 && g.perspective.znear < kMaxCoordinate)
    c.znear = static_cast<float>(g.perspective.znear);
  if (g.perspective.zfar > g.perspective.znear && g.perspective.zfar < 2.0 * kMaxCoordinate)
    c.zfar = static_cast<float>(g.perspective.zfar);
  c.fromFile = true;
  scene_.camera = c;
  haveCamera_ = true;
}

void Loader::addMediumBox(int nodeIndex, const glm::mat4& world) {
  const tinygltf::Node& node = model_.nodes[static_cast<std::size_t>(nodeIndex)];
  const std::string at = "nodes[" + std::to_string(nodeIndex) + "].extensions." + kMediaExtension;
  Medium m = readMediumExtension(node.extensions.at(kMediaExtension), false, world, file_, baseDir(), at);
  m.name = node.name.empty() ? "nodes[" + std::to_string(nodeIndex) + "]" : node.name;
  scene_.media.push_back(m);
  mediumPaths_.push_back(at);
}

void Loader::frameBounds() {
  // Look down -Z at the bounding sphere from far enough that it fits the vertical field of view.
  Camera c;
  // The geometry only: lights outside the model must not shrink it into a corner of the image.
  float radius = std::max(0.5f * scene_.geometryBounds.diagonal(), 1e-3f);
  float distance = radius / std::sin(0.5f * c.yfov);
  c.position = scene_.geometryBounds.center() + glm::vec3(0.0f, 0.0f, distance);
  c.znear = std::max(1e-4f, 0.01f * (distance - radius));
  c.zfar = 2.0f * (distance + radius);
  c.fromFile = false;
  scene_.camera = c;
}

void Loader::readAssetExtras() {
  const tinygltf::Value& extras = model_.asset.extras;
  if (!extras.IsObject()) return;
  for (const std::string& key : extras.Keys()) {
    const tinygltf::Value& v = extras.Get(key);
    if (v.IsNumber()) scene_.assetExtras[key] = v.GetNumberAsDouble();
  }
}

/// tinygltf replaces a value of the wrong type by the default without a word (baseColorFactor "red" becomes white, a
/// matrix holding "NaN" is ignored, extensionsRequired as a string is skipped) and the loader used to clamp
/// out-of-range factors silently. The glTF schema's types and ranges are checked here on the raw JSON, naming the glTF
/// path; the loader checks finiteness and its own bounds after.
void checkValues(const std::string& file, const nlohmann::json& doc) {
  auto fail = [&](const std::string& at, const std::string& what) { throw SceneError(file + ": " + at + ": " + what); };
  auto describe = [](const nlohmann::json& v) -> std::string {
    if (v.is_string()) return "a string";
    if (v.is_object()) return "an object";
    if (v.is_array()) return "an array of " + std::to_string(v.size());
    if (v.is_boolean()) return "a boolean";
    if (v.is_null()) return "null";
    return "the number " + v.dump();
  };
  // An array of n numbers in [lo, hi] (n = 0: any length).
  auto rangeText = [](double lo, double hi) -> std::string {
    const double big = std::numeric_limits<double>::max();
    return hi >= big ? (lo <= -big ? "" : " >= " + numberText(lo)) : " in [" + numberText(lo) + ", " + numberText(hi) + "]";
  };
  auto numbers = [&](const nlohmann::json& v, const std::string& at, std::size_t n, double lo, double hi) {
    std::string range = rangeText(lo, hi);
    std::string expected = "expected " + (n ? std::to_string(n) + " numbers" : std::string("numbers")) + range;
    if (!v.is_array() || (n && v.size() != n)) fail(at, expected + ", got " + describe(v));
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!v[i].is_number() || v[i].get<double>() < lo || v[i].get<double>() > hi)
        fail(at + "[" + std::to_string(i) + "]", expected + ", got " + describe(v[i]));
  };
  auto number = [&](const nlohmann::json& v, const std::string& at, double lo, double hi) {
    if (!v.is_number() || v.get<double>() < lo || v.get<double>() > hi)
      fail(at, "expected a number" + rangeText(lo, hi) + ", got " + describe(v));
  };
  auto arrayAt = [&](const char* key) -> const nlohmann::json* {
    auto it = doc.find(key);
    if (it == doc.end()) return nullptr;
    if (!it->is_array()) fail(key, "expected an array, got " + describe(*it));
    return &*it;
  };
  for (const char* key : {"extensionsUsed", "extensionsRequired"})
    if (const nlohmann::json* list = arrayAt(key))
      for (std::size_t i = 0; i < list->size(); ++i)
        if (!(*list)[i].is_string())
          fail(std::string(key) + "[" + std::to_string(i) + "]",
               "expected an extension name, got " + describe((*list)[i]));
  if (const nlohmann::json* nodes = arrayAt("nodes"))
    for (std::size_t n = 0; n < nodes->size(); ++n) {
      const nlohmann::json& node = (*nodes)[n];
      const std::string at = "nodes[" + std::to_string(n) + "]";
      if (!node.is_object()) fail(at, "expected an object, got " + describe(node));
      const double big = std::numeric_limits<double>::max();
      if (node.contains("matrix")) numbers(node["matrix"], at + ".matrix", 16, -big, big);
      if (node.contains("translation")) numbers(node["translation"], at + ".translation", 3, -big, big);
      if (node.contains("rotation")) numbers(node["rotation"], at + ".rotation", 4, -1.0, 1.0);
      if (node.contains("scale")) numbers(node["scale"], at + ".scale", 3, -big, big);
    }
  if (const nlohmann::json* materials = arrayAt("materials"))
    for (std::size_t m = 0; m < materials->size(); ++m) {
      const nlohmann::json& material = (*materials)[m];
      const std::string at = "materials[" + std::to_string(m) + "]";
      if (!material.is_object()) fail(at, "expected an object, got " + describe(material));
      if (auto pbr = material.find("pbrMetallicRoughness"); pbr != material.end()) {
        if (!pbr->is_object()) fail(at + ".pbrMetallicRoughness", "expected an object, got " + describe(*pbr));
        if (pbr->contains("baseColorFactor"))
          numbers((*pbr)["baseColorFactor"], at + ".pbrMetallicRoughness.baseColorFactor", 4, 0.0, 1.0);
        for (const char* factor : {"metallicFactor", "roughnessFactor"})
          if (pbr->contains(factor)) number((*pbr)[factor], at + ".pbrMetallicRoughness." + factor, 0.0, 1.0);
      }
      // The schema bounds emissiveFactor by 1; vplab takes larger factors (radiance in cd/m^2, bounded by the loader),
      // but a negative one would make an emitter count as dark.
      if (material.contains("emissiveFactor"))
        numbers(material["emissiveFactor"], at + ".emissiveFactor", 3, 0.0, std::numeric_limits<double>::max());
      if (auto ext = material.find("extensions"); ext != material.end() && ext->is_object())
        if (auto spec = ext->find("KHR_materials_specular");
            spec != ext->end() && spec->is_object() && spec->contains("specularFactor"))
          number((*spec)["specularFactor"], at + ".extensions.KHR_materials_specular.specularFactor", 0.0, 1.0);
    }
  if (auto ext = doc.find("extensions"); ext != doc.end() && ext->is_object())
    if (auto punctual = ext->find("KHR_lights_punctual"); punctual != ext->end() && punctual->is_object())
      if (auto lights = punctual->find("lights"); lights != punctual->end()) {
        const std::string listAt = "extensions.KHR_lights_punctual.lights";
        if (!lights->is_array()) fail(listAt, "expected an array, got " + describe(*lights));
        const double big = std::numeric_limits<double>::max();
        for (std::size_t i = 0; i < lights->size(); ++i) {
          const nlohmann::json& light = (*lights)[i];
          const std::string at = listAt + "[" + std::to_string(i) + "]";
          if (!light.is_object()) fail(at, "expected an object, got " + describe(light));
          if (!light.contains("type") || !light["type"].is_string())
            fail(at + ".type", "expected \"point\", \"spot\" or \"directional\"");
          if (light.contains("color")) numbers(light["color"], at + ".color", 3, 0.0, big);
          if (light.contains("intensity")) number(light["intensity"], at + ".intensity", 0.0, big);
          if (light.contains("spot")) {
            const nlohmann::json& spot = light["spot"];
            if (!spot.is_object()) fail(at + ".spot", "expected an object, got " + describe(spot));
            for (const char* angle : {"innerConeAngle", "outerConeAngle"})
              if (spot.contains(angle)) number(spot[angle], at + ".spot." + angle, 0.0, 0.5 * kPi);
          }
        }
      }
  // Properties tinygltf requires but reports without saying which element ("'count' property is missing in
  // Accessor").
  const std::vector<std::pair<const char*, std::vector<const char*>>> required = {
      {"accessors", {"componentType", "count", "type"}},
      {"bufferViews", {"buffer", "byteLength"}},
      {"buffers", {"byteLength"}},
      {"meshes", {"primitives"}}};
  for (const auto& [kind, keys] : required)
    if (const nlohmann::json* list = arrayAt(kind))
      for (std::size_t i = 0; i < list->size(); ++i) {
        const std::string at = std::string(kind) + "[" + std::to_string(i) + "]";
        if (!(*list)[i].is_object()) fail(at, "expected an object, got " + describe((*list)[i]));
        for (const char* key : keys)
          if (!(*list)[i].contains(key)) fail(at, std::string("the required property '") + key + "' is missing");
      }
}

/// tinygltf rejects some broken references itself, with messages that do not say where ("primitive indices accessor
/// out of bounds"). Checking the references first gives the glTF path instead. JSON that does not parse is reported
/// here too, in the project's words.
void checkReferences(const std::string& file, const std::string& baseDir, const char* json, std::size_t size) {
  if (jsonDepth(json, size) > kMaxJsonDepth)
    throw SceneError(file + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(json, json + size);
  } catch (const nlohmann::json::exception& e) {
    // tinygltf would quote the JSON library's exception id ("[json.exception.parse_error.101]").
    std::string why = describeJsonError(std::string_view(json, size), e);
    if (why.rfind("not valid JSON: ", 0) == 0) why = "invalid JSON " + why.substr(16);
    throw SceneError(file + ": not a valid glTF file: " + why);
  }
  if (!doc.is_object()) throw SceneError(file + ": not a valid glTF file: expected a JSON object");
  checkValues(file, doc);
  auto count = [&](const char* key) {
    auto it = doc.find(key);
    return it != doc.end() && it->is_array() ? it->size() : std::size_t{0};
  };
  auto check = [&](const nlohmann::json& value, std::size_t n, const std::string& where, const char* what) {
    if (!value.is_number_integer()) return;
    long long i = value.get<long long>();
    if (i < 0 || static_cast<std::size_t>(i) >= n)
      throw SceneError(file + ": " + where + ": " + what + " " + std::to_string(i) + " out of range (" +
                       std::to_string(n) + " " + what + "s)");
  };
  if (auto it = doc.find("extensionsRequired"); it != doc.end() && it->is_array())
    for (std::size_t i = 0; i < it->size(); ++i) {
      if (!(*it)[i].is_string()) continue;
      std::string name = (*it)[i].get<std::string>();
      if (isSupportedExtension(name)) continue;
      bool compressed = name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression";
      throw SceneError(file + ": extensionsRequired[" + std::to_string(i) + "]: '" + name + "' is not supported" +
                       (compressed ? "; decompress the file first (e.g. with gltf-transform or gltfpack)"
                                   : "; the file cannot be shown correctly without it"));
    }
  // A URI naming a directory or something unreadable: say so, instead of what reading it would throw.
  for (const char* kind : {"buffers", "images"}) {
    auto list = doc.find(kind);
    if (list == doc.end() || !list->is_array()) continue;
    for (std::size_t i = 0; i < list->size(); ++i) {
      const nlohmann::json& entry = (*list)[i];
      if (!entry.is_object() || !entry.contains("uri") || !entry["uri"].is_string()) continue;
      std::string uri = entry["uri"].get<std::string>();
      if (uri.rfind("data:", 0) == 0 || uri.find('%') != std::string::npos || uri.find(':') != std::string::npos)
        continue;
      std::error_code ec;
      std::filesystem::path target = std::filesystem::path(baseDir) / uri;
      std::string at = file + ": " + kind + "[" + std::to_string(i) + "].uri";
      if (std::filesystem::is_directory(target, ec)) throw SceneError(at + ": '" + uri + "' is a directory");
      if (std::filesystem::exists(target, ec) && !std::filesystem::is_regular_file(target, ec))
        throw SceneError(at + ": '" + uri + "' is not a regular file");
    }
  }
  // tinygltf drops extension values that are not objects without a word; a medium given as a number or an array
  // must not vanish silently.
  for (const char* kind : {"nodes", "scenes"}) {
    auto list = doc.find(kind);
    if (list == doc.end() || !list->is_array()) continue;
    for (std::size_t i = 0; i < list->size(); ++i) {
      const nlohmann::json& entry = (*list)[i];
      if (!entry.is_object() || !entry.contains("extensions") || !entry["extensions"].is_object()) continue;
      auto ext = entry["extensions"].find(kMediaExtension);
      if (ext != entry["extensions"].end() && !ext->is_object())
        throw SceneError(file + ": " + kind + "[" + std::to_string(i) + "].extensions." + kMediaExtension +
                         ": must be an object with sigmaA, sigmaS and optionally g and density");
    }
  }
  const std::size_t accessors = count("accessors"), views = count("bufferViews"), buffers = count("buffers");
  if (doc.contains("meshes") && doc["meshes"].is_array())
    for (std::size_t m = 0; m < doc["meshes"].size(); ++m) {
      const nlohmann::json& mesh = doc["meshes"][m];
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      for (std::size_t p = 0; p < mesh["primitives"].size(); ++p) {
        const nlohmann::json& prim = mesh["primitives"][p];
        if (!prim.is_object()) continue;
        std::string at = "meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "]";
        if (prim.contains("indices")) check(prim["indices"], accessors, at + ".indices", "accessor");
        if (prim.contains("attributes") && prim["attributes"].is_object())
          for (const auto& [name, value] : prim["attributes"].items())
            check(value, accessors, at + ".attributes." + name, "accessor");
      }
    }
  if (doc.contains("accessors") && doc["accessors"].is_array())
    for (std::size_t a = 0; a < accessors; ++a)
      if (doc["accessors"][a].is_object() && doc["accessors"][a].contains("bufferView"))
        check(doc["accessors"][a]["bufferView"], views, "accessors[" + std::to_string(a) + "].bufferView",
              "bufferView");
  // Buffers shorter than their byteLength: name the buffer rather than quoting tinygltf's data-URI dump.
  for (std::size_t b = 0; b < buffers; ++b) {
    const nlohmann::json& buffer = doc["buffers"][b];
    if (!buffer.is_object() || !buffer.contains("uri") || !buffer["uri"].is_string() ||
        !buffer.contains("byteLength") || !buffer["byteLength"].is_number_unsigned())
      continue;
    std::string uri = buffer["uri"].get<std::string>();
    auto declared = buffer["byteLength"].get<uint64_t>();
    std::string at = file + ": buffers[" + std::to_string(b) + "]";
    uint64_t actual = 0;
    if (uri.rfind("data:", 0) == 0) {
      std::size_t comma = uri.find(',');
      if (comma == std::string::npos) throw SceneError(at + ".uri: data URI without ','");
      std::size_t chars = uri.size() - comma - 1, padding = 0;
      for (std::size_t i = uri.size(); i > comma + 1 && uri[i - 1] == '=' && padding < 2; --i) ++padding;
      actual = chars * 3 / 4 - std::min<uint64_t>(padding, chars * 3 / 4);
      if (actual < declared)
        throw SceneError(at + ": data URI holds " + std::to_string(actual) + " bytes, byteLength says " +
                         std::to_string(declared));
    } else if (uri.find('%') == std::string::npos && uri.find(':') == std::string::npos) {
      try {
        actual = requireInputFile(baseDir + "/" + uri, kMaxReferencedBytes, "a glTF buffer");
      } catch (const FileReadError& e) {
        throw SceneError(at + ".uri: " + e.what());
      }
      if (actual < declared)
        throw SceneError(at + ": '" + uri + "' has " + std::to_string(actual) + " bytes, byteLength says " +
                         std::to_string(declared));
    }
  }
  if (doc.contains("bufferViews") && doc["bufferViews"].is_array())
    for (std::size_t v = 0; v < views; ++v)
      if (doc["bufferViews"][v].is_object() && doc["bufferViews"][v].contains("buffer"))
        check(doc["bufferViews"][v]["buffer"], buffers, "bufferViews[" + std::to_string(v) + "].buffer", "buffer");
}

/// tinygltf's file reader for referenced buffers and images, through readInputFile().
bool readReferencedFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  try {
    std::string bytes = readInputFile(path, kMaxReferencedBytes, "a glTF buffer or image");
    out->assign(bytes.begin(), bytes.end());
    return true;
  } catch (const FileReadError& e) {
    if (err) *err += std::string(e.what()) + "\n";
    return false;
  }
}

}  // namespace

bool withinCoordinateBound(const glm::vec3& v) {
  return finite(v) && std::abs(v.x) <= kMaxCoordinate && std::abs(v.y) <= kMaxCoordinate &&
         std::abs(v.z) <= kMaxCoordinate;
}

Scene loadScene(const std::string& path) {
  std::vector<unsigned char> bytes;
  try {
    // tinygltf takes the length as 32 bits.
    std::string text = readInputFile(path, std::numeric_limits<uint32_t>::max(), "a glTF scene");
    bytes.assign(text.begin(), text.end());
  } catch (const FileReadError& e) {
    throw SceneError(e.what());
  }

  bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (!binary && endsWith(path, ".glb")) throw SceneError(path + ": not a binary glTF file (no 'glTF' magic)");
  if (binary) {
    // The GLB header's total length must match what is on disk (glTF 4.4.2): a short file is truncated.
    if (bytes.size() < 20) throw SceneError(path + ": truncated .glb (" + std::to_string(bytes.size()) + " bytes)");
    uint32_t version = 0;
    std::memcpy(&version, bytes.data() + 4, 4);
    if (version != 2)
      throw SceneError(path + ": .glb container version " + std::to_string(version) + " is not supported (expected 2)");
    uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 8, 4);
    if (length > bytes.size())
      throw SceneError(path + ": truncated .glb (header says " + std::to_string(length) + " bytes, file has " +
                       std::to_string(bytes.size()) + ")");
    uint32_t jsonLength = 0;
    std::memcpy(&jsonLength, bytes.data() + 12, 4);
    if (jsonLength > bytes.size() - 20) throw SceneError(path + ": truncated .glb (JSON chunk exceeds the file)");
    checkReferences(path, directoryOf(path), reinterpret_cast<const char*>(bytes.data()) + 20, jsonLength);
  } else {
    checkReferences(path, directoryOf(path), reinterpret_cast<const char*>(bytes.data()), bytes.size());
  }

  tinygltf::TinyGLTF gltf;
  // Buffers and images the file refers to are read like the scene: regular files only, bounded in size.
  gltf.SetFsCallbacks({&tinygltf::FileExists, &tinygltf::ExpandFilePath, &readReferencedFile, &tinygltf::WriteWholeFile,
                       nullptr});
  CapturedImages images;
  gltf.SetImageLoader(&captureImage, &images);
  tinygltf::Model model;
  std::string err, warn;
  std::string baseDir = directoryOf(path);
  bool ok = false;
  try {
    ok = binary ? gltf.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), static_cast<unsigned int>(bytes.size()),
                                            baseDir)
                : gltf.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                           static_cast<unsigned int>(bytes.size()), baseDir);
  } catch (const std::exception& e) {
    // tinygltf reads referenced files whole; whatever it throws still names this file.
    throw SceneError(path + ": not a valid glTF file: " + firstLine(e.what()));
  }
  if (!ok) throw SceneError(path + ": not a valid glTF file: " + firstLine(err));

  Scene scene;
  scene.sourcePath = path;
  Loader(path, model, images, scene).run();
  return scene;
}

}  // namespace vplab
