#include "renderer/image/heatmap.h"

#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"

// stb_easy_font is header-only with static functions, some of which this file does not call.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace vplab {

namespace {

// Nine evenly spaced stops of matplotlib's viridis (t = 0, 1/8, ..., 1). Interpolating between them approximates the
// full 256-entry table (worst near the yellow end) and keeps its monotone lightness, which is what a heatmap needs.
constexpr std::array<Rgb8, 9> kViridis = {{{68, 1, 84},
                                           {72, 40, 120},
                                           {62, 73, 137},
                                           {49, 104, 142},
                                           {38, 130, 142},
                                           {31, 158, 137},
                                           {53, 183, 121},
                                           {110, 206, 88},
                                           {253, 231, 37}}};

// ColorBrewer RdBu (9 classes) reversed so that negative is blue and positive red, with the near-white centre at 0.5.
constexpr std::array<Rgb8, 9> kDiverging = {{{33, 102, 172},
                                             {67, 147, 195},
                                             {146, 197, 222},
                                             {209, 229, 240},
                                             {247, 247, 247},
                                             {253, 219, 199},
                                             {244, 165, 130},
                                             {214, 96, 77},
                                             {178, 24, 43}}};

constexpr Rgb8 kLegendBackground = {32, 32, 32};
constexpr Rgb8 kLegendText = {235, 235, 235};

struct Canvas {
  int width;
  int height;
  std::vector<std::uint8_t>& rgb;

  void set(int x, int y, Rgb8 c) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    rgb[i] = c[0];
    rgb[i + 1] = c[1];
    rgb[i + 2] = c[2];
  }
};

int textWidth(const std::string& text) {
  std::string copy = text;
  return stb_easy_font_width(copy.data());
}

// stb_easy_font builds glyphs from axis-aligned quads (4 vertices of x, y, z float + RGBA8 each); filling each
// quad's pixel rectangle rasterises the text without a GL context.
void drawText(Canvas& canvas, int x, int y, const std::string& text, Rgb8 color) {
  std::string copy = text;
  // A glyph is at most a few dozen 64-byte quads; a short buffer would silently drop the last characters.
  std::vector<char> vertices(copy.size() * 2048 + 64);
  int quads = stb_easy_font_print(static_cast<float>(x), static_cast<float>(y), copy.data(), nullptr, vertices.data(),
                                  static_cast<int>(vertices.size()));
  constexpr std::size_t kVertexBytes = 16;
  for (int q = 0; q < quads; ++q) {
    float v0[2], v2[2];
    std::memcpy(v0, vertices.data() + (4 * q + 0) * kVertexBytes, sizeof v0);
    std::memcpy(v2, vertices.data() + (4 * q + 2) * kVertexBytes, sizeof v2);
    int x0 = static_cast<int>(std::lround(std::min(v0[0], v2[0])));
    int x1 = static_cast<int>(std::lround(std::max(v0[0], v2[0])));
    int y0 = static_cast<int>(std::lround(std::min(v0[1], v2[1])));
    int y1 = static_cast<int>(std::lround(std::max(v0[1], v2[1])));
    for (int py = y0; py < y1; ++py)
      for (int px = x0; px < x1; ++px) canvas.set(px, py, color);
  }
}

std::string formatValue(float v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", static_cast<double>(v));
  return buffer;
}

float percentile99(std::vector<float> values) {
  if (values.empty()) return 0.0f;
  std::size_t k = static_cast<std::size_t>(std::floor(0.99 * static_cast<double>(values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

}  // namespace

const char* colormapName(Colormap map) {
  switch (map) {
    case Colormap::Viridis: return "viridis";
    case Colormap::Diverging: return "blue-white-red";
  }
  return "?";
}

Rgb8 colormapLookup(Colormap map, float t) {
  const std::array<Rgb8, 9>& table = map == Colormap::Viridis ? kViridis : kDiverging;
  float s = std::clamp(std::isnan(t) ? 0.0f : t, 0.0f, 1.0f) * static_cast<float>(table.size() - 1);
  std::size_t i = std::min(static_cast<std::size_t>(s), table.size() - 2);
  float f = s - static_cast<float>(i);
  Rgb8 out;
  for (int c = 0; c < 3; ++c)
    out[c] = static_cast<std::uint8_t>(std::lround((1.0f - f) * table[i][c] + f * table[i + 1][c]));
  return out;
}

void heatmapSize(int width, int height, int& outWidth, int& outHeight) {
  outWidth = std::max(width, kHeatmapMinWidth);
  outHeight = height + kHeatmapLegendHeight;
}

Heatmap renderHeatmap(const Image& values, const HeatmapOptions& options) {
  Heatmap h;
  heatmapSize(values.width, values.height, h.width, h.height);
  h.rgb.resize(static_cast<std::size_t>(h.width) * h.height * 3);
  Canvas canvas{h.width, h.height, h.rgb};
  for (int y = 0; y < h.height; ++y)
    for (int x = 0; x < h.width; ++x) canvas.set(x, y, kLegendBackground);

  // The scalar per pixel is the channel mean, so the mean of a relative-error heatmap is relMSE.
  std::vector<float> scalar(values.size());
  std::vector<float> finite;
  finite.reserve(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    glm::vec3 p = values.pixels[i];
    scalar[i] = (p.x + p.y + p.z) / 3.0f;
    if (isFinite(p) && std::isfinite(scalar[i]))
      finite.push_back(scalar[i]);
    else
      ++h.nonFinitePixels;
  }

  bool diverging = options.colormap == Colormap::Diverging;
  float lo = options.minValue, hi = options.maxValue;
  if (std::isnan(lo) || std::isnan(hi)) {
    if (diverging) {
      std::vector<float> magnitudes(finite.size());
      std::transform(finite.begin(), finite.end(), magnitudes.begin(), [](float v) { return std::abs(v); });
      float p = percentile99(std::move(magnitudes));
      if (std::isnan(lo)) lo = -p;
      if (std::isnan(hi)) hi = p;
    } else {
      float minimum = finite.empty() ? 0.0f : *std::min_element(finite.begin(), finite.end());
      if (std::isnan(lo)) lo = std::min(0.0f, minimum);
      if (std::isnan(hi)) hi = percentile99(finite);
    }
  }
  // A constant image (e.g. identical inputs) would give an empty range; widen it so the bar still means something.
  if (!(hi > lo)) hi = lo + 1.0f;
  h.minValue = lo;
  h.maxValue = hi;

  int offsetX = (h.width - values.width) / 2;
  for (int y = 0; y < values.height; ++y) {
    for (int x = 0; x < values.width; ++x) {
      std::size_t i = static_cast<std::size_t>(y) * values.width + x;
      bool ok = isFinite(values.pixels[i]) && std::isfinite(scalar[i]);
      canvas.set(offsetX + x, y, ok ? colormapLookup(options.colormap, (scalar[i] - lo) / (hi - lo)) : kNonFiniteRgb8);
    }
  }

  // Legend: colour bar, then the numbers under its ends (and the centre), then the title line.
  const int margin = 8, barTop = values.height + 4, barHeight = 12;
  const int barLeft = margin, barRight = h.width - margin;
  for (int x = barLeft; x < barRight; ++x) {
    Rgb8 c =
        colormapLookup(options.colormap, static_cast<float>(x - barLeft) / static_cast<float>(barRight - barLeft - 1));
    for (int y = barTop; y < barTop + barHeight; ++y) canvas.set(x, y, c);
  }
  const int numbersY = barTop + barHeight + 3;
  std::string loText = formatValue(lo);
  std::string hiText = formatValue(hi);
  drawText(canvas, barLeft, numbersY, loText, kLegendText);
  drawText(canvas, barRight - textWidth(hiText), numbersY, hiText, kLegendText);
  std::string midText = formatValue(0.5f * (lo + hi));
  drawText(canvas, (barLeft + barRight - textWidth(midText)) / 2, numbersY, midText, kLegendText);

  std::string title = options.title + " (" + colormapName(options.colormap) + ", linear)";
  if (h.nonFinitePixels > 0) title += ", " + std::to_string(h.nonFinitePixels) + " NaN/Inf in magenta";
  drawText(canvas, std::max(2, (h.width - textWidth(title)) / 2), numbersY + 12, title, kLegendText);
  return h;
}

Heatmap writeHeatmap(const std::string& path, const Image& values, const HeatmapOptions& options) {
  Heatmap h = renderHeatmap(values, options);
  writePngRgb8(path, h.width, h.height, h.rgb);
  return h;
}

}  // namespace vplab
