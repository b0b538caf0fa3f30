// The fit report's diagnostics (fitters/diagnostics.h, docs/stability.md): each failure mode the
// stability study found is built here and the report must name it; a healthy fit of the same
// data must raise none of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fitters/diagnostics.h"
#include "fitters/fit.h"
#include "fitters/report.h"
#include "models/model_string.h"
#include "synthetic_measurement.h"
#include "test_util.h"

namespace brdf {
namespace {

using fitters::FitModel;
using fitters::FitOptions;
using fitters::FitResult;
using testing::AllWarnings;
using testing::HasWarning;
using testing::SynthesizeOnHemisphere;
using testing::SyntheticOptions;

// The diagnostics' warnings begin with these words (the subsample and energy-bound notes are
// the fitter's own and say nothing about reliability).
const char* kDiagnostics[] = {"lobe narrower", "not identifiable", "coverage",
                              "outliers",      "model mismatch",   "not converged"};

constexpr const char* kGlossyPhong = "phong:rho_d=0.3,0.2,0.1:rho_s=0.2,0.25,0.3:n=300";
constexpr const char* kGlossyBlinn = "blinn-phong:rho_d=0.3,0.2,0.1:rho_s=0.2,0.25,0.3:m=300";

TEST(FitDiagnostics, HealthyFitsRaiseNone) {
  for (const char* text : {kGlossyPhong, kGlossyBlinn}) {
    const Model truth = ParseModel(text);
    const FitResult fit = FitModel(SynthesizeOnHemisphere(truth, {}), truth.name(), FitOptions{});
    ASSERT_TRUE(fit.converged) << text;
    for (const char* prefix : kDiagnostics) {
      EXPECT_FALSE(HasWarning(fit, prefix))
          << text << " raised '" << prefix << "'" << AllWarnings(fit);
    }
    // The recovered exponent is good to a few percent: the warnings' silence is deserved.
    EXPECT_NEAR(fit.model.params()[models::Phong::kExponent], 300, 0.03 * 300) << text;
  }
}

TEST(FitDiagnostics, LobeNarrowerThanTheSampleSpacingIsReported) {
  // A lobe 0.57 deg wide (n = 1e4) read every 15 deg of incidence and 10 deg of azimuth: the
  // mirror direction is sampled, its nearest neighbours lie 2.6 deg (4.5 widths) away or more.
  const Model truth = ParseModel("phong:rho_d=0.3,0.2,0.1:rho_s=0.2,0.25,0.3:n=1e4");
  SyntheticOptions options;
  options.theta_step_deg = 15;
  options.phi_step_deg = 10;
  const FitResult fit = FitModel(SynthesizeOnHemisphere(truth, options), "phong", FitOptions{});
  EXPECT_TRUE(HasWarning(fit, "lobe narrower than the sample spacing")) << AllWarnings(fit);
  // The truth's own lobe has no sample on its flank either.
  const fitters::PreparedSamples prepared =
      fitters::PrepareSamples(SynthesizeOnHemisphere(truth, options));
  const fitters::LobeResolution lobe =
      fitters::ResolveLobe(truth.Lobe().frame, 1e4, prepared.samples);
  EXPECT_EQ(lobe.flank_samples, 0u);
  EXPECT_GT(lobe.peak_samples, 0u);
  EXPECT_NEAR(lobe.half_width_deg, 180 / kPi / std::sqrt(1e4), 1e-3);
}

// A composition's lobes are each checked, whichever place the sharp one has: a lobe of
// alpha 0.004 (under half a degree) read every 15 deg of incidence and 10 deg of azimuth is
// reported by its place and name, the broad lobe beside it (alpha 0.3) is not.
TEST(FitDiagnostics, EachLobeOfACompositionIsChecked) {
  SyntheticOptions options;
  options.theta_step_deg = 15;
  options.phi_step_deg = 10;
  const struct {
    const char* model;
    const char* reported;
  } cases[] = {
      {"lambert+ggx+ggx:rho_d=0.3,0.2,0.1:f0=0.04:alpha=0.3:f0_2=0.5:alpha_2=0.004",
       "the fitted second lobe (roughness alpha_2 = 0.004"},
      {"lambert+ggx+ggx:rho_d=0.3,0.2,0.1:f0=0.5:alpha=0.004:f0_2=0.04:alpha_2=0.3",
       "the fitted first lobe (roughness alpha = 0.004"},
  };
  for (const auto& c : cases) {
    const Model truth = ParseModel(c.model);
    const fitters::PreparedSamples prepared =
        fitters::PrepareSamples(SynthesizeOnHemisphere(truth, options));
    FitResult result(truth);
    result.converged = true;
    result.stderr_available = true;
    result.stderr_values.assign(truth.params().size(), std::nan(""));
    result.samples = prepared.samples.size();
    fitters::AppendFitDiagnostics(prepared, &result, nullptr);
    int narrower = 0;
    for (const std::string& warning : result.warnings) {
      if (warning.rfind("lobe narrower", 0) != 0) continue;
      ++narrower;
      EXPECT_NE(warning.find(c.reported), std::string::npos) << warning;
    }
    EXPECT_EQ(narrower, 1) << c.model << AllWarnings(result);
  }
}

// The other side: a composition fitted to data it made, both lobes resolved by the 5 deg grid
// (alpha 0.08 and 0.3; albedo at most 0.94, inside the energy bound), recovers both widths and
// raises none of the diagnostics for either lobe.
TEST(FitDiagnostics, HealthyCompositionRaisesNoneForEitherLobe) {
  const Model truth =
      ParseModel("lambert+ggx+ggx:rho_d=0.05,0.03,0.01:f0=0.5:alpha=0.08:f0_2=0.05:alpha_2=0.3");
  const FitResult fit = FitModel(SynthesizeOnHemisphere(truth, {}), truth.name(), FitOptions{});
  ASSERT_TRUE(fit.converged);
  // Both lobes have a grey f0, so the fit may hold them in either order.
  const double sharp = std::min(fit.model.Param("alpha"), fit.model.Param("alpha_2"));
  const double broad = std::max(fit.model.Param("alpha"), fit.model.Param("alpha_2"));
  EXPECT_NEAR(sharp, 0.08, 0.03 * 0.08) << fit.model.ToString();
  EXPECT_NEAR(broad, 0.3, 0.03 * 0.3) << fit.model.ToString();
  for (const char* prefix : kDiagnostics) {
    EXPECT_FALSE(HasWarning(fit, prefix))
        << "raised '" << prefix << "' " << fit.model.ToString() << AllWarnings(fit);
  }
}

TEST(FitDiagnostics, SamplesTheFitSkipsDoNotCount) {
  // The diagnostics read the fit's prepared samples: a sample the fit skips (missing, NaN, at or
  // below the horizon) is not among them, even one placed on the lobe's peak.
  const Model truth = ParseModel("phong:rho_d=0.3:rho_s=0.5:n=300");
  SyntheticOptions options;
  options.theta_step_deg = 5;
  options.phi_step_deg = 15;
  Measurement measurement = SynthesizeOnHemisphere(truth, options);
  const fitters::PreparedSamples clean = fitters::PrepareSamples(measurement);
  Sample on_peak;  // exactly on the mirror direction: would count as a peak sample
  on_peak.wi = SphericalDirection(DegToRad(30), 0);
  on_peak.wo = SphericalDirection(DegToRad(30), kPi);
  on_peak.value = truth.Eval(on_peak.wi, on_peak.wo);
  Sample missing = on_peak, not_finite = on_peak, below = on_peak;
  missing.missing = true;
  not_finite.value[1] = std::nan("");
  below.wi = Vec3(on_peak.wi.x(), on_peak.wi.y(), -on_peak.wi.z());
  for (const Sample& skipped : {missing, not_finite, below}) measurement.samples.push_back(skipped);
  const fitters::PreparedSamples prepared = fitters::PrepareSamples(measurement);
  ASSERT_EQ(prepared.samples.size() + 3, measurement.samples.size());
  for (const LobeFrame& frame : {ParseModel("phong").Lobe().frame, kHalfVectorFrame}) {
    const fitters::LobeResolution with_skipped = fitters::ResolveLobe(frame, 300, prepared.samples);
    const fitters::LobeResolution without = fitters::ResolveLobe(frame, 300, clean.samples);
    EXPECT_GT(without.peak_samples, 0u);
    EXPECT_EQ(with_skipped.peak_samples, without.peak_samples);
    EXPECT_EQ(with_skipped.flank_samples, without.flank_samples);
    EXPECT_EQ(with_skipped.nearest_off_peak_deg, without.nearest_off_peak_deg);
  }
  const fitters::ResidualCheck residuals_with = fitters::CheckResiduals(truth, prepared);
  const fitters::ResidualCheck residuals_without = fitters::CheckResiduals(truth, clean);
  EXPECT_EQ(residuals_with.residuals, residuals_without.residuals);
  EXPECT_EQ(residuals_with.robust_scale, residuals_without.robust_scale);
  EXPECT_EQ(residuals_with.reduced_chi_square, residuals_without.reduced_chi_square);
}

TEST(FitDiagnostics, LobeResolutionCountsTheFlankExactly) {
  // Phong lobe of exponent 100 (sigma = 5.73 deg) at normal incidence; detectors on rings at
  // offsets 1, 4, 10 and 20 deg from the mirror direction (the normal). The flank is
  // [sigma/2, 3 sigma] = [2.87, 17.2] deg: the rings at 4 and 10 deg, 8 samples each.
  std::vector<fitters::FitSample> samples;
  for (double offset_deg : {1.0, 4.0, 10.0, 20.0}) {
    for (int k = 0; k < 8; ++k) {
      fitters::FitSample sample;
      sample.wi = Vec3(0, 0, 1);
      sample.wo = SphericalDirection(DegToRad(offset_deg), 2 * kPi * k / 8);
      samples.push_back(sample);
    }
  }
  const fitters::LobeResolution lobe =
      fitters::ResolveLobe(ParseModel("phong").Lobe().frame, 100, samples);
  EXPECT_EQ(lobe.peak_samples, 8u);
  EXPECT_EQ(lobe.flank_samples, 16u);
  EXPECT_NEAR(lobe.nearest_off_peak_deg, 4.0, 1e-9);
  // In half-vector terms the same rings sit at half the offset: theta_h = 0.5, 2, 5, 10 deg.
  const fitters::LobeResolution blinn = fitters::ResolveLobe(kHalfVectorFrame, 100, samples);
  EXPECT_EQ(blinn.peak_samples, 16u);  // 0.5 and 2 deg < 2.87 deg
  EXPECT_EQ(blinn.flank_samples, 16u);
}

TEST(FitDiagnostics, LobeOnMatteDataIsNotIdentifiable) {
  const Model matte = ParseModel("lambert:rho_d=0.5,0.3,0.2");
  const FitResult fit = FitModel(SynthesizeOnHemisphere(matte, {}), "phong", FitOptions{});
  EXPECT_TRUE(HasWarning(fit, "not identifiable")) << AllWarnings(fit);
  // The lambert fit of the same data is healthy.
  const FitResult lambert = FitModel(SynthesizeOnHemisphere(matte, {}), "lambert", FitOptions{});
  for (const char* prefix : kDiagnostics) {
    EXPECT_FALSE(HasWarning(lambert, prefix)) << prefix << AllWarnings(lambert);
  }
}

// Data brighter than any beckmann lobe can be (5 % above f0 = 1, as a traced surface's
// multiple scattering is): the lobe takes the whole albedo budget, f0 is pinned at 1 and the
// diffuse share has nothing left to share. Neither is measured, but the width is: its standard
// error is reported and no "not identifiable" warning fires. (The diffuse share's column of J^T J
// vanishes; left in, it made the covariance rank-deficient and hid alpha's error.)
TEST(FitDiagnostics, ALobeThatTakesTheWholeBudgetStillHasItsWidthMeasured) {
  Measurement bright = SynthesizeOnHemisphere(ParseModel("beckmann:rho_d=0:f0=1:alpha=0.5"), {});
  for (Sample& sample : bright.samples) sample.value *= 1.05;
  const FitResult fit = FitModel(bright, "beckmann", FitOptions{});
  ASSERT_TRUE(fit.converged);
  const ParamInfo& f0 = *fit.model.info().FindParam("f0");
  const ParamInfo& rho_d = *fit.model.info().FindParam("rho_d");
  const ParamInfo& alpha = *fit.model.info().FindParam("alpha");
  for (int c = 0; c < 3; ++c) {
    EXPECT_TRUE(f0.AtBound(fit.model.params()[f0.slot + c])) << fit.model.ToString();
    EXPECT_TRUE(rho_d.AtBound(fit.model.params()[rho_d.slot + c])) << fit.model.ToString();
    EXPECT_TRUE(std::isnan(fit.stderr_values[f0.slot + c]));
    EXPECT_TRUE(std::isnan(fit.stderr_values[rho_d.slot + c]));
  }
  ASSERT_TRUE(fit.stderr_available) << fit.stderr_note;
  const double width = fit.model.params()[alpha.slot];
  const double error = fit.stderr_values[alpha.slot];
  EXPECT_GT(error, 0);
  EXPECT_LT(error, 0.01 * width);
  EXPECT_FALSE(HasWarning(fit, "not identifiable")) << AllWarnings(fit);
}

// A faint lobe under 20 % noise: its peak, 5e-4 sr^-1 over a floor of 0.16, is 0.3 % of the
// signal, and the ~2,000 readings inside it average the noise down to about that. Whatever the
// noise's draw and the subsample's, the fitted lobe (grey or in one channel, at n = 1 or 1e5) is
// reported as no more than noise; a lobe 100 times as strong under the same noise is not.
TEST(FitDiagnostics, LobeOfNoiseIsNotIdentifiableWhateverTheDraw) {
  const Model faint = ParseModel("phong:rho_d=0.5:rho_s=1e-4:n=30");
  const Model clear = ParseModel("phong:rho_d=0.5:rho_s=1e-2:n=30");
  for (uint64_t data_seed : {1, 2, 3, 4, 5}) {
    SyntheticOptions options;
    options.noise = 0.2;
    options.seed = data_seed;
    for (uint64_t fit_seed : {1, 2}) {
      FitOptions fit_options;
      fit_options.seed = fit_seed;
      const FitResult fit = FitModel(SynthesizeOnHemisphere(faint, options), "phong", fit_options);
      EXPECT_TRUE(HasWarning(fit, "not identifiable"))
          << data_seed << " " << fit_seed << " " << fit.model.ToString() << AllWarnings(fit);
    }
    if (data_seed <= 2) {
      const FitResult fit = FitModel(SynthesizeOnHemisphere(clear, options), "phong", FitOptions{});
      EXPECT_FALSE(HasWarning(fit, "not identifiable")) << fit.model.ToString() << AllWarnings(fit);
    }
  }
}

TEST(FitDiagnostics, LowCoverageIsReportedAndFullCoverageIsNot) {
  const Model truth = ParseModel(kGlossyBlinn);
  SyntheticOptions low;
  low.theta_max_deg = 60;
  const FitResult fit = FitModel(SynthesizeOnHemisphere(truth, low), "blinn-phong", FitOptions{});
  ASSERT_TRUE(HasWarning(fit, "coverage")) << AllWarnings(fit);
  // cos^2(60 deg) = 25 % of the projected hemisphere is unobserved.
  bool quoted = false;
  for (const std::string& warning : fit.warnings) {
    quoted = quoted || (warning.find("theta = 60 deg") != std::string::npos &&
                        warning.find("25 %") != std::string::npos);
  }
  EXPECT_TRUE(quoted) << AllWarnings(fit);
  SyntheticOptions grazing;
  grazing.grazing_rings = true;  // up to 89 deg
  const FitResult full =
      FitModel(SynthesizeOnHemisphere(truth, grazing), "blinn-phong", FitOptions{});
  EXPECT_FALSE(HasWarning(full, "coverage")) << AllWarnings(full);
}

TEST(FitDiagnostics, NonConvergenceIsReported) {
  const Model truth = ParseModel(kGlossyBlinn);
  FitOptions options;
  options.max_iterations = 1;
  const FitResult fit = FitModel(SynthesizeOnHemisphere(truth, {}), "blinn-phong", options);
  ASSERT_FALSE(fit.converged);
  EXPECT_TRUE(HasWarning(fit, "not converged")) << AllWarnings(fit);
}

TEST(FitDiagnostics, OutliersAreReportedWithoutRobustLoss) {
  const Model truth = ParseModel(kGlossyBlinn);
  SyntheticOptions options;
  options.outlier_fraction = 0.05;
  options.seed = 7;
  const Measurement data = SynthesizeOnHemisphere(truth, options);
  const FitResult plain = FitModel(data, "blinn-phong", FitOptions{});
  EXPECT_TRUE(HasWarning(plain, "outliers")) << AllWarnings(plain);
  // Scattered spikes are not a region the model misses.
  const FitResult cauchy = FitModel(data, "blinn-phong", [] {
    FitOptions robust;
    robust.robust = fitters::Robust::kCauchy;
    return robust;
  }());
  EXPECT_FALSE(HasWarning(cauchy, "model mismatch")) << AllWarnings(cauchy);
  // 5 % spikes of x10 are 5 % of the samples beyond 5 scales: the count is what was planted.
  const fitters::ResidualCheck check =
      fitters::CheckResiduals(truth, fitters::PrepareSamples(data));
  EXPECT_NEAR(static_cast<double>(check.beyond_5_scale) / check.residuals, 0.05, 0.01);
  EXPECT_NEAR(check.robust_scale, 1.0, 0.1);  // the sigma column is honest for the inliers
}

TEST(FitDiagnostics, HonestSigmaGivesUnitChiSquare) {
  const Model truth = ParseModel(kGlossyPhong);
  const fitters::ResidualCheck check =
      fitters::CheckResiduals(truth, fitters::PrepareSamples(SynthesizeOnHemisphere(truth, {})));
  // 3 x 21,000 residuals: chi-square / dof = 1 +- 0.006.
  EXPECT_NEAR(check.reduced_chi_square, 1.0, 0.03);
  EXPECT_EQ(check.beyond_5_scale, 0u);
}

TEST(FitDiagnostics, ModelMismatchIsReported) {
  // Phong's lobe about the mirror direction is not Blinn-Phong's half-vector lobe: away from
  // normal incidence the two differ in shape, far beyond 1 % noise.
  const Model truth = ParseModel("phong:rho_d=0.3,0.2,0.1:rho_s=0.4,0.45,0.5:n=50");
  const FitResult fit = FitModel(SynthesizeOnHemisphere(truth, {}), "blinn-phong", FitOptions{});
  EXPECT_TRUE(HasWarning(fit, "model mismatch")) << AllWarnings(fit);
  EXPECT_FALSE(HasWarning(fit, "outliers")) << AllWarnings(fit);  // a region, not scattered
}

TEST(FitDiagnostics, WarningsReachTheJsonReport) {
  const Model truth = ParseModel(kGlossyBlinn);
  SyntheticOptions low;
  low.theta_max_deg = 60;
  const FitResult fit = FitModel(SynthesizeOnHemisphere(truth, low), "blinn-phong", FitOptions{});
  const nlohmann::json json = fitters::FitReportJson(fit, "synthetic", nullptr);
  bool found = false;
  for (const auto& warning : json["warnings"]) {
    found = found || warning.get<std::string>().rfind("coverage", 0) == 0;
  }
  EXPECT_TRUE(found) << json["warnings"].dump();
}

}  // namespace
}  // namespace brdf
