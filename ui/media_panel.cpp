#include "ui/media_panel.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

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
  std::string text = "mean free path " + triple(m.meanFreePath()) + " m\noptical depth across the scene " +
                     triple(m.sigmaT() * sceneDiagonal);
  if (!m.fillsSpace) {
    const glm::vec3 half = m.halfSizes();
    text += "\nalong the box's longest edge " + triple(m.sigmaT() * 2.0f * std::max({half.x, half.y, half.z}));
  }
  return text;
}

bool drawMediaPanel(const Scene& scene, std::vector<Medium>& media, const std::string& error) {
  bool changed = false;
  if (media.empty()) ImGui::TextDisabled("no media");
  const float diagonal = std::max(scene.geometryBounds.diagonal(), 1e-3f);
  for (std::size_t i = 0; i < media.size(); ++i) {
    Medium& m = media[i];
    ImGui::PushID(static_cast<int>(i));
    ImGui::Text("%s: %s", m.name.c_str(), m.fillsSpace ? "all space" : "box");
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
    ImGui::TextDisabled("%s", describeMedium(m, diagonal).c_str());
    if (ImGui::SmallButton("remove")) {
      media.erase(media.begin() + static_cast<std::ptrdiff_t>(i));
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
  if (!error.empty()) ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.4f, 1.0f), "%s", error.c_str());
  return changed;
}

}  // namespace vplab::ui
