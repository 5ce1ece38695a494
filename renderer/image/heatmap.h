#pragma once
// Error heatmaps: a per-pixel scalar (the channel mean of an error image) through a perceptual colormap, with a legend
// strip below the picture that shows the colour bar, its numbers and what is plotted. Viridis for magnitudes (relative
// error), a blue-white-red diverging map for signed differences (blue: too dark, red: too bright).

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "renderer/image/image.h"
#include "renderer/image/tonemap.h"

namespace vplab {

enum class Colormap {
  Viridis,    ///< matplotlib's viridis: perceptually uniform, readable in grey and by colour-blind viewers
  Diverging,  ///< ColorBrewer RdBu reversed: blue (negative) - white (0) - red (positive)
};

const char* colormapName(Colormap map);
/// Colour at t in [0, 1] (clamped), interpolated linearly between the table's stops in sRGB.
Rgb8 colormapLookup(Colormap map, float t);

/// Height in pixels of the legend strip under the picture.
inline constexpr int kHeatmapLegendHeight = 46;
/// The output is at least this wide so the legend text fits; a narrower picture is centred.
inline constexpr int kHeatmapMinWidth = 256;

struct HeatmapOptions {
  Colormap colormap = Colormap::Viridis;
  /// Values mapped to the two ends of the colour bar. NaN: taken from the data, robust to fireflies: [0, 99th
  /// percentile] for viridis (the minimum if some values are negative), [-p, p] with p the 99th percentile of |v|
  /// for the diverging map. Values outside are clamped to the end colours.
  float minValue = std::numeric_limits<float>::quiet_NaN();
  float maxValue = std::numeric_limits<float>::quiet_NaN();
  std::string title = "per-pixel error";  ///< what is plotted, printed in the legend (ASCII)
};

struct Heatmap {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< packed 8-bit sRGB rows, top first
  float minValue = 0.0f;          ///< the range actually used
  float maxValue = 0.0f;
  std::size_t nonFinitePixels = 0;  ///< drawn magenta and reported in the legend
};

/// Output size for a picture of width x height: max(width, kHeatmapMinWidth) x (height + kHeatmapLegendHeight).
void heatmapSize(int width, int height, int& outWidth, int& outHeight);

/// Colours the channel mean of each pixel of values (for relativeErrorImage that mean is the pixel's share of
/// relMSE) and draws the legend.
Heatmap renderHeatmap(const Image& values, const HeatmapOptions& options);
/// renderHeatmap, then a PNG; throws ImageIoError naming the file on failure.
Heatmap writeHeatmap(const std::string& path, const Image& values, const HeatmapOptions& options);

}  // namespace vplab
