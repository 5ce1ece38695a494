#include "evaluation/svg_chart.h"

#include "renderer/core/atomic_file.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace vplab {

namespace {

// Tableau 10: distinguishable in print and for the common colour-vision deficiencies; markers also differ by shape.
constexpr unsigned kPalette[] = {0x4e79a7, 0xf28e2b, 0xe15759, 0x76b7b2, 0x59a14f, 0xedc948, 0xb07aa1,
                                  0xff9da7, 0x9c755f, 0xbab0ac, 0x17becf, 0x6a3d9a, 0x3d3d3d, 0xbcbd22};
constexpr std::size_t kPaletteSize = sizeof kPalette / sizeof kPalette[0];

std::string svgColour(std::size_t index) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%06x", chartColourRgb(index));
  return buf;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

bool drawable(const glm::dvec2& p, bool logX, bool logY) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y)) return false;
  if (logX && p.x <= 0.0) return false;
  if (logY && p.y <= 0.0) return false;
  return true;
}

// One axis: data range -> pixel range, linear or in log10.
struct Axis {
  double lo = 0.0, hi = 1.0;  // in axis units (log10 of the data on a log axis)
  double p0 = 0.0, p1 = 1.0;  // pixels
  bool log = false;
  double toPixel(double v) const {
    double t = log ? std::log10(v) : v;
    return p0 + (t - lo) / (hi - lo) * (p1 - p0);
  }
};

Axis makeAxis(std::vector<double> values, bool logScale, double p0, double p1) {
  Axis a;
  a.log = logScale;
  a.p0 = p0;
  a.p1 = p1;
  if (values.empty()) values = logScale ? std::vector<double>{1.0, 10.0} : std::vector<double>{0.0, 1.0};
  double lo = *std::min_element(values.begin(), values.end());
  double hi = *std::max_element(values.begin(), values.end());
  if (logScale) {
    lo = std::log10(lo);
    hi = std::log10(hi);
    // Pad by a tenth of a decade (or half a decade around a single value) so markers do not sit on the frame.
    double pad = hi - lo < 1e-9 ? 0.5 : 0.05 * (hi - lo) + 0.05;
    lo -= pad;
    hi += pad;
  } else {
    double span = hi - lo;
    double pad = span < 1e-12 ? std::max(std::fabs(lo) * 0.1, 0.5) : 0.06 * span;
    lo -= pad;
    hi += pad;
  }
  a.lo = lo;
  a.hi = hi;
  return a;
}

// Marker shapes cycle with the colour index so series stay apart in greyscale too.
std::string marker(int shape, double x, double y, const std::string& colour) {
  std::ostringstream s;
  const double r = 4.0;
  switch (shape % 4) {
    case 0: s << "<circle cx=\"" << num(x) << "\" cy=\"" << num(y) << "\" r=\"" << r << "\""; break;
    case 1:
      s << "<rect x=\"" << num(x - r) << "\" y=\"" << num(y - r) << "\" width=\"" << 2 * r << "\" height=\"" << 2 * r
        << "\"";
      break;
    case 2:
      s << "<polygon points=\"" << num(x) << "," << num(y - r - 1) << " " << num(x - r - 1) << "," << num(y + r) << " "
        << num(x + r + 1) << "," << num(y + r) << "\"";
      break;
    default:
      s << "<polygon points=\"" << num(x) << "," << num(y - r - 1) << " " << num(x + r + 1) << "," << num(y) << " "
        << num(x) << "," << num(y + r + 1) << " " << num(x - r - 1) << "," << num(y) << "\"";
      break;
  }
  s << " fill=\"" << colour << "\" stroke=\"#222\" stroke-width=\"0.6\"/>";
  return s.str();
}

}  // namespace

unsigned chartColourRgb(std::size_t index) { return kPalette[index % kPaletteSize]; }

std::string axisTickLabel(double v) {
  char buf[32];
  double a = std::fabs(v);
  if (v == 0.0)
    return "0";
  else if (a >= 1e4 || a < 1e-3)
    std::snprintf(buf, sizeof buf, "%.0e", v);
  else
    std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string xmlEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') ? ' ' : c; break;
    }
  }
  return out;
}

std::vector<std::size_t> paretoFront(const std::vector<glm::dvec2>& points) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (std::isfinite(points[i].x) && std::isfinite(points[i].y)) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return points[a].x != points[b].x ? points[a].x < points[b].x : points[a].y < points[b].y;
  });
  // Sweep by increasing x: a point is on the front when its y is strictly below every y seen at a smaller-or-equal
  // x (equal points: the first one is kept, the copies are dominated by nothing but add nothing either).
  std::vector<std::size_t> front;
  double bestY = std::numeric_limits<double>::infinity();
  for (std::size_t i : order) {
    if (points[i].y < bestY) {
      front.push_back(i);
      bestY = points[i].y;
    }
  }
  return front;
}

std::vector<double> axisTicks(double lo, double hi, bool logScale, int target) {
  std::vector<double> ticks;
  if (!(lo <= hi) || !std::isfinite(lo) || !std::isfinite(hi)) return ticks;
  if (logScale) {
    if (hi <= 0.0) return ticks;
    lo = std::max(lo, hi * 1e-12);
    int d0 = static_cast<int>(std::floor(std::log10(lo)));
    int d1 = static_cast<int>(std::ceil(std::log10(hi)));
    bool fine = d1 - d0 < 3;
    for (int d = d0; d <= d1; ++d) {
      for (double m : {1.0, 2.0, 5.0}) {
        if (m != 1.0 && !fine) continue;
        double v = m * std::pow(10.0, d);
        if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) ticks.push_back(v);
      }
    }
    return ticks;
  }
  double span = hi - lo;
  if (span <= 0.0) return {lo};
  double raw = span / std::max(1, target);
  double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * mag;
    if (step >= raw) break;
  }
  // Multiples of the step computed directly (not accumulated), so 0.6 does not come out as 0.6000000000000001.
  for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k += 1.0) {
    double v = k * step;
    double digits = std::pow(10.0, std::max(0.0, -std::floor(std::log10(step))));
    ticks.push_back(std::round(v * digits) / digits);
  }
  return ticks;
}

std::string renderSvgChart(const ChartSpec& spec) {
  const double W = spec.width, H = spec.height;
  const double legendW = 190.0;
  const double left = 78.0, right = W - legendW - 16.0, top = 40.0, bottom = H - 62.0;

  std::vector<double> xs, ys;
  std::size_t hidden = 0;
  for (const ChartSeries& s : spec.series)
    for (const glm::dvec2& p : s.points) {
      if (!drawable(p, spec.logX, spec.logY)) {
        ++hidden;
        continue;
      }
      xs.push_back(p.x);
      ys.push_back(p.y);
    }
  Axis ax = makeAxis(xs, spec.logX, left, right);
  Axis ay = makeAxis(ys, spec.logY, bottom, top);

  std::ostringstream o;
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << spec.width << "\" height=\""
    << spec.height << "\" viewBox=\"0 0 " << spec.width << " " << spec.height
    << "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"12\">\n";
  o << "<title>" << xmlEscape(spec.title) << "</title>\n";
  o << "<rect x=\"0\" y=\"0\" width=\"" << spec.width << "\" height=\"" << spec.height << "\" fill=\"white\"/>\n";
  o << "<text x=\"" << num((left + right) / 2) << "\" y=\"24\" text-anchor=\"middle\" font-size=\"15\" "
    << "font-weight=\"bold\">" << xmlEscape(spec.title) << "</text>\n";

  // Grid and tick labels.
  auto axisValue = [](const Axis& a, double t) { return a.log ? std::pow(10.0, t) : t; };
  o << "<g class=\"grid\" stroke=\"#ddd\" stroke-width=\"1\">\n";
  std::vector<double> xt = axisTicks(axisValue(ax, ax.lo), axisValue(ax, ax.hi), ax.log);
  std::vector<double> yt = axisTicks(axisValue(ay, ay.lo), axisValue(ay, ay.hi), ay.log);
  for (double v : xt)
    o << "<line x1=\"" << num(ax.toPixel(v)) << "\" y1=\"" << num(top) << "\" x2=\"" << num(ax.toPixel(v)) << "\" y2=\""
      << num(bottom) << "\"/>\n";
  for (double v : yt)
    o << "<line x1=\"" << num(left) << "\" y1=\"" << num(ay.toPixel(v)) << "\" x2=\"" << num(right) << "\" y2=\""
      << num(ay.toPixel(v)) << "\"/>\n";
  o << "</g>\n";
  o << "<g class=\"axes\">\n";
  o << "<rect x=\"" << num(left) << "\" y=\"" << num(top) << "\" width=\"" << num(right - left) << "\" height=\""
    << num(bottom - top) << "\" fill=\"none\" stroke=\"#333\"/>\n";
  for (double v : xt)
    o << "<text x=\"" << num(ax.toPixel(v)) << "\" y=\"" << num(bottom + 16) << "\" text-anchor=\"middle\">"
      << xmlEscape(axisTickLabel(v)) << "</text>\n";
  for (double v : yt)
    o << "<text x=\"" << num(left - 6) << "\" y=\"" << num(ay.toPixel(v) + 4) << "\" text-anchor=\"end\">"
      << xmlEscape(axisTickLabel(v)) << "</text>\n";
  o << "<text x=\"" << num((left + right) / 2) << "\" y=\"" << num(bottom + 36) << "\" text-anchor=\"middle\">"
    << xmlEscape(spec.xLabel + (spec.logX ? " (log)" : "")) << "</text>\n";
  o << "<text x=\"18\" y=\"" << num((top + bottom) / 2) << "\" text-anchor=\"middle\" transform=\"rotate(-90 18 "
    << num((top + bottom) / 2) << ")\">" << xmlEscape(spec.yLabel + (spec.logY ? " (log)" : "")) << "</text>\n";
  o << "</g>\n";

  // The front first, so markers are drawn over it.
  std::vector<glm::dvec2> front;
  for (const glm::dvec2& p : spec.front)
    if (drawable(p, spec.logX, spec.logY)) front.push_back(p);
  if (!front.empty()) {
    o << "<g class=\"pareto-front\" fill=\"none\" stroke=\"#111\" stroke-width=\"1.4\" stroke-dasharray=\"5,3\">\n";
    // A step line: between two front points the best error reachable at a given time stays that of the faster one.
    o << "<polyline points=\"";
    for (std::size_t i = 0; i < front.size(); ++i) {
      if (i > 0) o << num(ax.toPixel(front[i].x)) << "," << num(ay.toPixel(front[i - 1].y)) << " ";
      o << num(ax.toPixel(front[i].x)) << "," << num(ay.toPixel(front[i].y)) << " ";
    }
    o << "\"/>\n</g>\n";
  }

  for (std::size_t si = 0; si < spec.series.size(); ++si) {
    const ChartSeries& s = spec.series[si];
    const std::string colour = svgColour(s.colour >= 0 ? static_cast<std::size_t>(s.colour) : si);
    int shape = s.shape >= 0 ? s.shape : static_cast<int>(si);
    o << "<g class=\"series\" data-name=\"" << xmlEscape(s.name) << "\">\n";
    std::vector<glm::dvec2> pts;
    std::vector<std::string> labels;
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      if (!drawable(s.points[i], spec.logX, spec.logY)) continue;
      pts.push_back(s.points[i]);
      labels.push_back(i < s.labels.size() ? s.labels[i] : std::string());
    }
    if (s.connect && pts.size() > 1) {
      o << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"1.6\" points=\"";
      for (const glm::dvec2& p : pts) o << num(ax.toPixel(p.x)) << "," << num(ay.toPixel(p.y)) << " ";
      o << "\"/>\n";
    }
    for (std::size_t i = 0; i < pts.size(); ++i) {
      double px = ax.toPixel(pts[i].x), py = ay.toPixel(pts[i].y);
      o << marker(shape, px, py, colour) << "\n";
      if (!labels[i].empty())
        o << "<text x=\"" << num(px + 6) << "\" y=\"" << num(py - 6) << "\" font-size=\"9\" fill=\"#333\">"
          << xmlEscape(labels[i]) << "</text>\n";
    }
    o << "</g>\n";
  }

  // Legend: one entry per series (even an empty one, so a missing measurement is visible), then the front.
  o << "<g class=\"legend\">\n";
  double lx = W - legendW, ly = top + 4;
  for (std::size_t si = 0; si < spec.series.size(); ++si) {
    const ChartSeries& s = spec.series[si];
    const std::string colour = svgColour(s.colour >= 0 ? static_cast<std::size_t>(s.colour) : si);
    o << "<g class=\"legend-entry\">" << marker(s.shape >= 0 ? s.shape : static_cast<int>(si), lx + 8, ly + 18.0 * si, colour) << "<text x=\""
      << num(lx + 20) << "\" y=\"" << num(ly + 18.0 * si + 4) << "\">" << xmlEscape(spec.series[si].name)
      << "</text></g>\n";
  }
  if (!front.empty()) {
    double y = ly + 18.0 * spec.series.size();
    o << "<g class=\"legend-entry\"><line x1=\"" << num(lx) << "\" y1=\"" << num(y) << "\" x2=\"" << num(lx + 16)
      << "\" y2=\"" << num(y) << "\" stroke=\"#111\" stroke-width=\"1.4\" stroke-dasharray=\"5,3\"/><text x=\""
      << num(lx + 20) << "\" y=\"" << num(y + 4) << "\">Pareto front</text></g>\n";
  }
  o << "</g>\n";
  if (hidden > 0)
    o << "<text class=\"note\" x=\"" << num(left) << "\" y=\"" << num(H - 8) << "\" font-size=\"11\" fill=\"#a00\">"
      << xmlEscape(std::to_string(hidden) + " point(s) not drawn (non-finite" +
                   (spec.logX || spec.logY ? " or <= 0 on a log axis" : "") + ")")
      << "</text>\n";
  o << "</svg>\n";
  return o.str();
}

void writeSvgChart(const std::string& path, const ChartSpec& spec) {
  writeFileAtomically(path, renderSvgChart(spec));
}

}  // namespace vplab
