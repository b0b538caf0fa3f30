// Tone-mapping operators and display encoding against direct computations (DESIGN §8).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/errors.h"
#include "hdr/bloom.h"
#include "hdr/blur.h"
#include "hdr/exposure.h"
#include "hdr/pipeline.h"
#include "hdr/tone_map.h"
#include "hdr/transfer.h"

namespace brdf {
namespace {

// A 3x2 image with a wide range of luminances and distinct chroma; the brightest is grey.
Image SmallScene() {
  Image image(3, 2);
  const float rgb[6][3] = {{0.01f, 0.02f, 0.03f}, {0.2f, 0.1f, 0.05f}, {1.0f, 1.0f, 1.0f},
                           {4.0f, 2.0f, 1.0f},    {0.0f, 0.0f, 0.0f},  {40.0f, 40.0f, 40.0f}};
  for (int i = 0; i < 6; ++i) {
    for (int c = 0; c < 3; ++c) image.rgba[i * 4 + c] = rgb[i][c];
  }
  return image;
}

double Y(const float* rgb) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

TEST(ToneMap, ReinhardGlobalMatchesDirectComputation) {
  const Image scene = SmallScene();
  const double key = 0.18, delta = 1e-4;
  // Reinhard et al. 2002, eqs. (1)-(3), written out independently of the library.
  double log_sum = 0.0;
  for (int i = 0; i < 6; ++i) log_sum += std::log(delta + Y(&scene.rgba[i * 4]));
  const double log_average = std::exp(log_sum / 6);

  const SceneLuminance measured = MeasureSceneLuminance(scene, delta);
  EXPECT_NEAR(measured.log_average, log_average, 1e-6 * log_average);
  Image mapped = scene;
  ApplyToneMapping(&mapped, PlanToneMapping(ToneOperator::kReinhard, measured, key, 0.0));
  for (int i = 0; i < 6; ++i) {
    const float* in = &scene.rgba[i * 4];
    const double world = Y(in);
    const double scaled = key / log_average * world;
    const double display = scaled / (1 + scaled);
    for (int c = 0; c < 3; ++c) {
      const double expected = world > 0 ? std::clamp(in[c] * display / world, 0.0, 1.0) : 0.0;
      EXPECT_NEAR(mapped.rgba[i * 4 + c], expected, 1e-5) << "pixel " << i << " channel " << c;
    }
    EXPECT_EQ(mapped.rgba[i * 4 + 3], 1.0f);  // alpha kept
  }
}

TEST(ToneMap, ExtendedWithWhiteOneIsIdentityOnLuminance) {
  Image image(16, 1);
  for (int x = 0; x < 16; ++x) {
    const float v = x / 16.0f;
    image.pixel(x, 0)[0] = v;
    image.pixel(x, 0)[1] = 0.5f * v;
    image.pixel(x, 0)[2] = 0.25f * v;
  }
  ToneMapping mapping;
  mapping.tone_operator = ToneOperator::kReinhardExtended;
  mapping.key_scale = 1.0;
  mapping.white = 1.0;
  Image mapped = image;
  ApplyToneMapping(&mapped, mapping);
  for (int x = 0; x < 16; ++x) {
    EXPECT_NEAR(Y(mapped.pixel(x, 0)), Y(image.pixel(x, 0)), 1e-6) << x;
  }
}

TEST(ToneMap, SceneMaximumMapsToOneWhenWhiteIsTheMaximum) {
  Image scene = SmallScene();
  const SceneLuminance measured = MeasureSceneLuminance(scene);
  // White "auto" is the scene maximum in key-scaled units.
  const ToneMapping mapping =
      PlanToneMapping(ToneOperator::kReinhardExtended, measured, 0.18, /*white=*/0.0);
  EXPECT_NEAR(mapping.white, mapping.key_scale * measured.max, 1e-9 * mapping.white);
  EXPECT_DOUBLE_EQ(ReinhardExtendedMap(mapping.white, mapping.white), 1.0);
  // The brightest pixel (grey, so no channel clips) maps to display luminance 1.
  Image mapped = scene;
  ApplyToneMapping(&mapped, mapping);
  EXPECT_NEAR(Y(mapped.pixel(2, 1)), 1.0, 1e-5);
  // Every other pixel maps below 1.
  for (int i = 0; i < 5; ++i) EXPECT_LT(Y(&mapped.rgba[i * 4]), 1.0);
}

TEST(ToneMap, ExponentialHasSlopeExposureAtZeroAndStaysBelowOne) {
  for (double exposure : {0.25, 1.0, 3.0, 40.0}) {
    const double h = 1e-7;
    EXPECT_NEAR((ExponentialMap(h, exposure) - ExponentialMap(0.0, exposure)) / h, exposure,
                1e-5 * exposure);
    EXPECT_EQ(ExponentialMap(0.0, exposure), 0.0);
    double previous = -1.0;
    for (double x = 0.0; x * exposure <= 30.0; x += 0.01 / exposure) {
      const double y = ExponentialMap(x, exposure);
      EXPECT_GE(y, 0.0);
      EXPECT_LT(y, 1.0);
      EXPECT_GT(y, previous);
      previous = y;
    }
  }
}

TEST(Transfer, SrgbKneeIsContinuousAndRoundTrips) {
  const double knee = 0.0031308;
  // IEC 61966-2-1: both pieces meet at the knee (to the precision of the published constants).
  EXPECT_NEAR(12.92 * knee, 1.055 * std::pow(knee, 1 / 2.4) - 0.055, 1e-6);
  EXPECT_NEAR(SrgbEncode(knee), 12.92 * knee, 1e-12);
  // The published constants leave a step of 3e-8 at the knee, far below an 8-bit code.
  EXPECT_NEAR(SrgbEncode(knee * (1 + 1e-9)), SrgbEncode(knee), 1e-7);
  EXPECT_NEAR(SrgbEncode(1.0), 1.0, 1e-12);
  for (int i = 0; i <= 100000; ++i) {
    const double x = i / 100000.0;
    ASSERT_NEAR(SrgbDecode(SrgbEncode(x)), x, 1e-6) << x;
    const TransferCurve gamma = TransferCurve::Parse("2.2");
    ASSERT_NEAR(gamma.Decode(gamma.Encode(x)), x, 1e-6) << x;
  }
}

TEST(Transfer, EightBitsRoundToNearest) {
  const Quantizer8 linear(TransferCurve::Parse("1"));
  const Quantizer8 srgb(TransferCurve::Parse("srgb"));
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    const double x = unit(random);
    // Skip values within float precision of a rounding tie.
    const double linear_code = 255 * x, srgb_code = 255 * SrgbEncode(x);
    if (std::abs(linear_code - std::floor(linear_code) - 0.5) > 1e-4) {
      ASSERT_EQ(linear(static_cast<float>(x)), std::lround(linear_code)) << x;
    }
    if (std::abs(srgb_code - std::floor(srgb_code) - 0.5) > 1e-3) {
      ASSERT_EQ(srgb(static_cast<float>(x)), std::lround(srgb_code)) << x;
    }
  }
  EXPECT_EQ(linear(0.0f), 0);
  EXPECT_EQ(linear(1.0f), 255);
  EXPECT_EQ(linear(7.0f), 255);         // clipped
  EXPECT_EQ(linear(-1.0f), 0);          // clipped
  EXPECT_EQ(linear(std::nanf("")), 0);  // never a bright NaN
  EXPECT_EQ(linear(0.49f / 255), 0);    // just below the first tie
  EXPECT_EQ(linear(0.51f / 255), 1);    // just above
}

TEST(Pipeline, AutoExposureBringsLogAverageToKey) {
  Image scene = SmallScene();
  ToneOptions options;
  options.tone_operator = ToneOperator::kNone;
  const ToneResult result = RunTonePipeline(scene, options);
  ApplyExposure(&scene, result.exposure);
  EXPECT_NEAR(MeasureSceneLuminance(scene, 1e-4 * result.exposure).log_average, options.key, 1e-5);
}

// An odd-sized scene with a few bright sources over a dim, noisy background, some black
// pixels and some of alpha 0: every edge case of the bright pass, the blurs' borders and the
// statistics.
Image BloomScene(int width, int height) {
  Image image(width, height);
  std::mt19937 random(7);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      float* p = image.pixel(x, y);
      const float base = 0.05f * uniform(random);
      for (int c = 0; c < 3; ++c) p[c] = base * (0.5f + uniform(random));
      if ((x * 7 + y * 3) % 29 == 0) p[0] = p[1] = p[2] = 0.0f;
      if ((x + y * 5) % 31 == 0) p[3] = 0.0f;
    }
  }
  const int sources[3][2] = {{width / 5, height / 3}, {width - 2, 1}, {width / 2, height - 3}};
  for (const auto& source : sources) {
    for (int dy = -2; dy <= 2; ++dy) {
      for (int dx = -2; dx <= 2; ++dx) {
        const int x = std::clamp(source[0] + dx, 0, width - 1);
        const int y = std::clamp(source[1] + dy, 0, height - 1);
        float* p = image.pixel(x, y);
        p[0] = 300.0f, p[1] = 200.0f, p[2] = 90.0f;
      }
    }
  }
  return image;
}

// The stages one after another, each over the whole image, as pipeline.h lists them.
Image8 StagedPipeline(Image image, const ToneOptions& options) {
  const SceneLuminance scene = MeasureSceneLuminance(image, options.delta);
  ApplyExposure(&image, options.exposure ? *options.exposure : AutoExposure(scene, options.key));
  if (options.bloom != BlurKind::kNone && options.bloom_strength > 0.0) {
    AddBloom(&image,
             Blur(BrightPass(image, options.bloom_threshold), options.bloom, options.bloom_sigma),
             options.bloom_strength);
  }
  const bool reinhard = options.tone_operator == ToneOperator::kReinhard ||
                        options.tone_operator == ToneOperator::kReinhardExtended;
  const SceneLuminance mapped =
      reinhard ? MeasureSceneLuminance(image, options.delta) : SceneLuminance{};
  ApplyToneMapping(&image,
                   PlanToneMapping(options.tone_operator, mapped, options.key, options.white));
  return EncodeDisplay(image, options.transfer);
}

TEST(Pipeline, FusedPassesGiveTheBytesOfTheStagesInTurn) {
  for (const auto& [width, height] : {std::pair{97, 61}, std::pair{64, 48}, std::pair{5, 3}}) {
    const Image scene = BloomScene(width, height);
    for (BlurKind bloom : {BlurKind::kNone, BlurKind::kBox, BlurKind::kGaussian, BlurKind::kKawase,
                           BlurKind::kDual}) {
      for (ToneOperator op : {ToneOperator::kReinhardExtended, ToneOperator::kReinhard,
                              ToneOperator::kExposure, ToneOperator::kNone}) {
        ToneOptions options;
        options.bloom = bloom;
        options.bloom_sigma = 4.0;
        options.bloom_strength = 0.3;
        options.tone_operator = op;
        if (op == ToneOperator::kExposure) options.exposure = 0.7;
        if (op == ToneOperator::kNone) options.transfer = TransferCurve::Parse("2.2");
        const Image8 fused = RunTonePipeline(scene, options).display;
        const Image8 staged = StagedPipeline(scene, options);
        ASSERT_EQ(fused.width, width);
        ASSERT_EQ(fused.height, height);
        EXPECT_TRUE(fused.rgb == staged.rgb) << width << "x" << height << " bloom "
                                             << BlurKindName(bloom) << ", " << ToneOperatorName(op);
      }
    }
  }
}

TEST(Pipeline, BytesDoNotDependOnTheThreadCount) {
  const Image scene = BloomScene(1031, 517);  // more rows than one statistics chunk
  ToneOptions options;
  options.bloom = BlurKind::kDual;
  const ToneResult many = RunTonePipeline(scene, options);
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const ToneResult one = RunTonePipeline(scene, options);
  EXPECT_EQ(one.exposure, many.exposure);
  EXPECT_EQ(one.mapping.key_scale, many.mapping.key_scale);
  EXPECT_TRUE(one.display.rgb == many.display.rgb);
}

TEST(Exposure, LogAverageMatchesADoubleSumOfLogs) {
  // Luminances over ten decades, as an HDR photograph spans; the pass's float logarithm must
  // not move the log-average (and so the automatic exposure) visibly.
  Image image(1000, 100);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> decades(-6.0, 4.0);
  double log_sum = 0.0, max = 0.0;
  for (int64_t i = 0; i < image.pixel_count(); ++i) {
    float* p = image.rgba.data() + 4 * i;
    p[0] = p[1] = p[2] = static_cast<float>(std::pow(10.0, decades(random)));
    const double luminance = PixelLuminance(p);
    log_sum += std::log(1e-4 + luminance);
    max = std::max(max, luminance);
  }
  const SceneLuminance scene = MeasureSceneLuminance(image, 1e-4);
  EXPECT_NEAR(scene.log_average, std::exp(log_sum / image.pixel_count()), 1e-6 * scene.log_average);
  EXPECT_EQ(scene.max, max);
  EXPECT_EQ(scene.pixels, image.pixel_count());
}

TEST(Pipeline, OptionsAreValidated) {
  ToneOptions options;
  options.key = 0.0;
  EXPECT_THROW(options.Validate(), UsageError);
  options = ToneOptions();
  options.bloom_sigma = -1.0;
  EXPECT_THROW(options.Validate(), UsageError);
  EXPECT_THROW(TransferCurve::Parse("banana"), UsageError);
  EXPECT_THROW(ParseToneOperator("drago"), UsageError);
}

}  // namespace
}  // namespace brdf
