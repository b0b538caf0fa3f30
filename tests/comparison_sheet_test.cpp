// The A | B sheets' colour error (render/comparison_sheet.h) on planted images: a hue shift that
// keeps the luminance is seen, a sharp peak does not swamp the statistics, the unlit back of a
// sphere is left out, a channel near black does not turn into thousands of per cent, and A and
// B share one exposure.
#include "render/comparison_sheet.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/colour.h"
#include "hdr/image.h"

namespace brdf {
namespace {

constexpr int kSize = 40;

// A "sphere" image: every pixel inside the disc of radius kSize/2 has alpha 1 and the value
// `inside(x, y)`; alpha 0 around it.
template <typename F>
Image Disc(F inside) {
  Image image(kSize, kSize, 0.0f);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const double u = (x + 0.5) / kSize * 2 - 1, v = (y + 0.5) / kSize * 2 - 1;
      if (u * u + v * v >= 1.0) continue;
      const Rgb value = inside(x, y);
      float* pixel = image.pixel(x, y);
      for (int c = 0; c < 3; ++c) pixel[c] = static_cast<float>(value[c]);
      pixel[3] = 1.0f;
    }
  }
  return image;
}

TEST(ComparisonSheet, ColourErrorIsPerChannelRelative) {
  const Rgb b(0.1, 0.1, 0.5);
  // Blue moved into green at equal luminance (Rec. 709 weights): luminance alone sees nothing.
  const double d_blue = -0.2, d_green = 0.2 * 0.0722 / 0.7152;
  const Rgb a = b + Rgb(0.0, d_green, d_blue);
  EXPECT_NEAR(Luminance(a), Luminance(b), 1e-12);
  EXPECT_NEAR(ColourRelativeError(a, b, 0.0), 0.4, 1e-12);  // the blue channel's 0.2 / 0.5
  EXPECT_EQ(ColourRelativeError(b, b, 0.01), 0.0);
  // A channel near black is measured against the floor, not against itself.
  EXPECT_NEAR(ColourRelativeError(Rgb(0.5, 0.5, 0.01), Rgb(0.5, 0.5, 0.0), 0.05), 0.2, 1e-12);
  EXPECT_EQ(ColourRelativeError(Rgb(0.1, 0, 0), Rgb::Zero(), 0.0), 1.0);
  EXPECT_EQ(ColourRelativeError(Rgb::Zero(), Rgb::Zero(), 0.0), 0.0);

  // Over a sphere: the hue shift everywhere gives 0.4 in every statistic.
  const ComparisonSheet sheet =
      CompareRadiance(Disc([&](int, int) { return a; }), Disc([&](int, int) { return b; }));
  EXPECT_NEAR(sheet.median_relative_error, 0.4, 1e-6);
  EXPECT_NEAR(sheet.max_relative_error, 0.4, 1e-6);
  EXPECT_NEAR(sheet.mean_relative_error, 0.4, 1e-6);
  EXPECT_EQ(sheet.colour_bar_top, 0.5);
}

TEST(ComparisonSheet, SharpPeakDoesNotSwampTheStatistics) {
  // B: grey 1 with a 3 x 3 highlight of 1000; A: 10 % brighter off the highlight, equal on it.
  auto peak = [](int x, int y) { return std::abs(x - 20) <= 1 && std::abs(y - 20) <= 1; };
  const Image b = Disc([&](int x, int y) { return Rgb::Constant(peak(x, y) ? 1000.0 : 1.0); });
  const Image a = Disc([&](int x, int y) { return Rgb::Constant(peak(x, y) ? 1000.0 : 1.1); });
  const ComparisonSheet sheet = CompareRadiance(a, b);
  // Relative to B's maximum the error would read 0.1 / (1 % of 1000) = 0.01.
  EXPECT_NEAR(sheet.reference_luminance, 1.0, 1e-6);
  EXPECT_NEAR(sheet.median_relative_error, 0.1, 1e-6);
  EXPECT_NEAR(sheet.p90_relative_error, 0.1, 1e-6);
  EXPECT_NEAR(sheet.max_relative_error, 0.1, 1e-6);
}

TEST(ComparisonSheet, StatisticsRunOverTheLitSphere) {
  // The lower half black in both (a directional light from above): left out, so the error of
  // the lit half is not halved by perfect matches of black.
  const Image b = Disc([](int, int y) { return y < kSize / 2 ? Rgb(0.2, 0.3, 0.4) : Rgb::Zero(); });
  const Image a = Disc([](int, int y) { return y < kSize / 2 ? Rgb(0.2, 0.3, 0.6) : Rgb::Zero(); });
  const ComparisonSheet sheet = CompareRadiance(a, b);
  int64_t upper = 0, all = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      if (b.pixel(x, y)[3] == 0.0f) continue;
      ++all;
      upper += y < kSize / 2;
    }
  }
  EXPECT_EQ(sheet.lit_pixels, upper);
  EXPECT_LT(sheet.lit_pixels, all);
  EXPECT_NEAR(sheet.median_relative_error, 0.5, 1e-6);  // blue 0.2 / 0.4
  EXPECT_NEAR(sheet.mean_relative_error, 0.5, 1e-6);
}

TEST(ComparisonSheet, OneExposureForBoth) {
  // A twice as bright as B: after the shared tone pipeline A's pixels stay brighter (each
  // exposed on its own, both would look the same).
  const Image b = Disc([](int, int) { return Rgb::Constant(0.2); });
  const Image a = Disc([](int, int) { return Rgb::Constant(0.4); });
  const ComparisonSheet sheet = ToneMapAndCompare(a, b, ToneOptions{}, "A", "B");
  ASSERT_GT(sheet.sheet.width, 2 * kSize);
  const int y = 28 + kSize / 2;  // below the label strip, through the centre
  const uint8_t* row = sheet.sheet.rgb.data() + static_cast<int64_t>(y) * sheet.sheet.width * 3;
  const int a_green = row[(kSize / 2) * 3 + 1], b_green = row[(kSize + kSize / 2) * 3 + 1];
  EXPECT_GT(a_green, b_green + 20);
  EXPECT_NEAR(sheet.median_relative_error, 1.0, 1e-6);
}

}  // namespace
}  // namespace brdf
