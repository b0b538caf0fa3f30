// Numerical robustness (docs/reliability.md): fits on data with zeros, missing samples and an
// extreme dynamic range return finite parameters for every model and loss; a render lit by an
// environment holding NaN and infinities writes a finite PNG and says how many pixels it
// replaced.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "core/angles.h"
#include "fitters/fit.h"
#include "hdr/image_files.h"
#include "models/model_list.h"
#include "models/model_string.h"
#include "test_util.h"

namespace brdf {
namespace {

// A very sharp lobe over a dark floor (1e-7 to ~1e5 sr^-1), a third of the samples exactly 0,
// every tenth missing (and holding NaN, as a reader would leave it).
Measurement HostileData() {
  const Model truth = ParseModel("blinn-phong:rho_d=1e-6,2e-6,3e-6:rho_s=0.9:m=100000");
  Measurement measurement;
  measurement.format = "synthetic";
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int k = 0; k < 1500; ++k) {
    Sample sample;
    sample.wi = SphericalDirection(std::acos(uniform(random)), 2 * kPi * uniform(random));
    // Half the outgoing directions near the mirror direction, where the lobe lives.
    sample.wo = k % 2 == 0
                    ? SphericalDirection(std::acos(uniform(random)), 2 * kPi * uniform(random))
                    : (MirrorDirection(sample.wi) +
                       0.01 * Vec3(uniform(random) - 0.5, uniform(random) - 0.5, 0))
                          .normalized();
    if (sample.wo.z() <= 0) continue;
    sample.value = truth.Eval(sample.wi, sample.wo);
    if (k % 3 == 0) sample.value = Rgb::Zero();
    if (k % 10 == 0) {
      sample.missing = true;
      sample.value = Rgb::Constant(std::numeric_limits<double>::quiet_NaN());
    }
    measurement.samples.push_back(sample);
  }
  return measurement;
}

// Fits of every loss, plain and Cauchy, of every model with (or without) a tabulated energy
// bound to HostileData stay finite.
void ExpectFitsOnHostileDataStayFinite(bool tabulated) {
  const Measurement measurement = HostileData();
  auto expect_finite = [&](const char* model, fitters::Loss loss, fitters::Robust robust) {
    fitters::FitOptions options;
    options.loss = loss;
    options.robust = robust;
    options.max_iterations = 50;
    options.start_exponents = {4, 256, 16384};
    const fitters::FitResult fit = fitters::FitModel(measurement, model, options);
    const std::string what = std::string(model) + " loss " + fitters::LossName(loss) + " robust " +
                             fitters::RobustName(robust);
    for (const double param : fit.model.params()) EXPECT_TRUE(std::isfinite(param)) << what;
    EXPECT_TRUE(std::isfinite(fit.metrics.rmse)) << what;
    EXPECT_GT(fit.skipped, 0u) << what;  // the missing samples were left out
  };
  int fitted = 0;
  models::ForEachModel([&](auto model) {
    using M = decltype(model);
    bool model_tabulated = false;
    M::ForEachLobe([&](auto lobe, auto) { model_tabulated |= decltype(lobe)::kTabulatedBound; });
    if (model_tabulated != tabulated) return;
    for (const fitters::Loss loss : {fitters::Loss::kL2, fitters::Loss::kLog,
                                     fitters::Loss::kCosineL2, fitters::Loss::kSqrt}) {
      expect_finite(M::kName, loss, fitters::Robust::kNone);
    }
    expect_finite(M::kName, fitters::Loss::kL2, fitters::Robust::kCauchy);
    ++fitted;
  });
  EXPECT_GT(fitted, 1);
}

// The diffuse and power-cosine models; the microfacet rungs below (slower: ten starts each).
TEST(NumericalRobustness, FitsOnZerosMissingSamplesAndHugeRangeStayFinite) {
  ExpectFitsOnHostileDataStayFinite(false);
}
TEST(NumericalRobustness, MicrofacetFitsOnZerosMissingSamplesAndHugeRangeStayFinite) {
  ExpectFitsOnHostileDataStayFinite(true);
}

// An environment of radiance 1 with a few broken pixels and, optionally, one very bright one.
std::string WriteEnvironment(const testing::ScratchDir& dir, const std::string& name,
                             float bright) {
  Image environment(16, 8);
  for (int64_t i = 0; i < environment.pixel_count(); ++i) {
    for (int c = 0; c < 3; ++c) environment.rgba[i * 4 + c] = 1.0f;
  }
  environment.pixel(3, 2)[0] = std::nanf("");
  environment.pixel(9, 5)[1] = INFINITY;
  environment.pixel(0, 0)[2] = -INFINITY;
  if (bright > 0) {
    for (int c = 0; c < 3; ++c) environment.pixel(8, 3)[c] = bright;
  }
  const std::string path = dir.File(name);
  WriteExr(path, environment, ExrPixelType::kFloat);
  return path;
}

TEST(NumericalRobustness, RenderUnderABrokenEnvironmentIsFiniteAndCounted) {
  testing::ScratchDir dir;
  const std::string env = WriteEnvironment(dir, "broken.exr", 0.0f);
  const testing::CommandResult result =
      testing::RunBrdf("render 'phong:rho_d=0.5:rho_s=0.2:n=20' --env '" + env +
                       "' --size 32 --spp 4 --quiet --out '" + dir.File("out.png") + "' --exr '" +
                       dir.File("out.exr") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  EXPECT_NE(result.err.find(env), std::string::npos) << result.err;
  EXPECT_NE(result.err.find(" 3 pixels"), std::string::npos) << result.err;
  const cv::Mat png = cv::imread(dir.File("out.png"), cv::IMREAD_COLOR);
  ASSERT_EQ(png.rows, 32);
  // The sphere is lit: the broken pixels neither blacked out nor blew up the image.
  const cv::Vec3b centre = png.at<cv::Vec3b>(16, 16);
  EXPECT_GT(centre[0] + centre[1] + centre[2], 30);
  EXPECT_LT(centre[0] + centre[1] + centre[2], 3 * 255);
  const Image radiance = ReadExr(dir.File("out.exr"));
  for (const float value : radiance.rgba) ASSERT_TRUE(std::isfinite(value));
}

TEST(NumericalRobustness, RadianceBeyondTheHalfRangeIsClampedNotInfinite) {
  // A texel of 1e10 (a sun in a map is ~1e9) makes the sphere's radiance exceed 65504, the
  // largest half: written as half it would read back as infinity.
  testing::ScratchDir dir;
  const std::string env = WriteEnvironment(dir, "sun.exr", 1e10f);
  const testing::CommandResult result =
      testing::RunBrdf("render 'phong:rho_d=0.5:rho_s=0.2:n=20' --env '" + env +
                       "' --size 32 --spp 4 --quiet --out '" + dir.File("out.png") + "' --exr '" +
                       dir.File("out.exr") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  EXPECT_NE(result.err.find("clamped"), std::string::npos) << result.err;
  const Image radiance = ReadExr(dir.File("out.exr"));
  float largest = 0;
  for (const float value : radiance.rgba) {
    ASSERT_TRUE(std::isfinite(value));
    largest = std::max(largest, value);
  }
  EXPECT_EQ(largest, 65504.0f);
}

}  // namespace
}  // namespace brdf
