#pragma once
// Charts of the speed-versus-accuracy sweeps (docs/theory.md §10) as standalone SVG 1.1 text, written without
// any plotting dependency: scatter/line series on linear or log axes, an optional Pareto front, a legend.
//
// The output is meant to be read by people and checked by tests: every series is one <g class="series"
// data-name="..."> group (markers and polyline), every legend entry one <g class="legend-entry">, the front one
// <g class="pareto-front">. Points that cannot be drawn (non-finite, or <= 0 on a log axis) are left out and counted in
// a note under the plot, so a chart never silently hides a bad measurement.

#include <cstddef>
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace vplab {

struct ChartSeries {
  std::string name;                 ///< legend text
  std::vector<glm::dvec2> points;   ///< (x, y) in data units
  std::vector<std::string> labels;  ///< optional per-point labels (empty, or one per point; "" for none)
  bool connect = true;              ///< join the points in the given order with a polyline
  int colour = -1;                  ///< index into the chart palette (chartColourRgb); -1: the series' position
  int shape = -1;                   ///< marker shape 0..3 (circle, square, triangle, diamond); -1: the position
};

struct ChartSpec {
  std::string title;
  std::string xLabel;
  std::string yLabel;
  bool logX = false;
  bool logY = false;
  std::vector<ChartSeries> series;
  /// Points of the Pareto front, drawn as a dashed step line in the order given (sorted by x); empty for none.
  std::vector<glm::dvec2> front;
  int width = 720;   ///< pixels
  int height = 440;  ///< pixels
};

/// Indices of the points no other point beats on both coordinates (minimising x and y): a point is on the front
/// when no other point is <= on both and < on one. Non-finite points are never on it. Sorted by x, then y.
std::vector<std::size_t> paretoFront(const std::vector<glm::dvec2>& points);

/// The chart as an SVG document (UTF-8, ASCII only). Never fails: an empty chart still has its axes and a note.
std::string renderSvgChart(const ChartSpec& spec);

/// renderSvgChart() written to a file; throws std::runtime_error naming the file when it cannot be written.
void writeSvgChart(const std::string& path, const ChartSpec& spec);

/// Escapes &, <, >, " and ' for XML text and attribute values; other control characters become spaces.
std::string xmlEscape(const std::string& text);

/// The charts' palette (Tableau 10), as 0xRRGGBB; the index wraps. The editor's chart uses it too, so a method has
/// the same colour on screen and in the bench's SVGs.
unsigned chartColourRgb(std::size_t index);

/// A tick value as printed under an axis: "%g", or "%.0e" outside [1e-3, 1e4).
std::string axisTickLabel(double value);

/// "Nice" tick values covering [lo, hi]: multiples of 1, 2 or 5 x 10^k on a linear axis (about `target` of them);
/// decades on a log axis, with 2 and 5 x 10^k added when the range spans fewer than three decades.
std::vector<double> axisTicks(double lo, double hi, bool logScale, int target = 6);

}  // namespace vplab
