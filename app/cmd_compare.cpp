// vplab compare: error metrics of an image against a reference (docs/guide.md, "Comparisons in CI"), optionally a
// heatmap of where.

#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>

#include "app/cli.h"
#include "app/commands.h"
#include "app/comparison.h"
#include "app/file_plan.h"
#include "renderer/core/text.h"
#include "renderer/image/heatmap.h"
#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"

namespace vplab::app {

namespace {

void print(const char* name, double value) {
  std::printf("%s %.9g\n", name, value);
}
void print(const char* name, std::size_t value) {
  std::printf("%s %zu\n", name, value);
}

}  // namespace

int cmdCompare(const Args& args) {
  cli::CommandLine cl(
      "vplab compare <image> <reference> [options]\n"
      "  Prints the error of <image> against <reference> (.exr, .pfm or .png), one 'name value' per line:\n"
      "  rmse, relmse = mean((I-R)^2 / (R^2 + 0.01)), energy ratios mean(I)/mean(R), means, and the counts of\n"
      "  NaN/Inf and negative pixels. Errors and means are over pixels finite in both images.\n"
      "  With any --max-* threshold the last line is PASS or FAIL (naming what failed) and FAIL exits 1.",
      {{"max-relmse", "X", "fail when relmse > X"},
       {"max-energy-error", "E", "fail when |energy_ratio - 1| > E (0.05: within 5% of the reference's energy)"},
       {"max-bad-pixels", "N", "fail when the image has more than N NaN/Inf or negative pixels"},
       {"allow-tonemapped", "", "compare a tonemapped PNG with linear radiance (EXR/PFM) anyway"},
       {"heatmap", "png", "also write a heatmap of the per-pixel relative error (viridis) with a legend"},
       {"signed", "", "heatmap of the signed difference I - R instead (blue: too dark, red: too bright)"},
       {"heatmap-max", "value", "fixed upper end of the heatmap scale (signed: +-value); default: 99th percentile"}});
  if (!cl.parse(args)) {
    std::printf("%s", cl.help().c_str());
    return 0;
  }
  cl.requirePositional(2, 2, "an image and a reference");
  if (cl.has("signed") && !cl.has("heatmap")) throw cli::CliError("--signed needs --heatmap <png>");
  float heatmapMax = cl.getFloat("heatmap-max", 0.0f);
  if (cl.has("heatmap-max") && !(heatmapMax > 0.0f)) throw cli::CliError("--heatmap-max must be a positive number");
  auto threshold = [&](const char* name) -> std::optional<double> {
    if (!cl.has(name)) return std::nullopt;
    float v = cl.getFloat(name, 0.0f);
    if (!(v >= 0.0f)) throw cli::CliError(std::string("option --") + name + " must be a number >= 0");
    return v;
  };
  std::optional<double> maxRelMse = threshold("max-relmse");
  std::optional<double> maxEnergyError = threshold("max-energy-error");
  std::optional<double> maxBadPixels = threshold("max-bad-pixels");

  const std::string& imagePath = cl.positional()[0];
  const std::string& referencePath = cl.positional()[1];
  cli::FilePlan files;
  files.input(imagePath);
  files.input(referencePath);
  if (auto heatmapPath = cl.value("heatmap")) files.output("--heatmap", *heatmapPath, cli::OutputKind::Png);
  files.check();
  bool imageLinear = isLinearFormat(imageFormatFromPath(imagePath));
  bool referenceLinear = isLinearFormat(imageFormatFromPath(referencePath));
  if (imageLinear != referenceLinear && !cl.has("allow-tonemapped"))
    throw cli::CliError((imageLinear ? referencePath : imagePath) +
                        " is a tonemapped PNG and the other image is linear radiance: their difference is the tonemap, "
                        "not the error (compare two EXR/PFM files, or pass --allow-tonemapped)");
  Image image = readImage(imagePath);
  Image reference = readImage(referencePath);
  if (image.width != reference.width || image.height != reference.height)
    // Two images that cannot be compared are a usage error, like a --ref of the wrong size (comparison.cpp).
    throw cli::CliError(imagePath + " is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                             " but reference " + referencePath + " is " + std::to_string(reference.width) + "x" +
                             std::to_string(reference.height));
  for (const std::string& line : cli::infoMismatches(readImageInfo(imagePath), readImageInfo(referencePath)))
    std::fprintf(stderr, "vplab compare: warning: %s\n", printable(line).c_str());

  ImageMetrics m = compareImages(image, reference);
  print("width", static_cast<std::size_t>(image.width));
  print("height", static_cast<std::size_t>(image.height));
  print("compared_pixels", m.comparedPixels);
  print("rmse", m.rmse);
  print("relmse", m.relMse);
  print("energy_ratio", m.energyRatioOverall);
  print("energy_ratio_r", m.energyRatio.x);
  print("energy_ratio_g", m.energyRatio.y);
  print("energy_ratio_b", m.energyRatio.z);
  print("mean_image", (m.meanImage.x + m.meanImage.y + m.meanImage.z) / 3.0);
  print("mean_reference", (m.meanReference.x + m.meanReference.y + m.meanReference.z) / 3.0);
  print("nonfinite_pixels", m.nonFinitePixels);
  print("nonfinite_reference_pixels", m.nonFiniteReferencePixels);
  print("negative_pixels", m.negativePixels);
  print("negative_reference_pixels", m.negativeReferencePixels);

  if (auto heatmapPath = cl.value("heatmap")) {
    HeatmapOptions options;
    bool isSigned = cl.has("signed");
    options.colormap = isSigned ? Colormap::Diverging : Colormap::Viridis;
    options.title = isSigned ? "I - R" : "(I-R)^2/(R^2+0.01)";
    if (cl.has("heatmap-max")) {
      options.minValue = isSigned ? -heatmapMax : 0.0f;
      options.maxValue = heatmapMax;
    }
    Image values = isSigned ? signedDifferenceImage(image, reference) : relativeErrorImage(image, reference);
    Heatmap h = writeHeatmap(*heatmapPath, values, options);
    std::fprintf(stderr, "wrote %s (%dx%d, scale %g .. %g)\n", heatmapPath->c_str(), h.width, h.height,
                 static_cast<double>(h.minValue), static_cast<double>(h.maxValue));
  }

  if (!maxRelMse && !maxEnergyError && !maxBadPixels) return 0;
  // A comparison with nothing finite to compare cannot pass.
  std::vector<std::string> failed;
  char line[160];
  if (m.comparedPixels == 0) failed.push_back("no pixel finite in both images");
  if (maxRelMse && !(m.relMse <= *maxRelMse)) {
    std::snprintf(line, sizeof line, "relmse %.6g > %g", m.relMse, *maxRelMse);
    failed.push_back(line);
  }
  double energyError = std::abs(m.energyRatioOverall - 1.0);
  if (maxEnergyError && !(energyError <= *maxEnergyError)) {
    std::snprintf(line, sizeof line, "energy error |%.6g - 1| > %g", m.energyRatioOverall, *maxEnergyError);
    failed.push_back(line);
  }
  double bad = static_cast<double>(m.nonFinitePixels + m.negativePixels);
  if (maxBadPixels && bad > *maxBadPixels) {
    std::snprintf(line, sizeof line, "bad pixels %.0f > %g", bad, *maxBadPixels);
    failed.push_back(line);
  }
  if (failed.empty()) {
    std::printf("PASS\n");
    return 0;
  }
  std::string text = "FAIL:";
  for (std::size_t i = 0; i < failed.size(); ++i) text += (i ? "; " : " ") + failed[i];
  std::printf("%s\n", text.c_str());
  return 1;
}

}  // namespace vplab::app
