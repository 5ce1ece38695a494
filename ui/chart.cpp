#include "ui/chart.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace vplab::ui {

std::vector<std::size_t> paretoFront(const std::vector<ChartPoint>& points) {
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  // Sorted by time (ties by error), a point is on the front exactly when its error is below every earlier one's.
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (points[a].frameMs != points[b].frameMs) return points[a].frameMs < points[b].frameMs;
    return points[a].relMse < points[b].relMse;
  });
  std::vector<std::size_t> front;
  double bestError = std::numeric_limits<double>::infinity();
  for (std::size_t i : order) {
    if (points[i].relMse < bestError) {
      front.push_back(i);
      bestError = points[i].relMse;
    }
  }
  return front;
}

std::string describeSettings(const Settings& s) {
  char b[64];
  if (std::isinf(s.clampBound))
    std::snprintf(b, sizeof b, "inf");
  else
    std::snprintf(b, sizeof b, "%g", s.clampBound);
  char line[256];
  std::snprintf(line, sizeof line, "N=%d bounces=%d b=%s r=%g ssbc=%d k=%d sm=%d%s", s.vplCount, s.vplMaxBounces, b,
                s.vslRadius, s.ssbcSteps, s.interleave, s.shadowMapSize, s.rejection ? " rejection" : "");
  return line;
}

int drawSpeedAccuracyChart(const std::vector<ChartPoint>& points, int highlight, float width, float height) {
  ImDrawList* draw = ImGui::GetWindowDrawList();
  ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("chart", ImVec2(width, height));
  const bool hovered = ImGui::IsItemHovered();
  const bool clicked = ImGui::IsItemClicked();
  draw->AddRectFilled(origin, ImVec2(origin.x + width, origin.y + height), IM_COL32(25, 25, 30, 255));
  if (points.empty()) {
    draw->AddText(ImVec2(origin.x + 8, origin.y + 8), IM_COL32(200, 200, 200, 255),
                  "No points yet: render a reference,\nthen try preview settings.");
    return -1;
  }
  // Both axes logarithmic: frame times and errors span decades between configurations.
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (const ChartPoint& p : points) {
    double v[2] = {std::log10(std::max(p.frameMs, 1e-3)), std::log10(std::max(p.relMse, 1e-12))};
    for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
  }
  for (int a = 0; a < 2; ++a) {
    double pad = std::max(0.05, 0.1 * (hi[a] - lo[a]));
    lo[a] -= pad;
    hi[a] += pad;
  }
  const float margin = 36.0f;
  auto toScreen = [&](const ChartPoint& p) {
    double x = (std::log10(std::max(p.frameMs, 1e-3)) - lo[0]) / (hi[0] - lo[0]);
    double y = (std::log10(std::max(p.relMse, 1e-12)) - lo[1]) / (hi[1] - lo[1]);
    return ImVec2(origin.x + margin + static_cast<float>(x) * (width - margin - 8.0f),
                  origin.y + height - margin + static_cast<float>(-y) * (height - margin - 8.0f));
  };
  char text[64];
  std::snprintf(text, sizeof text, "%.3g ms", std::pow(10.0, lo[0]));
  draw->AddText(ImVec2(origin.x + margin, origin.y + height - 18), IM_COL32(160, 160, 160, 255), text);
  std::snprintf(text, sizeof text, "%.3g ms", std::pow(10.0, hi[0]));
  draw->AddText(ImVec2(origin.x + width - 70, origin.y + height - 18), IM_COL32(160, 160, 160, 255), text);
  std::snprintf(text, sizeof text, "relMSE %.2g", std::pow(10.0, hi[1]));
  draw->AddText(ImVec2(origin.x + 4, origin.y + 4), IM_COL32(160, 160, 160, 255), text);
  std::snprintf(text, sizeof text, "%.2g", std::pow(10.0, lo[1]));
  draw->AddText(ImVec2(origin.x + 4, origin.y + height - margin - 14), IM_COL32(160, 160, 160, 255), text);

  std::vector<std::size_t> front = paretoFront(points);
  for (std::size_t i = 1; i < front.size(); ++i)
    draw->AddLine(toScreen(points[front[i - 1]]), toScreen(points[front[i]]), IM_COL32(255, 200, 60, 255), 2.0f);

  int hoveredIndex = -1;
  float bestDistance = 8.0f * 8.0f;
  ImVec2 mouse = ImGui::GetIO().MousePos;
  for (std::size_t i = 0; i < points.size(); ++i) {
    ImVec2 p = toScreen(points[i]);
    bool onFront = std::find(front.begin(), front.end(), i) != front.end();
    ImU32 colour = static_cast<int>(i) == highlight ? IM_COL32(90, 220, 120, 255)
                   : onFront                        ? IM_COL32(255, 200, 60, 255)
                                                    : IM_COL32(140, 170, 230, 255);
    draw->AddCircleFilled(p, 4.0f, colour);
    float dx = p.x - mouse.x, dy = p.y - mouse.y;
    if (hovered && dx * dx + dy * dy < bestDistance) {
      bestDistance = dx * dx + dy * dy;
      hoveredIndex = static_cast<int>(i);
    }
  }
  if (hoveredIndex >= 0) {
    const ChartPoint& p = points[static_cast<std::size_t>(hoveredIndex)];
    ImGui::BeginTooltip();
    ImGui::Text("%.2f ms   relMSE %.4g", p.frameMs, p.relMse);
    ImGui::TextUnformatted(p.label.c_str());
    ImGui::TextDisabled("click to restore these settings");
    ImGui::EndTooltip();
  }
  return clicked ? hoveredIndex : -1;
}

void drawPassTimings(const std::vector<PassTiming>& passes) {
  double largest = 1e-6;
  for (const PassTiming& p : passes) largest = std::max(largest, p.ms);
  for (const PassTiming& p : passes) {
    char overlay[64];
    std::snprintf(overlay, sizeof overlay, "%.2f ms", p.ms);
    ImGui::ProgressBar(static_cast<float>(p.ms / largest), ImVec2(180.0f, 0.0f), overlay);
    ImGui::SameLine();
    ImGui::TextUnformatted(p.name.c_str());
  }
}

}  // namespace vplab::ui
