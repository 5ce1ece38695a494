#pragma once
// The speed-versus-accuracy chart (docs/theory.md §10): every preview configuration tried is a point
// (frame time, relMSE against the current reference); the Pareto front joins the points no other point beats on
// both axes. Its colours, markers and method names are the bench's SVG charts' (evaluation/svg_chart.h), so a method
// looks the same on screen and in docs/benchmarks.md. The data, the front, the axes and the legend are plain
// functions; only drawing is ImGui's.

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

/// The bench method (one of benchMethodNames()) a preview configuration is a case of. A configuration that combines
/// levers is filed under the one that changes the image most: VSL (vslRadius > 0), then SSBC (steps > 0 with a finite
/// clamp), then clamp (finite b), then rejection; otherwise plain VPLs.
std::string chartMethod(const Settings& settings);

/// One logarithmic chart axis: the data's range in decades, padded so no marker sits on the frame and widened until
/// at least two ticks fall inside, mapped linearly (in log10) onto a pixel span.
struct LogAxis {
  double lo = 0.0, hi = 1.0;  ///< log10 of the data values at the two ends
  float p0 = 0.0f, p1 = 1.0f;  ///< pixels at lo and hi (p1 < p0 for an upward y axis)
  /// Pixel of a data value; values <= 0 (and below 10^lo) are pinned to the low end.
  float toPixel(double value) const;
  /// Data value at a pixel (the inverse of toPixel).
  double fromPixel(float pixel) const;
  /// Tick values inside the axis: decades, with 2 and 5 x 10^k when fewer than three decades are shown.
  std::vector<double> ticks() const;
};

/// The axis covering the finite, positive `values` (one decade around 1 when there are none).
LogAxis fitLogAxis(const std::vector<double>& values, float p0, float p1);

/// One legend entry: a method present in the chart and its colour (0xRRGGBB).
struct ChartLegendEntry {
  std::string method;
  unsigned rgb = 0;
};

/// The methods of `points`, each once, in benchMethodNames() order, with the bench charts' colour of each.
std::vector<ChartLegendEntry> chartLegend(const std::vector<ChartPoint>& points);

/// Index of the point measured with exactly `settings` (the current configuration), or -1.
int findChartPoint(const std::vector<ChartPoint>& points, const Settings& settings);

/// One line describing the many-light settings of a point (N, b, r, SSBC, k, shadow-map size).
std::string describeSettings(const Settings& settings);

/// Per-pass timing bar: name, milliseconds of the last change (0: the pass did not run, its result was cached) and
/// of the last time it ran.
struct PassTiming {
  std::string name;
  double ms = 0.0;
  double lastRunMs = 0.0;
};

/// Draws the chart into the current ImGui window (log relMSE against log frame time, titled axes with tick labels,
/// one colour per method, the Pareto front, a legend under the plot) and returns the index of a clicked point, or -1.
/// `highlight` marks the current configuration (-1 for none). The plot is at least 120 x 90 pixels.
int drawSpeedAccuracyChart(const std::vector<ChartPoint>& points, int highlight, float width, float height);
/// Horizontal bars, one per pass, scaled to the largest; a cached pass reads "cached" with its last time.
void drawPassTimings(const std::vector<PassTiming>& passes);

}  // namespace vplab::ui
