// The image error and the losses that follow a render (fitters/image_error.h, fit_samples.h:
// ResolveLoss): planted image errors, which loss `auto` resolves to on each kind of data, and
// recovery of a known model from data that can only be rendered.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/errors.h"
#include "core/measurement.h"
#include "fitters/energy_bound.h"
#include "fitters/fit.h"
#include "fitters/fit_samples.h"
#include "fitters/image_error.h"
#include "fitters/select.h"
#include "models/model_source.h"
#include "models/model_string.h"
#include "synthetic_measurement.h"
#include "test_util.h"

namespace brdf {
namespace {

using fitters::ImageErrorSetup;
using fitters::Loss;
using fitters::RelativeL1;
using fitters::RenderLitSphere;
using fitters::SphereRadiance;

Rgb LambertValue(double rho) { return Rgb::Constant(rho / kPi); }

TEST(ImageError, IsTheRelativeL1OfEachChannelAveraged) {
  SphereRadiance reference, test;
  reference.radiance = {Rgb(1.0, 2.0, 4.0), Rgb(3.0, 2.0, 0.0)};
  // Red off by 0.5 in total of 4 (12.5 %), green by 1 of 4 (25 %), blue exact.
  test.radiance = {Rgb(1.5, 3.0, 4.0), Rgb(3.0, 2.0, 0.0)};
  EXPECT_NEAR(RelativeL1(reference, test), (0.125 + 0.25 + 0.0) / 3.0, 1e-15);
  // A pixel the reference has no value for counts for neither render.
  reference.radiance.push_back(Rgb::Constant(std::numeric_limits<double>::quiet_NaN()));
  test.radiance.push_back(Rgb::Constant(100.0));
  EXPECT_NEAR(RelativeL1(reference, test), (0.125 + 0.25 + 0.0) / 3.0, 1e-15);
  test.radiance.pop_back();
  EXPECT_THROW(RelativeL1(reference, test), ComputeError);
}

TEST(ImageError, OfTwoLambertianSpheresIsTheirAlbedosRelativeDifference) {
  ImageErrorSetup setup;
  setup.size = 32;
  const auto white = [](const Vec3&, const Vec3&) { return LambertValue(0.5); };
  const auto grey = [](const Vec3&, const Vec3&) { return LambertValue(0.4); };
  const SphereRadiance a = RenderLitSphere(white, setup), b = RenderLitSphere(grey, setup);
  ASSERT_FALSE(a.radiance.empty());
  EXPECT_NEAR(RelativeL1(a, b), 0.2, 1e-12);
  EXPECT_EQ(RelativeL1(a, a), 0.0);
  // Every pixel is lit from above its horizon and seen along its own +z of the sphere's view.
  for (const fitters::PixelGeometry& pixel : fitters::LitSphereGeometry(setup)) {
    EXPECT_GT(pixel.wi.z(), 0.0);
    EXPECT_GT(pixel.wo.z(), 0.0);
    EXPECT_NEAR(pixel.wi.norm(), 1.0, 1e-12);
  }
}

TEST(ImageError, RadianceOfAPixelIsFTimesCosThetaI) {
  // A one-light, 2 x 2 render: each pixel's radiance is f cos theta_i of its own geometry.
  ImageErrorSetup setup;
  setup.size = 2;
  setup.light_theta_deg = {30.0};
  const SphereRadiance image =
      RenderLitSphere([](const Vec3&, const Vec3&) { return LambertValue(kPi); }, setup);
  const auto pixels = fitters::LitSphereGeometry(setup);
  ASSERT_EQ(image.radiance.size(), pixels.size());
  ASSERT_FALSE(pixels.empty());
  for (size_t k = 0; k < pixels.size(); ++k) {
    EXPECT_NEAR(image.radiance[k][0], pixels[k].wi.z(), 1e-15);
  }
}

TEST(LossResolution, AutoFollowsWhatTheDataAre) {
  const Model truth = ParseModel("ggx:rho_d=0.2:f0=0.04:alpha=0.2");
  // Data that can be rendered: the image loss.
  const Measurement table = ModelAsMeasurement(truth, "ggx table");
  EXPECT_EQ(fitters::ResolveLoss(Loss::kAuto, table), Loss::kImage);
  // Readings that state their noise: the chi-square.
  testing::SyntheticOptions noisy;
  noisy.noise = 0.01;
  const Measurement readings = testing::SynthesizeOnHemisphere(truth, noisy);
  ASSERT_EQ(readings.tabulated, nullptr);
  ASSERT_TRUE(readings.has_sigma());
  EXPECT_EQ(fitters::ResolveLoss(Loss::kAuto, readings), Loss::kL2);
  // Other samples: sqrt.
  testing::SyntheticOptions exact;
  exact.noise = 0.0;
  const Measurement samples = testing::SynthesizeOnHemisphere(truth, exact);
  ASSERT_FALSE(samples.has_sigma());
  EXPECT_EQ(fitters::ResolveLoss(Loss::kAuto, samples), Loss::kSqrt);
  // A loss given is kept; the image loss needs something to render.
  EXPECT_EQ(fitters::ResolveLoss(Loss::kLog, table), Loss::kLog);
  EXPECT_EQ(fitters::ResolveLoss(Loss::kImage, table), Loss::kImage);
  try {
    fitters::ResolveLoss(Loss::kImage, samples);
    FAIL() << "the image loss on samples without an evaluator was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(samples.source), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("sqrt"), std::string::npos) << error.what();
  }
}

TEST(ImageLoss, RecoversAModelFromItsRenderedSpheres) {
  // A table that is a known model: its spheres' pixels are all the fit sees.
  const Model truth = ParseModel("ggx:rho_d=0.3,0.2,0.1:f0=0.04,0.05,0.06:alpha=0.15");
  const Measurement table = ModelAsMeasurement(truth, "ggx table");
  fitters::FitOptions options;
  options.loss = Loss::kAuto;
  const fitters::FitResult fit = fitters::FitModel(table, "ggx", options);
  EXPECT_EQ(fit.loss, Loss::kImage);
  EXPECT_NE(fit.weighting.find("spheres"), std::string::npos) << fit.weighting;
  ASSERT_EQ(fit.model.params().size(), truth.params().size());
  for (size_t k = 0; k < truth.params().size(); ++k) {
    EXPECT_NEAR(fit.model.params()[k], truth.params()[k], 1e-4 * truth.params()[k] + 1e-7)
        << fit.model.ToString();
  }
  const SphereRadiance reference = RenderLitSphere(
      [&](const Vec3& wi, const Vec3& wo) { return table.tabulated->Eval(wi, wo); });
  const SphereRadiance fitted =
      RenderLitSphere([&](const Vec3& wi, const Vec3& wo) { return fit.model.Eval(wi, wo); });
  EXPECT_LT(RelativeL1(reference, fitted), 1e-4);
}

TEST(ImageLoss, AutoChoosesByTheImageAndSaysSo) {
  // Rendered data made by lambert: every lobed candidate renders as well, and the simplest,
  // lambert, is kept.
  const Measurement matte = ModelAsMeasurement(ParseModel("lambert:rho_d=0.6,0.5,0.4"), "matte");
  fitters::FitOptions options;
  options.loss = Loss::kAuto;
  fitters::Selection selection;
  const fitters::FitResult fit = fitters::SelectAndFit(matte, options, &selection);
  EXPECT_EQ(selection.criterion, "image");
  EXPECT_EQ(fit.model.name(), "lambert") << selection.reason;
  EXPECT_NE(selection.reason.find("image error"), std::string::npos) << selection.reason;
  // Rendered data made by ggx: a microfacet candidate renders closest.
  const Measurement glossy =
      ModelAsMeasurement(ParseModel("ggx:rho_d=0.2:f0=0.05:alpha=0.1"), "glossy");
  fitters::Selection glossy_selection;
  const fitters::FitResult glossy_fit = fitters::SelectAndFit(glossy, options, &glossy_selection);
  EXPECT_EQ(glossy_fit.model.name(), "ggx") << glossy_selection.reason;
  for (const fitters::CandidateScore& candidate : glossy_selection.candidates) {
    EXPECT_TRUE(std::isfinite(candidate.image_error)) << candidate.model;
    if (candidate.model == "lambert") {
      EXPECT_GT(candidate.image_error, 0.1);
    }
  }
  // Rendered data made by a coat over a base: the second lobe is what renders closest, and the
  // sentence says what it bought.
  const Model coat_over_base = ParseModel(
      "lambert+ggx+ggx:rho_d=0.1,0.08,0.05:f0=0.1,0.06,0.03:alpha=0.3:f0_2=0.02:"
      "alpha_2=0.05");
  // Inside the fit's energy bound (a model beyond it cannot be recovered).
  ASSERT_LT(fitters::EnergyBound(coat_over_base).maxCoeff(), 1.0);
  const Measurement coated = ModelAsMeasurement(coat_over_base, "coated");
  fitters::Selection coated_selection;
  const fitters::FitResult coated_fit = fitters::SelectAndFit(coated, options, &coated_selection);
  EXPECT_EQ(coated_fit.model.name(), "lambert+ggx+ggx") << coated_selection.reason;
  double single_lobe_error = 0;
  for (const fitters::CandidateScore& candidate : coated_selection.candidates) {
    if (candidate.model == "ggx") single_lobe_error = candidate.image_error;
    if (candidate.model == "lambert+ggx+ggx") {
      EXPECT_LT(candidate.image_error, 1e-3) << coated_fit.model.ToString();
    }
  }
  EXPECT_GT(single_lobe_error, 0.02) << coated_selection.reason;
}

}  // namespace
}  // namespace brdf
