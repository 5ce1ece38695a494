#include "renderer/scene/lights_json.h"

#include "renderer/core/atomic_file.h"
#include "renderer/core/text.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/vdb_grid.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>

namespace vplab {
namespace {

using Json = nlohmann::json;

const char* typeName(PunctualLight::Type t) {
  switch (t) {
    case PunctualLight::Type::Point: return "point";
    case PunctualLight::Type::Spot: return "spot";
    case PunctualLight::Type::Directional: return "directional";
  }
  return "?";
}

Json vec(const glm::vec3& v) { return Json::array({v.x, v.y, v.z}); }
Json vec(const glm::vec2& v) { return Json::array({v.x, v.y}); }

/// Reads the file's values with the loader's bounds, naming the key of anything wrong.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw LightsJsonError(file_ + ": " + where + ": " + what);
  }
  float number(const Json& j, const std::string& where, double bound) const {
    if (!j.is_number() || !std::isfinite(j.get<double>()) || std::abs(j.get<double>()) > bound)
      fail(where, "expected a finite number within +-" + std::to_string(bound));
    return static_cast<float>(j.get<double>());
  }
  glm::vec3 vec3(const Json& j, const std::string& where, double bound) const {
    if (!j.is_array() || j.size() != 3) fail(where, "expected 3 numbers");
    return {number(j[0], where, bound), number(j[1], where, bound), number(j[2], where, bound)};
  }
  glm::vec2 vec2(const Json& j, const std::string& where, double bound) const {
    if (!j.is_array() || j.size() != 2) fail(where, "expected 2 numbers");
    return {number(j[0], where, bound), number(j[1], where, bound)};
  }
  const Json& member(const Json& object, const char* key, const std::string& where) const {
    if (!object.is_object() || !object.contains(key)) fail(where, std::string("missing '") + key + "'");
    return object[key];
  }

 private:
  std::string file_;
};

}  // namespace

std::string lightsSidecarPath(const std::string& scenePath) { return scenePath + ".lights.json"; }

std::string lightsToJson(const Scene& scene) {
  Json punctual = Json::array();
  for (const PunctualLight& l : scene.punctualLights) {
    Json j = {{"name", l.name}, {"type", typeName(l.type)}, {"intensity", vec(l.intensity)}};
    if (!l.isDirectional()) j["position"] = vec(l.position);
    if (l.type != PunctualLight::Type::Point) j["direction"] = vec(l.direction);
    if (l.type == PunctualLight::Type::Spot) {
      j["innerConeAngle"] = l.innerConeAngle;
      j["outerConeAngle"] = l.outerConeAngle;
    }
    punctual.push_back(j);
  }
  Json area = Json::array();
  std::vector<int> entryOf(scene.materials.size(), -1);
  for (uint32_t t : scene.emissiveTriangles) {
    uint32_t m = scene.triangleMaterials[t];
    // A textured emitter (emissive or base colour texture) keeps its texture coordinates, one triple per triangle.
    const bool textured = scene.materials[m].emissiveTexture >= 0 || scene.materials[m].baseColorTexture >= 0;
    if (entryOf[m] < 0) {
      entryOf[m] = static_cast<int>(area.size());
      area.push_back({{"material", scene.materials[m].name},
                      {"emission", vec(scene.materials[m].emission)},
                      {"triangles", Json::array()}});
      if (textured) area.back()["uvs"] = Json::array();
    }
    const glm::uvec3& tri = scene.triangles[t];
    Json& entry = area[static_cast<std::size_t>(entryOf[m])];
    entry["triangles"].push_back({vec(scene.positions[tri.x]), vec(scene.positions[tri.y]), vec(scene.positions[tri.z])});
    if (textured) entry["uvs"].push_back({vec(scene.uvs[tri.x]), vec(scene.uvs[tri.y]), vec(scene.uvs[tri.z])});
  }
  Json media = Json::array();
  for (const Medium& m : scene.media) {
    Json j = {{"name", m.name}, {"sigmaA", vec(m.sigmaA)}, {"sigmaS", vec(m.sigmaS)}, {"g", m.g}};
    // A density grid is named, not copied: the .vdb file stays where the scene (or the editor) found it.
    if (m.density)
      j["density"] = {{"uri", m.densityUri}, {"grid", m.densityGridName}, {"scale", m.densityScale}};
    if (m.fillsSpace) {
      j["fillsSpace"] = true;
    } else {
      // Column-major, as glTF writes a node matrix.
      Json world = Json::array();
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) world.push_back(m.worldFromBox[c][r]);
      j["worldFromBox"] = world;
    }
    media.push_back(j);
  }
  return Json({{"punctualLights", punctual}, {"areaLights", area}, {"media", media}}).dump(2) + "\n";
}

void saveLightsFile(const std::string& path, const Scene& scene) {
  try {
    writeFileAtomically(path, lightsToJson(scene));
  } catch (const FileWriteError& e) {
    throw LightsJsonError(e.what());
  }
}

void applyLightsFile(const std::string& path, Scene& scene) {
  std::string text;
  try {
    // Area lights list their triangles: a big scene's sidecar is tens of megabytes, never gigabytes.
    text = readInputFile(path, 512u << 20, "a lights sidecar");
  } catch (const FileReadError& e) {
    throw LightsJsonError(e.what());
  }
  Json doc;
  try {
    doc = Json::parse(text);
  } catch (const Json::exception& e) {
    throw LightsJsonError(path + ": " + describeJsonError(text, e));
  }
  if (!doc.is_object()) throw LightsJsonError(path + ": not a JSON object (expected {\"punctualLights\": [...], ...})");
  Reader r(path);

  // Everything is read into new values first: the scene changes only when the whole file is valid.
  std::vector<PunctualLight> punctual;
  const Json& list = r.member(doc, "punctualLights", "punctualLights");
  if (!list.is_array()) r.fail("punctualLights", "expected an array");
  for (std::size_t i = 0; i < list.size(); ++i) {
    std::string at = "punctualLights[" + std::to_string(i) + "]";
    const Json& j = list[i];
    PunctualLight l;
    const Json& type = r.member(j, "type", at);
    std::string t = type.is_string() ? type.get<std::string>() : "";
    if (t == "point") l.type = PunctualLight::Type::Point;
    else if (t == "spot") l.type = PunctualLight::Type::Spot;
    else if (t == "directional") l.type = PunctualLight::Type::Directional;
    else r.fail(at + ".type", "expected \"point\", \"spot\" or \"directional\"");
    if (j.contains("name") && j["name"].is_string()) l.name = j["name"].get<std::string>();
    l.intensity = r.vec3(r.member(j, "intensity", at), at + ".intensity", kMaxEmission);
    if (l.intensity.r < 0.0f || l.intensity.g < 0.0f || l.intensity.b < 0.0f) r.fail(at + ".intensity", "negative");
    if (!l.isDirectional()) l.position = r.vec3(r.member(j, "position", at), at + ".position", kMaxCoordinate);
    if (l.type != PunctualLight::Type::Point) {
      glm::vec3 d = r.vec3(r.member(j, "direction", at), at + ".direction", 1e6);
      if (!(glm::length(d) > 0.0f)) r.fail(at + ".direction", "zero vector");
      l.direction = glm::normalize(d);
    }
    if (l.type == PunctualLight::Type::Spot) {
      l.innerConeAngle = r.number(r.member(j, "innerConeAngle", at), at + ".innerConeAngle", 2.0);
      l.outerConeAngle = r.number(r.member(j, "outerConeAngle", at), at + ".outerConeAngle", 2.0);
      if (!(l.innerConeAngle >= 0.0f && l.innerConeAngle < l.outerConeAngle && l.outerConeAngle <= 1.5707964f))
        r.fail(at, "needs 0 <= innerConeAngle < outerConeAngle <= pi/2");
    }
    punctual.push_back(l);
  }

  struct Area {
    std::string material;
    glm::vec3 emission;
    std::vector<glm::vec3> corners;  ///< three per triangle
    std::vector<glm::vec2> uvs;      ///< three per triangle, or empty (untextured: zero)
  };
  std::vector<Area> areas;
  const Json& areaList = r.member(doc, "areaLights", "areaLights");
  if (!areaList.is_array()) r.fail("areaLights", "expected an array");
  for (std::size_t i = 0; i < areaList.size(); ++i) {
    std::string at = "areaLights[" + std::to_string(i) + "]";
    const Json& j = areaList[i];
    Area a;
    const Json& name = r.member(j, "material", at);
    if (!name.is_string()) r.fail(at + ".material", "expected a string");
    a.material = name.get<std::string>();
    a.emission = r.vec3(r.member(j, "emission", at), at + ".emission", kMaxEmission);
    if (a.emission.r < 0.0f || a.emission.g < 0.0f || a.emission.b < 0.0f) r.fail(at + ".emission", "negative");
    const Json& tris = r.member(j, "triangles", at);
    if (!tris.is_array()) r.fail(at + ".triangles", "expected an array");
    for (std::size_t t = 0; t < tris.size(); ++t) {
      std::string tAt = at + ".triangles[" + std::to_string(t) + "]";
      if (!tris[t].is_array() || tris[t].size() != 3) r.fail(tAt, "expected 3 corners");
      for (int k = 0; k < 3; ++k) a.corners.push_back(r.vec3(tris[t][static_cast<std::size_t>(k)], tAt, kMaxCoordinate));
    }
    if (j.contains("uvs")) {
      const Json& uvs = j["uvs"];
      if (!uvs.is_array() || uvs.size() != tris.size()) r.fail(at + ".uvs", "expected one triple per triangle");
      for (std::size_t t = 0; t < uvs.size(); ++t) {
        std::string tAt = at + ".uvs[" + std::to_string(t) + "]";
        if (!uvs[t].is_array() || uvs[t].size() != 3) r.fail(tAt, "expected 3 texture coordinates");
        for (int k = 0; k < 3; ++k) a.uvs.push_back(r.vec2(uvs[t][static_cast<std::size_t>(k)], tAt, kMaxCoordinate));
      }
    }
    areas.push_back(std::move(a));
  }

  // Media: optional (a sidecar saved before the editor edited media keeps the scene's), checked as the loader checks
  // the glTF extension's.
  std::optional<std::vector<Medium>> media;
  if (doc.contains("media")) {
    const Json& list = doc["media"];
    if (!list.is_array()) r.fail("media", "expected an array");
    media.emplace();
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string at = "media[" + std::to_string(i) + "]";
      const Json& j = list[i];
      Medium m;
      const Json& name = r.member(j, "name", at);
      if (!name.is_string()) r.fail(at + ".name", "expected a string");
      m.name = name.get<std::string>();
      m.sigmaA = r.vec3(r.member(j, "sigmaA", at), at + ".sigmaA", kMaxMediumSigma);
      m.sigmaS = r.vec3(r.member(j, "sigmaS", at), at + ".sigmaS", kMaxMediumSigma);
      m.g = r.number(r.member(j, "g", at), at + ".g", 1.0);
      if (j.contains("fillsSpace")) {
        if (!j["fillsSpace"].is_boolean()) r.fail(at + ".fillsSpace", "expected true or false");
        m.fillsSpace = j["fillsSpace"].get<bool>();
      }
      if (j.contains("density") && !m.fillsSpace) {
        // The grid first: the box read below keeps mapping onto the grid's index box (Medium::setBox).
        const Json& d = j["density"];
        const std::string dAt = at + ".density";
        const Json& uri = r.member(d, "uri", dAt);
        const Json& grid = r.member(d, "grid", dAt);
        if (!uri.is_string() || !grid.is_string()) r.fail(dAt, "expected \"uri\" and \"grid\" strings");
        const std::filesystem::path file(uri.get<std::string>());
        const std::string resolved =
            file.is_absolute() ? file.string() : (std::filesystem::path(path).parent_path() / file).string();
        try {
          m.setDensity(readVdbDensity(resolved, grid.get<std::string>()), glm::mat4(1.0f));
        } catch (const VdbError& e) {
          r.fail(dAt, e.what());
        }
        m.densityUri = uri.get<std::string>();
        m.densityGridName = grid.get<std::string>();
        m.densityScale = r.number(r.member(d, "scale", dAt), dAt + ".scale", kMaxMediumSigma);
      }
      if (!m.fillsSpace) {
        const Json& world = r.member(j, "worldFromBox", at);
        if (!world.is_array() || world.size() != 16) r.fail(at + ".worldFromBox", "expected 16 numbers (column-major)");
        glm::mat4 w;
        for (int c = 0; c < 4; ++c)
          for (int k = 0; k < 4; ++k)
            w[c][k] = r.number(world[static_cast<std::size_t>(4 * c + k)], at + ".worldFromBox", kMaxCoordinate);
        m.setBox(w);
      }
      if (std::string problem = mediumProblem(m); !problem.empty()) r.fail(at, problem);
      media->push_back(m);
    }
    if (std::string problem = mediaProblem(*media); !problem.empty()) r.fail("media", problem);
  }

  // Apply: the scene's own area lights go, the file's come in.
  if (media) scene.media = std::move(*media);
  scene.punctualLights = std::move(punctual);
  std::size_t kept = 0;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t)
    if (!scene.materials[scene.triangleMaterials[t]].isEmissive()) {
      scene.triangles[kept] = scene.triangles[t];
      scene.triangleMaterials[kept] = scene.triangleMaterials[t];
      ++kept;
    }
  scene.triangles.resize(kept);
  scene.triangleMaterials.resize(kept);
  for (Material& m : scene.materials) m.emission = glm::vec3(0.0f);
  for (const Area& a : areas) {
    uint32_t material = static_cast<uint32_t>(scene.materials.size());
    for (uint32_t m = 0; m < scene.materials.size(); ++m)
      if (scene.materials[m].name == a.material) material = m;
    if (material == scene.materials.size()) {
      Material m;
      m.name = a.material;
      m.baseColor = glm::vec3(0.0f);
      m.specular = 0.0f;
      scene.materials.push_back(m);
    }
    scene.materials[material].emission = a.emission;
    for (std::size_t c = 0; c + 2 < a.corners.size(); c += 3) {
      const glm::vec3 n = glm::cross(a.corners[c + 1] - a.corners[c], a.corners[c + 2] - a.corners[c]);
      if (!(glm::length(n) > 0.0f)) continue;
      auto base = static_cast<uint32_t>(scene.positions.size());
      for (int k = 0; k < 3; ++k) {
        scene.positions.push_back(a.corners[c + static_cast<std::size_t>(k)]);
        scene.normals.push_back(glm::normalize(n));
        scene.uvs.push_back(a.uvs.empty() ? glm::vec2(0.0f) : a.uvs[c + static_cast<std::size_t>(k)]);
      }
      scene.triangles.emplace_back(base, base + 1, base + 2);
      scene.triangleMaterials.push_back(material);
    }
  }
  scene.finalize();
}

bool applyLightsSidecar(Scene& scene) {
  const std::string path = lightsSidecarPath(scene.sourcePath);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return false;  // one that exists but is no regular file is an error
  applyLightsFile(path, scene);
  scene.staging += std::string(scene.staging.empty() ? "" : "; ") + "lights from " + path;
  return true;
}

}  // namespace vplab
