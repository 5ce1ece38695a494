#include "ui/media_panel.h"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cassert>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "renderer/scene/density_grid.h"
#include "renderer/scene/media_gltf.h"
#include "renderer/scene/vdb_grid.h"

namespace vplab::ui {

namespace {

Medium greyFog(const Scene& scene) {
  Medium m;
  m.name = "fog " + std::to_string(scene.media.size() + 1);
  m.sigmaA = glm::vec3(0.05f);
  m.sigmaS = glm::vec3(0.5f);
  m.g = 0.3f;
  return m;
}

std::string triple(const glm::vec3& v) {
  char text[96];
  std::snprintf(text, sizeof text, "%.3g %.3g %.3g", v.x, v.y, v.z);
  return text;
}

/// Per channel 1 / sigma_t (inf where the channel does not interact), as Medium::meanFreePath.
glm::vec3 freePath(const glm::vec3& sigmaT) {
  const float inf = std::numeric_limits<float>::infinity();
  return {sigmaT.x > 0.0f ? 1.0f / sigmaT.x : inf, sigmaT.y > 0.0f ? 1.0f / sigmaT.y : inf,
          sigmaT.z > 0.0f ? 1.0f / sigmaT.z : inf};
}

/// A density grid's file, grid name, voxels and density range, and its density scale (returns true when it changed).
bool drawDensityGrid(Medium& m) {
  const DensityGrid& grid = *m.density;
  ImGui::TextDisabled("density grid '%s' of %s", m.densityGridName.c_str(),
                      std::filesystem::path(m.densityUri).filename().string().c_str());
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", m.densityUri.c_str());
  // The stored box is the active voxels' bounding box with a voxel of zeros on every side (density_grid.h).
  const glm::ivec3 box = grid.size - 2;
  ImGui::TextDisabled("%dx%dx%d voxels, %llu active", box.x, box.y, box.z,
                      static_cast<unsigned long long>(grid.activeVoxels));
  ImGui::TextDisabled("density %.3g to %.3g, times the scale", grid.minValue, grid.maxValue);
  const bool changed = ImGui::DragFloat("density scale", &m.densityScale, 0.01f, 0.0f, 1e3f, "%.3f");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("multiplies the grid's density; sigma_a and sigma_s above are per unit density");
  return changed;
}

}  // namespace

Medium newFogBox(const Scene& scene) {
  Medium m = greyFog(scene);
  const Bounds& b = scene.geometryBounds;
  const glm::vec3 half = 0.99f * 0.5f * glm::max(b.extent(), glm::vec3(1e-3f));
  glm::mat4 world(1.0f);
  world[0][0] = half.x;
  world[1][1] = half.y;
  world[2][2] = half.z;
  world[3] = glm::vec4(b.center(), 1.0f);
  m.setBox(world);
  return m;
}

Medium newFogEverywhere(const Scene& scene) {
  Medium m = greyFog(scene);
  m.fillsSpace = true;
  return m;
}

void moveMediumBox(Medium& medium, const glm::vec3& offset) {
  if (medium.fillsSpace) return;
  glm::mat4 world = medium.worldFromBox;
  world[3] += glm::vec4(offset, 0.0f);
  medium.setBox(world);
}

void resizeMediumBox(Medium& medium, const glm::vec3& halfSizes) {
  if (medium.fillsSpace) return;
  const glm::vec3 old = medium.halfSizes();
  glm::mat4 world = medium.worldFromBox;
  for (int i = 0; i < 3; ++i) {
    // An axis of zero length has no direction left: it takes the world axis.
    const glm::vec3 axis = old[i] > 0.0f ? glm::vec3(world[i]) / old[i] : glm::vec3(i == 0, i == 1, i == 2);
    world[i] = glm::vec4(axis * halfSizes[i], 0.0f);
  }
  medium.setBox(world);
}

std::string describeMedium(const Medium& m, float sceneDiagonal) {
  if (m.isVacuum()) return "vacuum: light crosses it unchanged";
  // A grid's density varies: its densest voxel has the shortest free path and gives the largest depths, which bound
  // what any ray through the smoke meets.
  const glm::vec3 sigmaT = m.sigmaTMax();
  const std::string downTo = m.heterogeneous() ? "down to " : "", upTo = m.heterogeneous() ? "up to " : "";
  std::string text = "mean free path " + downTo + triple(freePath(sigmaT)) + " m\noptical depth across the scene " +
                     upTo + triple(sigmaT * sceneDiagonal);
  if (!m.fillsSpace) {
    const glm::vec3 half = m.halfSizes();
    text += "\nalong the box's longest edge " + upTo + triple(sigmaT * 2.0f * std::max({half.x, half.y, half.z}));
  }
  return text;
}

int densityTarget(const std::vector<Medium>& media, int selected) {
  if (selected >= 0 && selected < static_cast<int>(media.size()) && !media[selected].fillsSpace) return selected;
  for (std::size_t i = 0; i < media.size(); ++i)
    if (!media[i].fillsSpace) return static_cast<int>(i);
  return -1;
}

std::size_t attachVdb(const Scene& scene, std::vector<Medium>& media, int index, const std::string& path,
                      const std::string& gridName) {
  Medium m;
  if (index < 0) {
    m = newFogBox(scene);
    m.name = std::filesystem::path(path).stem().string();  // the smoke is named after its file
  } else {
    m = media.at(static_cast<std::size_t>(index));
  }
  assert(!m.fillsSpace && "a density grid needs a box");
  attachDensity(m, path, gridName, m.densityScale);  // throws before `media` is touched
  if (index < 0) {
    media.push_back(std::move(m));
    return media.size() - 1;
  }
  media[static_cast<std::size_t>(index)] = std::move(m);
  return static_cast<std::size_t>(index);
}

bool openVdb(const Scene& scene, std::vector<Medium>& media, MediaPanelInput& input, const std::string& path) {
  try {
    input.selected =
        static_cast<int>(attachVdb(scene, media, densityTarget(media, input.selected), path, input.gridName));
  } catch (const VdbError& e) {
    input.vdbError = e.what();
    return false;
  }
  input.vdbError.clear();
  return true;
}

bool drawMediaPanel(const Scene& scene, std::vector<Medium>& media, const std::string& error, MediaPanelInput& input) {
  bool changed = false;
  if (media.empty()) ImGui::TextDisabled("no media");
  const float diagonal = std::max(scene.geometryBounds.diagonal(), 1e-3f);
  for (std::size_t i = 0; i < media.size(); ++i) {
    Medium& m = media[i];
    const int index = static_cast<int>(i);
    ImGui::PushID(index);
    const std::string title = m.name + ": " +
                              (m.fillsSpace        ? "all space"
                               : m.heterogeneous() ? "box, density grid"
                                                   : "box");
    if (ImGui::Selectable(title.c_str(), input.selected == index))
      input.selected = input.selected == index ? -1 : index;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("select: an opened or dropped .vdb goes to this box");
    if (!m.fillsSpace) {
      glm::vec3 centre = m.centre(), half = m.halfSizes();
      if (ImGui::DragFloat3("centre", &centre.x, 0.005f * diagonal, -diagonal * 10.0f, diagonal * 10.0f, "%.3f")) {
        moveMediumBox(m, centre - m.centre());
        changed = true;
      }
      if (ImGui::DragFloat3("half size", &half.x, 0.005f * diagonal, 0.0f, diagonal * 10.0f, "%.3f")) {
        resizeMediumBox(m, half);
        changed = true;
      }
    }
    // Logarithmic drags would stall at 0, which is a common value (no absorption): linear drags with a fine step.
    changed |= ImGui::DragFloat3("sigmaA (1/m)", &m.sigmaA.x, 0.005f, 0.0f, 1e3f, "%.3f");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("absorption coefficient per channel (RGB), 1/m");
    changed |= ImGui::DragFloat3("sigmaS (1/m)", &m.sigmaS.x, 0.005f, 0.0f, 1e3f, "%.3f");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("scattering coefficient per channel (RGB), 1/m");
    changed |= ImGui::SliderFloat("g", &m.g, -0.95f, 0.95f, "%.2f");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Henyey-Greenstein asymmetry: > 0 scatters forward");
    if (m.heterogeneous()) changed |= drawDensityGrid(m);
    ImGui::PushTextWrapPos(0.0f);  // three triples of figures are wider than the panel
    ImGui::TextDisabled("%s", describeMedium(m, diagonal).c_str());
    ImGui::PopTextWrapPos();
    if (ImGui::SmallButton("remove")) {
      media.erase(media.begin() + static_cast<std::ptrdiff_t>(i));
      // The selection follows its medium.
      if (input.selected == index) input.selected = -1;
      if (input.selected > index) --input.selected;
      changed = true;
      ImGui::PopID();
      break;
    }
    ImGui::PopID();
  }
  if (ImGui::Button("+ fog box")) {
    media.push_back(newFogBox(scene));
    changed = true;
  }
  ImGui::SameLine();
  if (ImGui::Button("+ fog everywhere")) {
    media.push_back(newFogEverywhere(scene));
    changed = true;
  }
  const ImVec4 errorColour(1.0f, 0.4f, 0.4f, 1.0f);
  if (!error.empty()) ImGui::TextColored(errorColour, "%s", error.c_str());
  // Smoke from a .vdb: onto the selected box, else the first box, else a new one (densityTarget).
  ImGui::Separator();
  ImGui::InputText(".vdb", &input.vdbPath);
  ImGui::InputText("grid", &input.gridName);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("the float grid read from the file; smoke is usually 'density'");
  const int target = densityTarget(media, input.selected);
  const std::string open =
      (target < 0 ? std::string("open .vdb as a new box") : "open .vdb into '" + media[target].name + "'") +
      "###open-vdb";
  if (ImGui::Button(open.c_str())) changed |= openVdb(scene, media, input, input.vdbPath);
  ImGui::TextDisabled("or drop a .vdb on the window");
  if (!input.vdbError.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, errorColour);
    ImGui::TextWrapped("%s", input.vdbError.c_str());
    ImGui::PopStyleColor();
  }
  return changed;
}

}  // namespace vplab::ui
