// The AVX2 paths of the HDR pipeline (core/simd.h) against the scalar ones: the same bytes, the
// same statistics, bit for bit, on images made of every edge case the loops branch on.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/simd.h"
#include "hdr/bloom.h"
#include "hdr/blur.h"
#include "hdr/exposure.h"
#include "hdr/pipeline.h"
#include "hdr/transfer.h"

namespace brdf {
namespace {

// Runs `run` with the AVX2 paths off, then on, and restores the setting; skips the test on
// a processor without AVX2 (there is only one path there).
template <typename Run>
auto BothPaths(Run&& run) {
  const bool was = SetAvx2Enabled(true);
  const bool available = Avx2Enabled();
  SetAvx2Enabled(false);
  auto scalar = run();
  SetAvx2Enabled(true);
  auto vector = run();
  SetAvx2Enabled(was);
  return std::make_pair(available, std::make_pair(std::move(scalar), std::move(vector)));
}

bool SameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// A scene of dim noise, black and negative pixels, alpha 0, a few sources far above the bloom
// threshold, and (when `extremes`) infinite, huge and subnormal channels: the log's fallback,
// the quantizer's clipping, the tone map's black pixels.
Image EdgeScene(int width, int height, bool extremes) {
  Image image(width, height);
  std::mt19937 random(11);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      float* p = image.pixel(x, y);
      const float base = 0.05f * uniform(random);
      for (int c = 0; c < 3; ++c) p[c] = base * (0.5f + uniform(random));
      const int pattern = (x * 7 + y * 3) % 37;
      if (pattern == 0) p[0] = p[1] = p[2] = 0.0f;
      if (pattern == 1) p[1] = -0.5f;                  // negative luminance
      if (pattern == 2) p[0] = 200.0f, p[1] = 150.0f;  // a bright speck
      if ((x + y * 5) % 31 == 0) p[3] = 0.0f;
      if (extremes && pattern == 3) p[2] = std::numeric_limits<float>::infinity();
      if (extremes && pattern == 4) p[0] = p[1] = p[2] = 1e-39f;  // subnormal
      if (extremes && pattern == 5) p[0] = p[1] = p[2] = 3e38f;
    }
  }
  for (int dy = -3; dy <= 3; ++dy) {
    for (int dx = -3; dx <= 3; ++dx) {
      float* p = image.pixel(std::clamp(width / 3 + dx, 0, width - 1),
                             std::clamp(height / 2 + dy, 0, height - 1));
      p[0] = 500.0f, p[1] = 300.0f, p[2] = 100.0f;
    }
  }
  return image;
}

TEST(HdrAvx2, QuantizerGivesTheScalarCodes) {
  std::vector<float> values = {0.0f,
                               -0.0f,
                               -1.0f,
                               1.0f,
                               2.0f,
                               1e-45f,
                               1e-39f,
                               std::nextafter(1.0f, 0.0f),
                               std::numeric_limits<float>::infinity(),
                               -std::numeric_limits<float>::infinity(),
                               std::nanf("")};
  std::mt19937 random(5);
  std::uniform_real_distribution<float> unit(-0.1f, 1.1f);
  for (int i = 0; i < 20000; ++i) values.push_back(unit(random));
  for (const char* curve : {"srgb", "1", "2.2", "0.25", "8"}) {
    const TransferCurve transfer = TransferCurve::Parse(curve);
    const Quantizer8 quantize(transfer);
    // Every threshold and its neighbours: where a rounding decision flips.
    std::vector<float> all = values;
    for (int k = 0; k < 255; ++k) {
      const float threshold = static_cast<float>(transfer.Decode((k + 0.5) / 255.0));
      all.insert(all.end(),
                 {std::nextafter(threshold, 0.0f), threshold, std::nextafter(threshold, 1.0f)});
    }
    std::vector<uint8_t> expected(all.size());
    for (size_t i = 0; i < all.size(); ++i) expected[i] = quantize(all[i]);
    const auto [available, paths] = BothPaths([&] {
      std::vector<uint8_t> codes(all.size());
      quantize.EncodeMany(all.data(), static_cast<int64_t>(all.size()), codes.data());
      return codes;
    });
    if (!available) GTEST_SKIP() << "no AVX2 on this processor";
    EXPECT_EQ(paths.first, expected) << curve;
    EXPECT_EQ(paths.second, expected) << curve;
    // Planes: the same values read as red, green and blue thirds.
    const int64_t n = static_cast<int64_t>(all.size()) / 3;
    const auto planes =
        BothPaths([&] {
          std::vector<uint8_t> rgb(3 * n);
          quantize.EncodePlanes(all.data(), all.data() + n, all.data() + 2 * n, n, rgb.data());
          return rgb;
        }).second;
    for (int64_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(planes.first[3 * i + c], expected[c * n + i]) << curve << " " << i;
        ASSERT_EQ(planes.second[3 * i + c], expected[c * n + i]) << curve << " " << i;
      }
    }
  }
}

TEST(HdrAvx2, StatisticsAreTheScalarBits) {
  for (const auto& [width, height] : {std::pair{1031, 37}, std::pair{8, 3}, std::pair{13, 5}}) {
    for (const auto& [extremes, delta] : {std::pair{false, 1e-4}, std::pair{true, 1e-4},
                                          std::pair{true, 1e-42}}) {  // a subnormal argument
      const Image scene = EdgeScene(width, height, extremes);
      const double d = delta;
      const auto [available, paths] = BothPaths([&] { return MeasureSceneLuminance(scene, d); });
      if (!available) GTEST_SKIP() << "no AVX2 on this processor";
      const SceneLuminance& a = paths.first;
      const SceneLuminance& b = paths.second;
      EXPECT_EQ(std::memcmp(&a.log_average, &b.log_average, sizeof(double)), 0);
      EXPECT_EQ(std::memcmp(&a.log_average_lit, &b.log_average_lit, sizeof(double)), 0);
      EXPECT_EQ(a.max, b.max);
      EXPECT_EQ(a.pixels, b.pixels);
      EXPECT_EQ(a.black_pixels, b.black_pixels);
      if (width > 100) {
        EXPECT_GT(a.black_pixels, 0);  // the scene reaches that branch
      }
    }
  }
}

TEST(HdrAvx2, BrightPassAndBlursAreTheScalarBits) {
  for (const auto& [width, height] : {std::pair{97, 61}, std::pair{200, 9}, std::pair{11, 7}}) {
    const Image scene = EdgeScene(width, height, false);
    const auto [available, bright] = BothPaths([&] { return BrightPass(scene, 1.0, 0.7).rgba; });
    if (!available) GTEST_SKIP() << "no AVX2 on this processor";
    EXPECT_TRUE(SameBits(bright.first, bright.second)) << width << "x" << height;
    const auto down = BothPaths([&] { return BrightPassDown(scene, 1.0, 0.7).rgba; }).second;
    EXPECT_TRUE(SameBits(down.first, down.second)) << width << "x" << height;
    for (double sigma : {0.8, 3.0, 13.0}) {
      const auto blurred = BothPaths([&] { return GaussianBlur(scene, sigma).rgba; }).second;
      EXPECT_TRUE(SameBits(blurred.first, blurred.second))
          << width << "x" << height << ", Gaussian sigma " << sigma;
    }
    for (int levels : {1, 2, 4}) {
      const auto blurred = BothPaths([&] { return DualFilterBlur(scene, levels).rgba; }).second;
      EXPECT_TRUE(SameBits(blurred.first, blurred.second))
          << width << "x" << height << ", " << levels << " levels";
    }
  }
}

// The fused bright pass skips the row segments the statistics pass's peaks prove dark: the
// same bytes as without peaks, on both paths, at thresholds where some segments are dark and
// some not (NaN and infinite channels inside the dark ones).
TEST(HdrAvx2, BrightPassDownSkipsOnlyWhatThePeaksProveDark) {
  const int width = 333, height = 41;  // six segments, the last one partial
  for (bool extremes : {false, true}) {
    Image scene = EdgeScene(width, height, extremes);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        float* p = scene.pixel(x, y);
        // Bright specks only in columns 100..179 of rows 10..19.
        const bool window = x >= 100 && x < 180 && y >= 10 && y < 20;
        if (!window && p[0] == 200.0f) p[0] = p[1] = 0.03f;
      }
    }
    scene.pixel(20, 5)[1] = std::numeric_limits<float>::quiet_NaN();
    scene.pixel(300, 30)[0] = -std::numeric_limits<float>::infinity();
    for (double threshold : {0.0, 1.0, 50.0}) {
      const auto [available, paths] = BothPaths([&] {
        std::vector<float> peaks(PeakFloats(width, height));
        MeasureSceneLuminance(scene, 1e-4, peaks.data());
        return std::make_pair(BrightPassDown(scene, threshold, 0.7, peaks.data()).rgba, peaks);
      });
      if (!available) GTEST_SKIP() << "no AVX2 on this processor";
      const std::vector<float> plain = BrightPassDown(scene, threshold, 0.7).rgba;
      EXPECT_TRUE(SameBits(paths.first.first, plain)) << threshold;
      EXPECT_TRUE(SameBits(paths.second.first, plain)) << threshold;
      EXPECT_EQ(paths.first.second, paths.second.second);  // the peaks (a zero's sign aside)
      if (threshold == 1.0) {  // the skip is reached, and so is the bright pass
        int dark = 0;
        const std::vector<float>& peaks = paths.second.second;
        for (int64_t i = 0; i < static_cast<int64_t>(peaks.size()); i += 3) {
          const float exposed[3] = {peaks[i] * 0.7f, peaks[i + 1] * 0.7f, peaks[i + 2] * 0.7f};
          dark += PixelLuminance(exposed) <= 1.0f;
        }
        EXPECT_GT(dark, 0);
        EXPECT_LT(dark, static_cast<int>(peaks.size() / 3));
      }
    }
  }
}

TEST(HdrAvx2, PipelineGivesTheScalarBytes) {
  for (const auto& [width, height] :
       {std::pair{97, 61}, std::pair{64, 48}, std::pair{5, 3}, std::pair{1031, 41}}) {
    for (bool extremes : {false, true}) {
      const Image scene = EdgeScene(width, height, extremes);
      for (BlurKind bloom : {BlurKind::kNone, BlurKind::kGaussian, BlurKind::kDual}) {
        for (ToneOperator op : {ToneOperator::kReinhardExtended, ToneOperator::kReinhard,
                                ToneOperator::kExposure, ToneOperator::kNone}) {
          ToneOptions options;
          options.bloom = bloom;
          options.bloom_sigma = 6.0;
          options.bloom_strength = 0.3;
          options.tone_operator = op;
          if (op == ToneOperator::kNone) options.transfer = TransferCurve::Parse("2.2");
          const auto [available, paths] =
              BothPaths([&] { return RunTonePipeline(scene, options); });
          if (!available) GTEST_SKIP() << "no AVX2 on this processor";
          const ToneResult& a = paths.first;
          const ToneResult& b = paths.second;
          EXPECT_EQ(a.exposure, b.exposure);
          EXPECT_EQ(a.mapping.key_scale, b.mapping.key_scale);
          EXPECT_EQ(a.mapping.white, b.mapping.white);
          EXPECT_TRUE(a.display.rgb == b.display.rgb)
              << width << "x" << height << (extremes ? " with extremes" : "") << ", bloom "
              << BlurKindName(bloom) << ", " << ToneOperatorName(op);
        }
      }
    }
  }
}

}  // namespace
}  // namespace brdf
