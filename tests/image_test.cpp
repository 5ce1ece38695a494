#include <gtest/gtest.h>
#include <sys/wait.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>

#include "renderer/core/sampling.h"
#include "renderer/image/heatmap.h"
#include "renderer/image/image_io.h"
#include "renderer/image/metrics.h"
#include "renderer/image/tonemap.h"
#include "renderer/offline/emitter_mask.h"
#include "renderer/offline/path_tracer.h"
#include "tests/test_scenes.h"
#include "tests/test_tmp.h"

namespace vplab {

namespace {

// Values that exercise sign, magnitude and position: a swapped row or channel shows up as a mismatch.
Image gradientImage(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.at(x, y) = glm::vec3(0.01f * x + 0.5f * y, std::pow(2.0f, static_cast<float>(x - y)), -0.25f + 0.125f * x);
  return img;
}

void expectSameImage(const Image& a, const Image& b, float tolerance) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(a.at(x, y)[c], b.at(x, y)[c], tolerance) << x << "," << y << " c" << c;
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string floatBytes(float v, bool bigEndian) {
  char b[4];
  std::memcpy(b, &v, 4);
  if (bigEndian) std::swap(b[0], b[3]), std::swap(b[1], b[2]);
  return std::string(b, 4);
}

}  // namespace

TEST(ImageIo, ExrRoundTripIsExact) {
  Image img = gradientImage(7, 5);
  std::string path = test::tmpPath("round.exr");
  writeImage(path, img);
  expectSameImage(readImage(path), img, 0.0f);
}

TEST(ImageIo, PfmRoundTripIsExact) {
  Image img = gradientImage(6, 4);
  std::string path = test::tmpPath("round.pfm");
  writeImage(path, img);
  expectSameImage(readImage(path), img, 0.0f);
}

TEST(ImageIo, PfmStoresRowsBottomUpAndReadsBothByteOrders) {
  // A 2x2 hand-written file: the first stored row is the bottom of the picture.
  for (bool bigEndian : {false, true}) {
    std::string data = std::string("PF\n2 2\n") + (bigEndian ? "1.0" : "-1.0") + "\n";
    const float bottom[6] = {1, 2, 3, 4, 5, 6}, top[6] = {7, 8, 9, 10, 11, 12};
    for (float v : bottom) data += floatBytes(v, bigEndian);
    for (float v : top) data += floatBytes(v, bigEndian);
    std::string path = test::tmpPath(bigEndian ? "be.pfm" : "le.pfm");
    writeBytes(path, data);
    Image img = readImage(path);
    ASSERT_EQ(img.width, 2);
    ASSERT_EQ(img.height, 2);
    EXPECT_EQ(img.at(0, 0), glm::vec3(7, 8, 9)) << "big endian: " << bigEndian;
    EXPECT_EQ(img.at(1, 0), glm::vec3(10, 11, 12));
    EXPECT_EQ(img.at(0, 1), glm::vec3(1, 2, 3));
    EXPECT_EQ(img.at(1, 1), glm::vec3(4, 5, 6));
  }
}

TEST(ImageIo, GreyPfmIsReplicated) {
  std::string data = "Pf\n1 1\n-1.0\n" + floatBytes(0.75f, false);
  std::string path = test::tmpPath("grey.pfm");
  writeBytes(path, data);
  EXPECT_EQ(readImage(path).at(0, 0), glm::vec3(0.75f));
}

TEST(ImageIo, PngRoundTripWithinQuantisation) {
  Image img(16, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) img.at(x, y) = glm::vec3(x / 15.0f, y / 7.0f, 0.5f * (x + y) / 22.0f);
  std::string path = test::tmpPath("round.png");
  writeImage(path, img);
  Image back = readImage(path);
  ASSERT_EQ(back.width, 16);
  ASSERT_EQ(back.height, 8);
  for (std::size_t i = 0; i < img.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      // Half an 8-bit step in sRGB, mapped back through the transfer function's slope at this value.
      float encoded = srgbFromLinear(img.pixels[i][c]);
      float step = linearFromSrgb(std::min(1.0f, encoded + 0.5f / 255.0f)) -
                   linearFromSrgb(std::max(0.0f, encoded - 0.5f / 255.0f));
      EXPECT_NEAR(back.pixels[i][c], img.pixels[i][c], step + 1e-6f) << i << " c" << c;
    }
}

TEST(ImageIo, PngAppliesExposureClampAndMarksNonFinite) {
  Image img(4, 1);
  img.at(0, 0) = glm::vec3(0.25f);  // +1 stop -> 0.5 linear
  img.at(1, 0) = glm::vec3(-1.0f, 7.0f, 0.0f);
  img.at(2, 0) = glm::vec3(std::numeric_limits<float>::quiet_NaN(), 0.1f, 0.1f);
  img.at(3, 0) = glm::vec3(0.1f, std::numeric_limits<float>::infinity(), 0.1f);
  std::string path = test::tmpPath("exposure.png");
  writeImage(path, img, 1.0f);
  Image back = readImage(path);
  EXPECT_NEAR(back.at(0, 0).x, 0.5f, 0.005f);
  EXPECT_EQ(back.at(1, 0), glm::vec3(0.0f, 1.0f, 0.0f));
  EXPECT_EQ(back.at(2, 0), glm::vec3(1.0f, 0.0f, 1.0f));
  EXPECT_EQ(back.at(3, 0), glm::vec3(1.0f, 0.0f, 1.0f));
}

TEST(ImageIo, MissingFileThrowsWithItsName) {
  for (const char* ext : {".exr", ".pfm", ".png"}) {
    std::string path = test::tmpPath(std::string("does_not_exist") + ext);
    try {
      readImage(path);
      FAIL() << "no exception for " << path;
    } catch (const ImageIoError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

TEST(ImageIo, GarbageFileThrowsWithItsName) {
  for (const char* ext : {".exr", ".pfm", ".png"}) {
    std::string path = test::tmpPath(std::string("garbage") + ext);
    writeBytes(path, "this is not an image at all, just some text\n");
    try {
      readImage(path);
      FAIL() << "no exception for " << path;
    } catch (const ImageIoError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

TEST(ImageIo, TruncatedPfmAndUnknownExtensionThrow) {
  std::string path = test::tmpPath("short.pfm");
  writeBytes(path, "PF\n4 4\n-1.0\n" + floatBytes(1.0f, false));
  EXPECT_THROW(readImage(path), ImageIoError);
  EXPECT_THROW(readImage(test::tmpPath("picture.bmp")), ImageIoError);
  EXPECT_THROW(writeImage(test::tmpPath("picture.jpg"), Image(1, 1)), ImageIoError);
}

TEST(ImageTonemap, SrgbRoundTripAndKnownValues) {
  for (int i = 0; i <= 1000; ++i) {
    float v = i / 1000.0f;
    EXPECT_NEAR(linearFromSrgb(srgbFromLinear(v)), v, 1e-5f) << v;
  }
  EXPECT_FLOAT_EQ(srgbFromLinear(0.0f), 0.0f);
  EXPECT_FLOAT_EQ(srgbFromLinear(1.0f), 1.0f);
  EXPECT_NEAR(srgbFromLinear(0.5f), 0.735357f, 1e-5f);  // IEC 61966-2-1
  EXPECT_NEAR(linearFromSrgb(0.5f), 0.214041f, 1e-5f);
  EXPECT_NEAR(srgbFromLinear(0.002f), 0.002f * 12.92f, 1e-7f);  // linear toe
  EXPECT_FLOAT_EQ(exposureScale(-2.0f), 0.25f);
  EXPECT_EQ(tonemapPixel(glm::vec3(2.0f, -1.0f, 0.25f), 1.0f), (Rgb8{255, 0, 188}));
}

// The tonemap finds a pixel's byte by a search over the thresholds between bytes: it must give the byte of the sRGB
// formula itself, here for every 256th float in [0, 1] and the 8 floats on either side of each byte's threshold.
TEST(Tonemap, ThresholdSearchGivesTheFormulasBytes) {
  auto formula = [](float v) { return quantize8(srgbFromLinear(v)); };
  auto check = [&](std::uint32_t bits) {
    const float v = std::bit_cast<float>(bits);
    ASSERT_EQ(tonemapPixel(glm::vec3(v), 0.0f)[0], formula(v)) << v;
  };
  const std::uint32_t one = std::bit_cast<std::uint32_t>(1.0f);
  for (std::uint32_t bits = 0; bits <= one; bits += 256) check(bits);
  int switches = 0;
  for (std::uint32_t bits = 1; bits <= one; bits += 1u << 10) {
    // Where the byte changes inside a step, the floats around the change.
    if (formula(std::bit_cast<float>(bits - 1)) == formula(std::bit_cast<float>(std::min(one, bits + (1u << 10)))))
      continue;
    ++switches;
    for (std::uint32_t b = bits - 1; b <= std::min(one, bits + (1u << 10)); ++b) check(b);
  }
  EXPECT_GE(switches, 255);
  EXPECT_EQ(tonemapPixel(glm::vec3(-0.0f, 1e30f, 0.5f), 0.0f), (Rgb8{0, 255, formula(0.5f)}));
}

TEST(ImageMetrics, IdenticalImagesHaveZeroError) {
  Image img = gradientImage(8, 8);
  ImageMetrics m = compareImages(img, img);
  EXPECT_EQ(m.comparedPixels, 64u);
  EXPECT_EQ(m.rmse, 0.0);
  EXPECT_EQ(m.relMse, 0.0);
  EXPECT_DOUBLE_EQ(m.energyRatioOverall, 1.0);
}

TEST(ImageMetrics, ConstantOffsetHasKnownErrors) {
  Image ref(4, 4, glm::vec3(0.1f, 0.2f, 0.3f));
  Image img(4, 4, glm::vec3(0.2f, 0.3f, 0.4f));
  ImageMetrics m = compareImages(img, ref);
  EXPECT_NEAR(m.rmse, 0.1, 1e-6);
  double expected = (0.01 / (0.01 + 0.01) + 0.01 / (0.04 + 0.01) + 0.01 / (0.09 + 0.01)) / 3.0;
  EXPECT_NEAR(m.relMse, expected, 1e-6);
  EXPECT_NEAR(m.energyRatio.x, 2.0, 1e-6);
  EXPECT_NEAR(m.energyRatio.y, 1.5, 1e-6);
  EXPECT_NEAR(m.energyRatio.z, 4.0 / 3.0, 1e-6);
  EXPECT_NEAR(m.energyRatioOverall, 0.9 / 0.6, 1e-6);
  EXPECT_NEAR(m.meanImage.z, 0.4, 1e-6);
  EXPECT_NEAR(m.meanReference.x, 0.1, 1e-6);
}

TEST(ImageMetrics, HalfEnergyFromDarkenedHalf) {
  // Clamping that removes half of the light shows as an energy ratio of 0.5.
  Image ref(2, 2, glm::vec3(1.0f));
  Image img = ref;
  img.at(0, 0) = img.at(1, 0) = glm::vec3(0.0f);
  ImageMetrics m = compareImages(img, ref);
  EXPECT_NEAR(m.energyRatioOverall, 0.5, 1e-12);
  EXPECT_NEAR(m.rmse, std::sqrt(0.5), 1e-7);
  EXPECT_NEAR(m.relMse, 0.5 / 1.01, 1e-7);
}

TEST(ImageMetrics, NonFiniteAndNegativePixelsAreCountedAndExcluded) {
  Image ref(3, 2, glm::vec3(0.5f));
  Image img = ref;
  img.at(0, 0) = glm::vec3(std::numeric_limits<float>::quiet_NaN(), 0.5f, 0.5f);
  img.at(1, 0) = glm::vec3(0.5f, -std::numeric_limits<float>::infinity(), 0.5f);
  img.at(2, 0) = glm::vec3(0.5f, 0.5f, -0.5f);
  ref.at(2, 1) = glm::vec3(std::numeric_limits<float>::infinity());
  ImageMetrics m = compareImages(img, ref);
  EXPECT_EQ(m.nonFinitePixels, 2u);
  EXPECT_EQ(m.nonFiniteReferencePixels, 1u);
  EXPECT_EQ(m.negativePixels, 1u);
  EXPECT_EQ(m.negativeReferencePixels, 0u);
  EXPECT_EQ(m.comparedPixels, 3u);
  EXPECT_TRUE(std::isfinite(m.relMse));
  EXPECT_NEAR(m.rmse, std::sqrt(1.0 / 9.0), 1e-7);  // one channel off by 1 among 3 pixels x 3 channels
}

TEST(ImageMetrics, SizeMismatchThrows) {
  EXPECT_THROW(compareImages(Image(4, 4), Image(4, 5)), std::invalid_argument);
  EXPECT_THROW(relativeErrorImage(Image(3, 4), Image(4, 4)), std::invalid_argument);
  EXPECT_THROW(signedDifferenceImage(Image(3, 4), Image(4, 4)), std::invalid_argument);
}

TEST(ImageMetrics, ErrorImagesAgreeWithTheMetrics) {
  Image ref = gradientImage(5, 3);
  Image img = ref;
  img.at(2, 1) += glm::vec3(0.5f, -0.25f, 0.0f);
  Image rel = relativeErrorImage(img, ref);
  Image diff = signedDifferenceImage(img, ref);
  double sum = 0.0;
  for (const glm::vec3& p : rel.pixels) sum += static_cast<double>(p.x) + p.y + p.z;
  EXPECT_NEAR(sum / (3.0 * rel.size()), compareImages(img, ref).relMse, 1e-7);
  EXPECT_NEAR(diff.at(2, 1).x, 0.5f, 1e-6f);
  EXPECT_NEAR(diff.at(2, 1).y, -0.25f, 1e-6f);
  EXPECT_EQ(diff.at(0, 0), glm::vec3(0.0f));
}

TEST(ImageHeatmap, ColormapEnds) {
  EXPECT_EQ(colormapLookup(Colormap::Viridis, 0.0f), (Rgb8{68, 1, 84}));
  EXPECT_EQ(colormapLookup(Colormap::Viridis, 1.0f), (Rgb8{253, 231, 37}));
  EXPECT_EQ(colormapLookup(Colormap::Viridis, 2.0f), (Rgb8{253, 231, 37}));
  Rgb8 mid = colormapLookup(Colormap::Diverging, 0.5f);
  EXPECT_GT(mid[0], 240);
  EXPECT_GT(mid[2], 240);
  Rgb8 low = colormapLookup(Colormap::Diverging, 0.0f), high = colormapLookup(Colormap::Diverging, 1.0f);
  EXPECT_GT(low[2], low[0]);    // negative is blue
  EXPECT_GT(high[0], high[2]);  // positive is red
}

TEST(ImageHeatmap, WritesPngWithLegendStrip) {
  Image ref(64, 32, glm::vec3(0.5f));
  Image img = ref;
  for (int x = 0; x < 64; ++x) img.at(x, 10) = glm::vec3(0.5f + x / 64.0f);
  img.at(3, 3) = glm::vec3(std::numeric_limits<float>::quiet_NaN());
  HeatmapOptions options;
  options.title = "relMSE";
  std::string path = test::tmpPath("heatmap.png");
  Heatmap h = writeHeatmap(path, relativeErrorImage(img, ref), options);
  EXPECT_EQ(h.nonFinitePixels, 1u);
  EXPECT_EQ(h.minValue, 0.0f);
  EXPECT_GT(h.maxValue, 0.0f);

  Image png = readImage(path);
  int w = 0, hgt = 0;
  heatmapSize(64, 32, w, hgt);
  ASSERT_EQ(png.width, w);
  ASSERT_EQ(png.height, hgt);
  EXPECT_EQ(png.width, kHeatmapMinWidth);
  EXPECT_EQ(png.height, 32 + kHeatmapLegendHeight);

  int offsetX = (w - 64) / 2;
  EXPECT_EQ(png.at(offsetX + 3, 3), glm::vec3(1.0f, 0.0f, 1.0f));  // NaN shown as magenta
  // Zero error maps to the low end of viridis, the worst row to the high end.
  glm::vec3 zero = linearFromSrgb(glm::vec3(68, 1, 84) / 255.0f);
  expectSameImage(
      [&] {
        Image p(1, 1);
        p.at(0, 0) = png.at(offsetX, 0);
        return p;
      }(),
      [&] {
        Image p(1, 1);
        p.at(0, 0) = zero;
        return p;
      }(),
      1e-3f);
  EXPECT_GT(png.at(offsetX + 63, 10).y, 0.6f);

  // Legend: the colour bar runs from dark purple (left) to yellow (right), and white text lies below it.
  int barY = 32 + 8;
  EXPECT_LT(png.at(10, barY).y, 0.05f);
  EXPECT_GT(png.at(w - 10, barY).y, 0.7f);
  int textPixels = 0;
  for (int y = barY + 8; y < hgt; ++y)
    for (int x = 0; x < w; ++x)
      if (png.at(x, y).x > 0.7f && png.at(x, y).y > 0.7f && png.at(x, y).z > 0.7f) ++textPixels;
  EXPECT_GT(textPixels, 100);
}

TEST(ImageHeatmap, SignedDifferenceIsSymmetricAroundZero) {
  Image ref(8, 8, glm::vec3(1.0f));
  Image img = ref;
  img.at(0, 0) = glm::vec3(0.0f);  // too dark
  img.at(7, 7) = glm::vec3(2.0f);  // too bright
  HeatmapOptions options;
  options.colormap = Colormap::Diverging;
  options.minValue = -1.0f;
  options.maxValue = 1.0f;
  Heatmap h = renderHeatmap(signedDifferenceImage(img, ref), options);
  int offsetX = (h.width - 8) / 2;
  auto pixel = [&](int x, int y) {
    std::size_t i = (static_cast<std::size_t>(y) * h.width + offsetX + x) * 3;
    return Rgb8{h.rgb[i], h.rgb[i + 1], h.rgb[i + 2]};
  };
  EXPECT_EQ(pixel(0, 0), colormapLookup(Colormap::Diverging, 0.0f));
  EXPECT_EQ(pixel(7, 7), colormapLookup(Colormap::Diverging, 1.0f));
  EXPECT_EQ(pixel(3, 3), colormapLookup(Colormap::Diverging, 0.5f));
}

namespace {

// Runs the vplab executable and returns its exit status; stdout goes to output.
int runVplab(const std::string& arguments, std::string& output) {
  std::string command = std::string(VPLAB_BINARY) + " " + arguments + " 2>/dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return -1;
  char buffer[256];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST(ImageCompareCli, PrintsMetricsAndFailsOnMismatch) {
  ASSERT_TRUE(std::filesystem::exists(VPLAB_BINARY)) << "the test suite builds vplab: " << VPLAB_BINARY;
  Image ref(8, 8, glm::vec3(0.1f, 0.2f, 0.3f));
  Image img(8, 8, glm::vec3(0.2f, 0.3f, 0.4f));
  std::string a = test::tmpPath("cli_a.exr"), b = test::tmpPath("cli_b.pfm"), small = test::tmpPath("cli_small.exr");
  std::string heatmap = test::tmpPath("cli_heatmap.png");
  writeImage(a, img);
  writeImage(b, ref);
  writeImage(small, Image(4, 8));
  std::filesystem::remove(heatmap);

  std::string output;
  ASSERT_EQ(runVplab("compare " + a + " " + b + " --heatmap " + heatmap, output), 0);
  std::map<std::string, double> values;
  std::istringstream lines(output);
  std::string name;
  double value;
  while (lines >> name >> value) values[name] = value;
  ImageMetrics expected = compareImages(img, ref);
  ASSERT_TRUE(values.count("relmse") && values.count("rmse") && values.count("energy_ratio")) << output;
  EXPECT_NEAR(values["relmse"], expected.relMse, 1e-7);
  EXPECT_NEAR(values["rmse"], expected.rmse, 1e-7);
  EXPECT_NEAR(values["energy_ratio"], 1.5, 1e-6);
  EXPECT_EQ(values["nonfinite_pixels"], 0.0);
  EXPECT_EQ(readImage(heatmap).height, 8 + kHeatmapLegendHeight);

  std::string ignored;
  EXPECT_EQ(runVplab("compare " + small + " " + b, ignored), 2);  // images that cannot be compared: usage
  EXPECT_EQ(runVplab("compare " + test::tmpPath("missing.exr") + " " + b, ignored), 3);  // an unreadable input
  EXPECT_EQ(runVplab("compare " + a, ignored), 2);
}


TEST(ImageMetrics, EmitterMaskLeavesTheEmitterOutOfTheMeanRatio) {
  // A lit surface 5 % too dark, next to an emitter 100x brighter, scaled like the rest: over all pixels the ratio
  // is dominated by the emitter; with the emitter excluded it is the surface's 0.95.
  Image ref(4, 1, glm::vec3(1.0f));
  ref.at(0, 0) = glm::vec3(300.0f);
  Image img = ref;
  for (int x = 1; x < 4; ++x) img.at(x, 0) *= 0.95f;
  PixelMask emitter(4, 1);
  emitter.at(0, 0) = 1;
  EXPECT_GT(compareImages(img, ref).energyRatioOverall, 0.999);
  EXPECT_NEAR(meanRatioExcludingEmitters(img, ref, emitter), 0.95, 1e-6);
  EXPECT_EQ(compareImagesExcluding(img, ref, emitter).comparedPixels, 3u);
  EXPECT_EQ(dilateMask(emitter, 1).count(), 2u);
  EXPECT_EQ(blockMask(dilateMask(emitter, 1), 2).count(), 1u);
  EXPECT_THROW(compareImagesExcluding(img, ref, PixelMask(2, 2)), std::invalid_argument);
  EXPECT_NEAR(unitMeanScale(ref, emitter), 1.0, 1e-6);
}

TEST(ImageMetrics, EmitterMaskCoversTheCornellLightAndItsEdge) {
  auto cornell = test::loadAssetScene("cornell-box");
  const int size = 32;
  PixelMask bare = emitterMask(cornell->embree(), size, size, 0);
  PixelMask mask = emitterMask(cornell->embree(), size, size);
  EXPECT_GT(bare.count(), 0u) << "the ceiling light is in view";
  EXPECT_LT(bare.count(), std::size_t(size * size / 10));
  EXPECT_GT(mask.count(), bare.count());
  Settings s = test::smallReferenceSettings(size, 16);
  Image direct = renderReference(*cornell, s).image;
  // The pixels the mask keeps are lit surfaces, far dimmer than the emitter (the brightest pixel of the image).
  double brightest = 0.0, brightestKept = 0.0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double l = luminance(direct.at(x, y));
      brightest = std::max(brightest, l);
      if (!mask.at(x, y)) brightestKept = std::max(brightestKept, l);
    }
  EXPECT_LT(brightestKept, 0.2 * brightest);
}

}  // namespace vplab
