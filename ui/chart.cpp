#include "ui/chart.h"

#include <imgui.h>

#include "evaluation/svg_chart.h"
#include "evaluation/sweep.h"
#include "renderer/settings_json.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace vplab::ui {

std::vector<std::size_t> paretoFront(const std::vector<ChartPoint>& points) {
  // The bench's front, so the editor and the SVG charts agree on which configurations are on it.
  std::vector<glm::dvec2> xy;
  xy.reserve(points.size());
  for (const ChartPoint& p : points) xy.push_back({p.frameMs, p.relMse});
  return vplab::paretoFront(xy);
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

std::string chartMethod(const Settings& s) {
  if (s.vslRadius > 0.0f) return "vsl";
  const bool clamped = std::isfinite(s.clampBound);
  if (clamped && s.ssbcSteps > 0) return "ssbc";
  if (clamped) return "clamp";
  if (s.rejection) return "reject";
  return "vpl";
}

float LogAxis::toPixel(double value) const {
  double t = value > 0.0 ? std::clamp(std::log10(value), lo, hi) : lo;
  return p0 + static_cast<float>((t - lo) / (hi - lo)) * (p1 - p0);
}

double LogAxis::fromPixel(float pixel) const {
  return std::pow(10.0, lo + static_cast<double>((pixel - p0) / (p1 - p0)) * (hi - lo));
}

std::vector<double> LogAxis::ticks() const { return axisTicks(std::pow(10.0, lo), std::pow(10.0, hi), true); }

LogAxis fitLogAxis(const std::vector<double>& values, float p0, float p1) {
  LogAxis a;
  a.p0 = p0;
  a.p1 = p1;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double v : values)
    if (std::isfinite(v) && v > 0.0) lo = std::min(lo, std::log10(v)), hi = std::max(hi, std::log10(v));
  if (lo > hi) {
    lo = 0.0;
    hi = 1.0;
  } else {
    // The bench charts' padding: a twentieth of the range plus a twentieth of a decade, half a decade around one value.
    double pad = hi - lo < 1e-9 ? 0.5 : 0.05 * (hi - lo) + 0.05;
    lo -= pad;
    hi += pad;
  }
  a.lo = lo;
  a.hi = hi;
  // 1-2-5 ticks are at most 0.4 decades apart, so this ends after a few steps.
  while (a.ticks().size() < 2) a.lo -= 0.1, a.hi += 0.1;
  return a;
}

std::vector<ChartLegendEntry> chartLegend(const std::vector<ChartPoint>& points) {
  std::vector<bool> present(benchMethodNames().size(), false);
  for (const ChartPoint& p : points) present[static_cast<std::size_t>(benchMethodIndex(chartMethod(p.settings)))] = true;
  std::vector<ChartLegendEntry> legend;
  for (std::size_t i = 0; i < present.size(); ++i)
    if (present[i]) legend.push_back({benchMethodNames()[i], chartColourRgb(i)});
  return legend;
}

int findChartPoint(const std::vector<ChartPoint>& points, const Settings& settings) {
  const std::string key = settingsToJson(settings);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (settingsToJson(points[i].settings) == key) return static_cast<int>(i);
  return -1;
}

namespace {

ImU32 toImColour(unsigned rgb, int alpha = 255) {
  return IM_COL32((rgb >> 16) & 0xff, (rgb >> 8) & 0xff, rgb & 0xff, alpha);
}

// The GL series' marker of the bench charts (a square), with their dark outline.
void drawMarker(ImDrawList* draw, ImVec2 c, ImU32 colour) {
  const float r = 4.0f;
  draw->AddRectFilled(ImVec2(c.x - r, c.y - r), ImVec2(c.x + r, c.y + r), colour);
  draw->AddRect(ImVec2(c.x - r, c.y - r), ImVec2(c.x + r, c.y + r), IM_COL32(20, 20, 20, 255));
}

const ImU32 kAxisText = IM_COL32(190, 190, 190, 255);
const ImU32 kGrid = IM_COL32(60, 60, 68, 255);
const ImU32 kFront = IM_COL32(230, 230, 230, 200);
const ImU32 kCurrent = IM_COL32(255, 255, 255, 255);

}  // namespace

int drawSpeedAccuracyChart(const std::vector<ChartPoint>& points, int highlight, float width, float height) {
  width = std::max(width, 120.0f);
  height = std::max(height, 90.0f);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("chart", ImVec2(width, height));
  const bool hovered = ImGui::IsItemHovered();
  const bool clicked = ImGui::IsItemClicked();
  draw->AddRectFilled(origin, ImVec2(origin.x + width, origin.y + height), IM_COL32(25, 25, 30, 255));
  if (points.empty()) {
    draw->AddText(ImVec2(origin.x + 8, origin.y + 8), IM_COL32(200, 200, 200, 255),
                  "No points yet: render a reference,\nthen try preview settings.");
    return -1;
  }
  // Room for the y title above the plot, y tick labels left of it, x tick labels and the x title under it.
  const float line = ImGui::GetTextLineHeight();
  const float left = origin.x + ImGui::CalcTextSize("5e-05").x + 10.0f, right = origin.x + width - 12.0f;
  const float top = origin.y + line + 8.0f, bottom = origin.y + height - 2.0f * line - 10.0f;
  std::vector<double> times, errors;
  for (const ChartPoint& p : points) times.push_back(p.frameMs), errors.push_back(p.relMse);
  // Both axes logarithmic: frame times and errors span decades between configurations.
  const LogAxis ax = fitLogAxis(times, left, right), ay = fitLogAxis(errors, bottom, top);
  auto toScreen = [&](const ChartPoint& p) { return ImVec2(ax.toPixel(p.frameMs), ay.toPixel(p.relMse)); };

  // Grid and tick labels; a label that would overlap the previous one is left out (its grid line stays).
  float lastLabelEnd = -1e30f;
  for (double v : ax.ticks()) {
    float x = ax.toPixel(v);
    draw->AddLine(ImVec2(x, top), ImVec2(x, bottom), kGrid);
    std::string text = axisTickLabel(v);
    ImVec2 size = ImGui::CalcTextSize(text.c_str());
    float x0 = std::clamp(x - 0.5f * size.x, origin.x, origin.x + width - size.x);
    if (x0 < lastLabelEnd + 4.0f) continue;
    draw->AddText(ImVec2(x0, bottom + 3.0f), kAxisText, text.c_str());
    lastLabelEnd = x0 + size.x;
  }
  float lastLabelTop = 1e30f;
  for (double v : ay.ticks()) {
    float y = ay.toPixel(v);
    draw->AddLine(ImVec2(left, y), ImVec2(right, y), kGrid);
    std::string text = axisTickLabel(v);
    ImVec2 size = ImGui::CalcTextSize(text.c_str());
    float y0 = y - 0.5f * size.y;
    if (y0 + size.y > lastLabelTop - 1.0f) continue;
    draw->AddText(ImVec2(left - 5.0f - size.x, y0), kAxisText, text.c_str());
    lastLabelTop = y0;
  }
  draw->AddRect(ImVec2(left, top), ImVec2(right, bottom), IM_COL32(150, 150, 150, 255));
  draw->AddText(ImVec2(origin.x + 4.0f, origin.y + 3.0f), kAxisText, "relMSE vs reference (log scale)");
  const char* xTitle = "preview frame time [ms] (log scale)";
  draw->AddText(ImVec2(0.5f * (left + right - ImGui::CalcTextSize(xTitle).x), bottom + line + 6.0f), kAxisText,
                xTitle);

  // The front as the bench draws it, a step line: between two front points the best error reachable in a given
  // time stays that of the faster one.
  std::vector<std::size_t> front = paretoFront(points);
  for (std::size_t i = 1; i < front.size(); ++i) {
    ImVec2 a = toScreen(points[front[i - 1]]), b = toScreen(points[front[i]]);
    draw->AddLine(a, ImVec2(b.x, a.y), kFront, 1.5f);
    draw->AddLine(ImVec2(b.x, a.y), b, kFront, 1.5f);
  }

  int hoveredIndex = -1;
  float bestDistance = 8.0f * 8.0f;
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  for (std::size_t i = 0; i < points.size(); ++i) {
    ImVec2 p = toScreen(points[i]);
    drawMarker(draw, p, toImColour(chartColourRgb(static_cast<std::size_t>(benchMethodIndex(chartMethod(points[i].settings))))));
    float dx = p.x - mouse.x, dy = p.y - mouse.y;
    if (hovered && dx * dx + dy * dy < bestDistance) {
      bestDistance = dx * dx + dy * dy;
      hoveredIndex = static_cast<int>(i);
    }
  }
  if (highlight >= 0 && highlight < static_cast<int>(points.size()))
    draw->AddCircle(toScreen(points[static_cast<std::size_t>(highlight)]), 8.0f, kCurrent, 16, 2.0f);
  if (hoveredIndex >= 0) {
    const ChartPoint& p = points[static_cast<std::size_t>(hoveredIndex)];
    draw->AddCircle(toScreen(p), 7.0f, IM_COL32(255, 255, 255, 160), 16, 1.0f);
    ImGui::BeginTooltip();
    ImGui::Text("%s: %.2f ms   relMSE %.4g", chartMethod(p.settings).c_str(), p.frameMs, p.relMse);
    ImGui::TextUnformatted(p.label.c_str());
    if (hoveredIndex == highlight) ImGui::TextDisabled("the current settings");
    ImGui::TextDisabled("click to restore these settings");
    ImGui::EndTooltip();
  }

  // Legend: one entry per method present, then the two marks; entries wrap to the chart's width.
  const float legendStart = ImGui::GetCursorPosX();
  float used = 0.0f;
  auto entry = [&](const char* id, ImU32 colour, const std::string& text) {
    const float w = ImGui::GetFrameHeight() * 0.6f + ImGui::GetStyle().ItemInnerSpacing.x + ImGui::CalcTextSize(text.c_str()).x;
    if (used > 0.0f && used + w + ImGui::GetStyle().ItemSpacing.x <= width)
      ImGui::SameLine(), used += ImGui::GetStyle().ItemSpacing.x;
    else
      ImGui::SetCursorPosX(legendStart), used = 0.0f;
    ImVec4 c = ImGui::ColorConvertU32ToFloat4(colour);
    const float side = ImGui::GetFrameHeight() * 0.6f;
    ImGui::ColorButton(id, c, ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoDragDrop, ImVec2(side, side));
    ImGui::SameLine(0.0f, ImGui::GetStyle().ItemInnerSpacing.x);
    ImGui::TextUnformatted(text.c_str());
    used += w;
  };
  for (const ChartLegendEntry& e : chartLegend(points)) entry(("##legend-" + e.method).c_str(), toImColour(e.rgb), e.method);
  entry("##front", kFront, "Pareto front");
  if (highlight >= 0) entry("##current", kCurrent, "ringed: current settings");
  return clicked ? hoveredIndex : -1;
}

void drawPassTimings(const std::vector<PassTiming>& passes) {
  double largest = 1e-6;
  for (const PassTiming& p : passes) largest = std::max(largest, p.ms);
  for (const PassTiming& p : passes) {
    char overlay[64];
    if (p.ms > 0.0)
      std::snprintf(overlay, sizeof overlay, "%.2f ms", p.ms);
    else if (p.lastRunMs > 0.0)
      std::snprintf(overlay, sizeof overlay, "cached (%.2f ms to run)", p.lastRunMs);
    else
      std::snprintf(overlay, sizeof overlay, "cached");
    ImGui::ProgressBar(static_cast<float>(p.ms / largest), ImVec2(180.0f, 0.0f), overlay);
    ImGui::SameLine();
    ImGui::TextUnformatted(p.name.c_str());
  }
}

}  // namespace vplab::ui
