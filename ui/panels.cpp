#include "ui/panels.h"

#include "renderer/core/sampling.h"
#include "renderer/scene/staging.h"
#include "renderer/vpl/generation_methods.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <variant>

namespace vplab::ui {

namespace {

// Every control of a setting is labelled with the setting's one name (its settings-file key and script verb, the
// command-line flag in kebab case) and shows the settings table's help and flag as its tooltip, so the editor, the
// files and the command line speak of the same thing (renderer/settings.h, "the settings table").
const SettingInfo& settingRow(const char* key) {
  const SettingInfo* info = findSetting(key);
  if (!info) throw std::logic_error(std::string("no setting '") + key + "'");
  return *info;
}

void settingTooltip(const char* key, const char* more = nullptr) {
  if (!ImGui::IsItemHovered()) return;
  const SettingInfo& info = settingRow(key);
  ImGui::SetTooltip("%s%s%s\n--%s", info.help, more ? "\n" : "", more ? more : "", settingFlag(key).c_str());
}

bool settingSliderInt(Settings& s, const char* key, int lo, int hi, ImGuiSliderFlags flags = 0) {
  int* v = &(s.*std::get<int Settings::*>(settingRow(key).member));
  bool changed = ImGui::SliderInt(key, v, lo, hi, "%d", flags | ImGuiSliderFlags_AlwaysClamp);
  settingTooltip(key);
  return changed;
}

bool settingSliderFloat(Settings& s, const char* key, float lo, float hi, const char* format,
                        ImGuiSliderFlags flags = 0, const char* more = nullptr) {
  float* v = &(s.*std::get<float Settings::*>(settingRow(key).member));
  bool changed = ImGui::SliderFloat(key, v, lo, hi, format, flags | ImGuiSliderFlags_AlwaysClamp);
  settingTooltip(key, more);
  return changed;
}

bool settingCombo(Settings& s, const char* key, const char* more = nullptr) {
  const SettingChoice& choice = std::get<SettingChoice>(settingRow(key).member);
  const int current = choice.get(s);
  bool changed = false;
  if (ImGui::BeginCombo(key, choice.names[static_cast<std::size_t>(current)].c_str())) {
    for (int i = 0; i < static_cast<int>(choice.names.size()); ++i)
      if (ImGui::Selectable(choice.names[static_cast<std::size_t>(i)].c_str(), i == current) && i != current) {
        choice.set(s, i);
        changed = true;
      }
    ImGui::EndCombo();
  }
  settingTooltip(key, more);
  return changed;
}

bool settingCheckbox(Settings& s, const char* key) {
  bool changed = ImGui::Checkbox(key, &(s.*std::get<bool Settings::*>(settingRow(key).member)));
  settingTooltip(key);
  return changed;
}

}  // namespace

bool drawManyLightPanel(Settings& s, const VplStats& stats, double clampEnergyRemoved, VisibilityMethod visibilityInUse,
                        float sceneDiagonal) {
  bool changed = false;
  ImGui::TextDisabled("VPL generation");
  if (settingCombo(s, "generation")) {
    // Rejection is a light-tracing method (validateSettings); the others choose their VPLs by importance already.
    if (s.generation != VplGeneration::Light) s.rejection = false;
    changed = true;
  }
  // Beyond previewRepresentatives VPLs the preview gathers a per-view cut of them (representative_lights.h).
  changed |= settingSliderInt(s, "vplCount", 1, 1 << 20, ImGuiSliderFlags_Logarithmic);
  changed |= settingSliderInt(s, "vplMaxBounces", 1, 64);
  int seed = static_cast<int>(std::min<uint32_t>(s.seed, 1u << 30));
  if (ImGui::InputInt("seed", &seed) && seed >= 0) {
    s.seed = static_cast<uint32_t>(seed);
    changed = true;
  }
  settingTooltip("seed");

  if (s.generation == VplGeneration::Bidirectional) {
    changed |= settingSliderInt(s, "birCandidateFactor", 1, 64, ImGuiSliderFlags_Logarithmic);
    changed |= settingSliderFloat(s, "birLightShare", 0.01f, 1.0f, "%.2f");
    changed |= settingSliderFloat(s, "birEpsilon", 0.0f, 1.0f, "%.2f");
  } else if (s.generation == VplGeneration::Metropolis) {
    changed |= settingSliderInt(s, "mirChains", 1, 4096, ImGuiSliderFlags_Logarithmic);
    changed |= settingSliderFloat(s, "mirLargeStepProbability", 0.01f, 1.0f, "%.2f");
    changed |= settingSliderInt(s, "mirBurnIn", 0, 64);
    changed |= settingSliderInt(s, "mirBootstrapPaths", 16, 16384, ImGuiSliderFlags_Logarithmic);
    changed |= settingSliderFloat(s, "mirEpsilon", 0.0f, 1.0f, "%.2f");
  }
  if (s.generation != VplGeneration::Light || s.rejection)
    changed |= settingSliderInt(s, "importancePoints", 1, 4096, ImGuiSliderFlags_Logarithmic);
  if (s.generation == VplGeneration::Light) {
    ImGui::Separator();
    ImGui::TextDisabled("Rejection (Georgiev & Slusallek 2010)");
    changed |= settingCheckbox(s, "rejection");
  }
  if (s.rejection) {
    changed |= settingSliderFloat(s, "rejectionEpsilon", 0.0f, 1.0f, "%.3f", 0,
                                  "0 rejects VPLs that miss every importance point");
  }
  // What the last generation did: method, VPLs kept of candidates, acceptance (with rejection also the pilot's
  // prediction and its spread; Metropolis: accepted mutations), time, and any warning such as a fallback.
  ImGui::TextWrapped("%s", describeVplStats(stats).c_str());
  for (const std::string& w : stats.warnings) ImGui::TextColored(ImVec4(1.0f, 0.6f, 0.2f, 1.0f), "%s", w.c_str());

  ImGui::Separator();
  ImGui::TextDisabled("Bounded geometry term G_b = min(G, b)");
  bool bounded = !std::isinf(s.clampBound);
  // b in 1/m^2, or relative to the scene (units of 1/diagonal^2), which means the same on a box and on a model in
  // millimetres; the other unit is shown beside it. Switched on, b starts at 20 / diagonal^2.
  const double diagonal2 = std::max(static_cast<double>(sceneDiagonal) * sceneDiagonal, 1e-12);
  if (ImGui::Checkbox("clamp", &bounded)) {
    s.clampBoundRelative = bounded ? 20.0f : 0.0f;
    s.clampBound = bounded ? static_cast<float>(20.0 / diagonal2) : kInfinity;
    changed = true;
  }
  settingTooltip("clampBound", "off: clampBound = inf");
  if (bounded) {
    bool relative = s.clampBoundRelative > 0.0f;
    ImGui::SameLine();
    if (ImGui::Checkbox("relative to the scene", &relative)) {
      s.clampBoundRelative = relative ? static_cast<float>(s.clampBound * diagonal2) : 0.0f;
      changed = true;
    }
    settingTooltip("clampBoundRelative");
    if (relative) {
      changed |= settingSliderFloat(s, "clampBoundRelative", 0.01f, 100000.0f, "%.3g", ImGuiSliderFlags_Logarithmic,
                                    "b = this / diagonal^2");
      ImGui::Text("b = %.3g 1/m^2 (diagonal %.3g m)", s.clampBoundRelative / diagonal2, sceneDiagonal);
    } else {
      changed |= settingSliderFloat(s, "clampBound", 0.01f, 10000.0f, "%.3g", ImGuiSliderFlags_Logarithmic,
                                    "b on cos1 cos2 / d^2; the residual is local: d < 1/sqrt(b)");
      ImGui::Text("= %.3g / diagonal^2 (diagonal %.3g m)", s.clampBound * diagonal2, sceneDiagonal);
    }
    ImGui::Text("residual range 1/sqrt(b) = %.3g m", 1.0 / std::sqrt(std::max(s.clampBound, 1e-6f)));
  }
  if (clampEnergyRemoved >= 0.0) {
    ImGui::Text("clamp removes ~%.1f %% at sample points", 100.0 * clampEnergyRemoved);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(
          "An estimate while you edit: over at most 256 camera-visible points on a coarse grid, the\n"
          "luminance min(G, b) loses against G, summed over every VPL each point sees. The exact VPL\n"
          "render measures the same over every pixel (shown under this panel once it ran).");
  } else {
    ImGui::TextDisabled("clamp energy removed: not measured");
  }
  changed |= settingSliderInt(s, "ssbcSteps", 0, 2);
  changed |= settingCheckbox(s, "ssbcCoarseRings");

  ImGui::Separator();
  ImGui::TextDisabled("Virtual spherical lights (Hasan et al. 2009)");
  bool vsl = s.vslRadius > 0.0f;
  if (ImGui::Checkbox("VSL", &vsl)) {
    s.vslRadius = vsl ? 0.05f : 0.0f;
    changed = true;
  }
  settingTooltip("vslRadius", "off: vslRadius = 0");
  if (vsl) {
    changed |= settingSliderFloat(s, "vslRadius", 0.001f, 1.0f, "%.4f", ImGuiSliderFlags_Logarithmic);
    changed |= settingCheckbox(s, "vslRadiusFromDensity");
    changed |= settingSliderInt(s, "vslSamples", 1, 64);
  }

  ImGui::Separator();
  ImGui::TextDisabled("GL preview");
  changed |= settingSliderInt(s, "interleave", 1, 8);
  changed |= settingSliderInt(s, "indirectDownscale", 1, 4);
  changed |= settingCombo(s, "visibility",
                          "cube: one map per VPL, sharp, costs VPLs x triangles; ism: a point-splatted "
                          "tile per VPL, cost independent of the triangle count, leaks through thin walls; auto: cube "
                          "maps while triangles x VPLs <= " VPLAB_AUTO_CUBE_LIMIT);
  if (s.visibility == VisibilityMethod::Auto) ImGui::TextDisabled("auto picked %s", toString(visibilityInUse));
  // A power-of-two size: the slider moves its exponent.
  auto powerOfTwoSlider = [&](const char* key, int minLog, int maxLog) {
    int& value = s.*std::get<int Settings::*>(settingRow(key).member);
    int sizeLog = static_cast<int>(std::lround(std::log2(std::max(value, 1 << minLog))));
    if (ImGui::SliderInt(key, &sizeLog, minLog, maxLog, "")) {
      value = 1 << sizeLog;
      changed = true;
    }
    settingTooltip(key);
    ImGui::SameLine();
    ImGui::Text("%d", value);
  };
  if (visibilityInUse == VisibilityMethod::Ism) {
    powerOfTwoSlider("ismTileSize", 4, 8);
    powerOfTwoSlider("ismPointBudget", 10, 25);
  } else {
    powerOfTwoSlider("shadowMapSize", 4, 11);
  }
  changed |= settingSliderFloat(s, "shadowBias", 0.0f, 0.1f, "%.4f", ImGuiSliderFlags_Logarithmic);
  changed |= settingSliderInt(s, "previewRepresentatives", 16, 4096, ImGuiSliderFlags_Logarithmic);
  changed |= settingSliderInt(s, "directLightSamples", 1, 256, ImGuiSliderFlags_Logarithmic);
  powerOfTwoSlider("lightShadowMapSize", 4, 12);
  changed |= settingSliderFloat(s, "exposure", -10.0f, 10.0f, "%.1f");
  return changed;
}

bool drawOfflineSettingsPanel(Settings& s) {
  bool changed = false;
  int size[2] = {s.width, s.height};
  if (ImGui::InputInt2("image size", size) && size[0] >= 16 && size[1] >= 16 && size[0] <= 2048 && size[1] <= 2048) {
    s.width = size[0];
    s.height = size[1];
    changed = true;
  }
  changed |= settingSliderInt(s, "samplesPerPixel", 1, 4096, ImGuiSliderFlags_Logarithmic);
  changed |= settingSliderInt(s, "exactSamplesPerPixel", 1, 4096, ImGuiSliderFlags_Logarithmic);
  changed |= settingSliderInt(s, "maxDepth", 1, 64);
  return changed;
}

std::vector<LightHandle> editableLights(const Scene& scene) {
  std::vector<LightHandle> lights;
  for (uint32_t i = 0; i < scene.punctualLights.size(); ++i) {
    const PunctualLight& l = scene.punctualLights[i];
    const char* kind = l.isDirectional() ? "directional" : l.type == PunctualLight::Type::Spot ? "spot" : "point";
    lights.push_back({LightHandle::Kind::Punctual, i, std::string(kind) + ": " + (l.name.empty() ? std::to_string(i) : l.name)});
  }
  std::set<uint32_t> emissive;
  for (uint32_t t : scene.emissiveTriangles) emissive.insert(scene.triangleMaterials[t]);
  for (uint32_t m : emissive)
    lights.push_back({LightHandle::Kind::AreaMaterial, m, "area: " + scene.materials[m].name});
  return lights;
}

LightEdit moveLight(Scene& scene, const LightHandle& light, const glm::vec3& offset) {
  if (light.kind == LightHandle::Kind::Punctual) {
    PunctualLight& l = scene.punctualLights.at(light.index);
    if (l.isDirectional()) return LightEdit::None;
    l.position += offset;
    scene.updateBounds();
    return LightEdit::Punctual;
  }
  // Each vertex moves once even when several emissive triangles share it.
  std::set<uint32_t> vertices;
  for (uint32_t t = 0; t < scene.triangles.size(); ++t)
    if (scene.triangleMaterials[t] == light.index)
      for (int k = 0; k < 3; ++k) vertices.insert(scene.triangles[t][k]);
  for (uint32_t v : vertices) scene.positions[v] += offset;
  scene.finalize();
  return LightEdit::Geometry;
}

LightEdit scaleLight(Scene& scene, const LightHandle& light, float scale) {
  if (light.kind == LightHandle::Kind::Punctual) {
    scene.punctualLights.at(light.index).intensity *= scale;
    return LightEdit::Punctual;
  }
  scene.materials.at(light.index).emission *= scale;
  return LightEdit::Geometry;
}

LightEdit aimLight(Scene& scene, const LightHandle& light, const glm::vec3& direction) {
  if (light.kind != LightHandle::Kind::Punctual || !(glm::length(direction) > 0.0f)) return LightEdit::None;
  scene.punctualLights.at(light.index).direction = glm::normalize(direction);
  return LightEdit::Punctual;
}

LightEdit addLight(Scene& scene, NewLight kind) {
  const Bounds& b = scene.geometryBounds;
  const glm::vec3 center = b.valid() ? b.center() : glm::vec3(0.0f);
  const float radius = std::max(0.5f * b.diagonal(), 1e-3f);
  const glm::vec3 above = center + glm::vec3(0.0f, 2.0f * radius, 0.0f);
  const std::string name = "added " + std::to_string(scene.punctualLights.size() + scene.materials.size());
  if (kind == NewLight::Area) {
    addSquareLight(scene, above, center, radius, kPi, name);
  } else {
    PunctualLight l;
    l.name = name;
    if (kind == NewLight::Point) {
      l.type = PunctualLight::Type::Point;
      l.position = above;
      l.intensity = glm::vec3(kPi * 4.0f * radius * radius);  // E = I / d^2 at the centre, d = 2R
    } else {
      l.type = PunctualLight::Type::Directional;
      l.direction = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.5f));
      l.intensity = glm::vec3(kPi);
    }
    scene.punctualLights.push_back(l);
    scene.updateBounds();
    return LightEdit::Punctual;
  }
  scene.finalize();
  return LightEdit::Geometry;
}

LightEdit deleteLight(Scene& scene, const LightHandle& light) {
  if (light.kind == LightHandle::Kind::Punctual) {
    scene.punctualLights.erase(scene.punctualLights.begin() + light.index);
    scene.updateBounds();
    return LightEdit::Punctual;
  }
  // The triangles go; their vertices stay unreferenced (harmless, and no index has to be rewritten).
  std::size_t kept = 0;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t)
    if (scene.triangleMaterials[t] != light.index) {
      scene.triangles[kept] = scene.triangles[t];
      scene.triangleMaterials[kept] = scene.triangleMaterials[t];
      ++kept;
    }
  scene.triangles.resize(kept);
  scene.triangleMaterials.resize(kept);
  scene.finalize();
  return LightEdit::Geometry;
}

LightEdit drawLightsPanel(Scene& scene, std::vector<glm::vec3>& offsets, std::vector<float>& scales) {
  std::vector<LightHandle> lights = editableLights(scene);
  offsets.resize(lights.size(), glm::vec3(0.0f));
  scales.resize(lights.size(), 1.0f);
  if (lights.empty()) ImGui::TextDisabled("no lights");
  LightEdit changed = LightEdit::None;
  const float step = 0.01f * std::max(scene.bounds.diagonal(), 1e-3f);
  for (std::size_t i = 0; i < lights.size(); ++i) {
    ImGui::PushID(static_cast<int>(i));
    ImGui::TextUnformatted(lights[i].name.c_str());
    const PunctualLight* punctual =
        lights[i].kind == LightHandle::Kind::Punctual ? &scene.punctualLights[lights[i].index] : nullptr;
    glm::vec3 offset = offsets[i];
    if ((!punctual || !punctual->isDirectional()) &&
        ImGui::DragFloat3("offset", &offset.x, step, -scene.bounds.diagonal(), scene.bounds.diagonal(), "%.3f")) {
      changed = combine(changed, moveLight(scene, lights[i], offset - offsets[i]));
      offsets[i] = offset;
    }
    if (punctual && punctual->type != PunctualLight::Type::Point) {
      glm::vec3 direction = punctual->direction;
      if (ImGui::DragFloat3("direction", &direction.x, 0.01f, -1.0f, 1.0f, "%.2f")) {
        changed = combine(changed, aimLight(scene, lights[i], direction));
      }
    }
    float scale = scales[i];
    if (ImGui::SliderFloat("intensity x", &scale, 0.05f, 20.0f, "%.2f", ImGuiSliderFlags_Logarithmic) && scale > 0.0f) {
      changed = combine(changed, scaleLight(scene, lights[i], scale / scales[i]));
      scales[i] = scale;
    }
    bool deleted = ImGui::SmallButton("delete");
    if (deleted) {
      changed = combine(changed, deleteLight(scene, lights[i]));
      offsets.erase(offsets.begin() + static_cast<std::ptrdiff_t>(i));
      scales.erase(scales.begin() + static_cast<std::ptrdiff_t>(i));
    }
    ImGui::PopID();
    if (deleted) break;  // the handles after it are stale; the next frame lists the lights again
  }
  // New punctual lights are listed after the existing punctual ones, new area lights last.
  const auto punctualCount = static_cast<std::ptrdiff_t>(scene.punctualLights.size());
  auto add = [&](NewLight kind) {
    changed = combine(changed, addLight(scene, kind));
    std::ptrdiff_t at = kind == NewLight::Area ? static_cast<std::ptrdiff_t>(offsets.size()) : punctualCount;
    offsets.insert(offsets.begin() + at, glm::vec3(0.0f));
    scales.insert(scales.begin() + at, 1.0f);
  };
  if (ImGui::Button("+ point")) add(NewLight::Point);
  ImGui::SameLine();
  if (ImGui::Button("+ area")) add(NewLight::Area);
  ImGui::SameLine();
  if (ImGui::Button("+ directional")) add(NewLight::Directional);
  return changed;
}

void drawSceneInfo(const Scene& scene) {
  ImGui::TextWrapped("%s", scene.sourcePath.c_str());
  ImGui::Text("%zu triangles, %zu materials", scene.triangles.size(), scene.materials.size());
  ImGui::Text("%zu emissive triangles, %zu punctual lights", scene.emissiveTriangles.size(),
              scene.punctualLights.size());
  ImGui::Text("camera %s", scene.camera.fromFile ? "from the file" : "framed by vplab");
  if (!scene.staging.empty()) ImGui::TextWrapped("staged %s", scene.staging.c_str());
  if (scene.degenerateTrianglesDropped)
    ImGui::Text("%zu degenerate triangles dropped", scene.degenerateTrianglesDropped);
  for (const std::string& w : scene.warnings) ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "%s", w.c_str());
}

}  // namespace vplab::ui
