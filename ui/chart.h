#pragma once
// The speed-versus-accuracy chart (MANYLIGHTS.md section 10): every preview configuration tried is a point
// (frame time, relMSE against the current reference); the Pareto front joins the points no other point beats on
// both axes. The data and the front are plain functions; drawing is ImGui's.

#include "renderer/settings.h"

#include <string>
#include <vector>

namespace vplab::ui {

struct ChartPoint {
  double frameMs = 0.0;  ///< preview frame time
  double relMse = 0.0;   ///< against the reference current when the point was measured
  Settings settings;     ///< restored by a click
  std::string label;     ///< short summary shown on hover
};

/// Indices of the points on the Pareto front (minimise both frame time and relMSE), sorted by frame time.
/// A point is on the front when no other point is at least as good on both axes and better on one.
std::vector<std::size_t> paretoFront(const std::vector<ChartPoint>& points);

/// One line describing the many-light settings of a point (N, b, r, SSBC, k, shadow-map size).
std::string describeSettings(const Settings& settings);

/// Per-pass timing bar: name and milliseconds.
struct PassTiming {
  std::string name;
  double ms = 0.0;
};

/// Draws the chart into the current ImGui window (log relMSE against log frame time) and returns the index of a
/// clicked point, or -1. `highlight` marks the current configuration (-1 for none).
int drawSpeedAccuracyChart(const std::vector<ChartPoint>& points, int highlight, float width, float height);
/// Horizontal bars, one per pass, scaled to the largest.
void drawPassTimings(const std::vector<PassTiming>& passes);

}  // namespace vplab::ui
