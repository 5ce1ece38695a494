#include "renderer/vpl/vpl_json.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

#include "renderer/core/atomic_file.h"

namespace vplab {

namespace {

using nlohmann::json;

json vec(const glm::vec3& v) { return json::array({v.x, v.y, v.z}); }
json vec(const glm::vec2& v) { return json::array({v.x, v.y}); }

glm::vec3 readVec3(const json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) throw VplJsonError(where + ": expected an array of 3 numbers");
  return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()};
}
glm::vec2 readVec2(const json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 2) throw VplJsonError(where + ": expected an array of 2 numbers");
  return {j[0].get<float>(), j[1].get<float>()};
}

json vplToJson(const Vpl& v) {
  return json{{"position", vec(v.position)}, {"normal", vec(v.normal)}, {"geometricNormal", vec(v.geometricNormal)},
              {"incoming", vec(v.incoming)}, {"flux", vec(v.flux)},     {"uv", vec(v.uv)},
              {"material", v.material},      {"bounce", v.bounce},      {"radius", v.radius}};
}

Vpl vplFromJson(const json& j, const std::string& where) {
  if (!j.is_object()) throw VplJsonError(where + ": expected an object");
  auto field = [&](const char* name) -> const json& {
    auto it = j.find(name);
    if (it == j.end()) throw VplJsonError(where + "." + name + ": missing");
    return *it;
  };
  Vpl v;
  v.position = readVec3(field("position"), where + ".position");
  v.normal = readVec3(field("normal"), where + ".normal");
  // Older files have no geometric normal: the shading normal is the best stand-in.
  v.geometricNormal = j.contains("geometricNormal") ? readVec3(j["geometricNormal"], where + ".geometricNormal")
                                                    : v.normal;
  v.incoming = readVec3(field("incoming"), where + ".incoming");
  v.flux = readVec3(field("flux"), where + ".flux");
  v.uv = readVec2(field("uv"), where + ".uv");
  v.material = field("material").get<uint32_t>();
  v.bounce = field("bounce").get<uint32_t>();
  v.radius = j.value("radius", 0.0f);
  return v;
}

}  // namespace

std::string vplSetToJson(const VplSet& set) {
  json stats{{"pathsTraced", set.stats.pathsTraced},
             {"candidates", set.stats.candidates},
             {"accepted", set.stats.accepted},
             {"acceptanceRate", set.stats.acceptanceRate},
             {"candidateCapReached", set.stats.candidateCapReached},
             {"generationSeconds", set.stats.generationSeconds}};
  json vpls = json::array(), rejected = json::array();
  for (const Vpl& v : set.vpls) vpls.push_back(vplToJson(v));
  for (const Vpl& v : set.rejected) rejected.push_back(vplToJson(v));
  return json{{"stats", stats}, {"vpls", vpls}, {"rejected", rejected}}.dump(1);
}

VplSet vplSetFromJson(const std::string& text) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    throw VplJsonError(std::string("not JSON: ") + e.what());
  }
  if (!root.is_object()) throw VplJsonError("$: expected an object");
  VplSet set;
  try {
    if (root.contains("stats")) {
      const json& s = root["stats"];
      set.stats.pathsTraced = s.value("pathsTraced", uint64_t{0});
      set.stats.candidates = s.value("candidates", uint64_t{0});
      set.stats.accepted = s.value("accepted", uint64_t{0});
      set.stats.acceptanceRate = s.value("acceptanceRate", 1.0);
      set.stats.candidateCapReached = s.value("candidateCapReached", false);
      set.stats.generationSeconds = s.value("generationSeconds", 0.0);
    }
    if (!root.contains("vpls") || !root["vpls"].is_array()) throw VplJsonError("$.vpls: expected an array");
    const json& vpls = root["vpls"];
    for (std::size_t i = 0; i < vpls.size(); ++i)
      set.vpls.push_back(vplFromJson(vpls[i], "$.vpls[" + std::to_string(i) + "]"));
    if (root.contains("rejected")) {
      const json& rej = root["rejected"];
      if (!rej.is_array()) throw VplJsonError("$.rejected: expected an array");
      for (std::size_t i = 0; i < rej.size(); ++i)
        set.rejected.push_back(vplFromJson(rej[i], "$.rejected[" + std::to_string(i) + "]"));
    }
  } catch (const json::exception& e) {
    throw VplJsonError(std::string("wrong value type: ") + e.what());
  }
  return set;
}

void saveVplSet(const std::string& path, const VplSet& set) {
  try {
    writeFileAtomically(path, vplSetToJson(set) + "\n");
  } catch (const FileWriteError& e) {
    throw VplJsonError(e.what());
  }
}

VplSet loadVplSet(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw VplJsonError(path + ": cannot open");
  std::stringstream buffer;
  buffer << in.rdbuf();
  try {
    return vplSetFromJson(buffer.str());
  } catch (const VplJsonError& e) {
    throw VplJsonError(path + ": " + e.what());
  }
}

}  // namespace vplab
