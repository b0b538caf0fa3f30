// A model term of a new kind, defined in this file alone (models/term.h: what a term provides),
// composed with lambert and fitted by the fitter without any change elsewhere: the proof that a
// new term is one file (plus one list entry to give it a name on the command line).
#include <ceres/dynamic_autodiff_cost_function.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/angles.h"
#include "direction_chi_square.h"
#include "energy/albedo.h"
#include "energy/monte_carlo.h"
#include "fitters/fit_composition.h"
#include "fitters/residual.h"
#include "models/composition.h"
#include "models/lambert.h"
#include "models/model_list.h"
#include "models/model_string.h"
#include "objective_rows.h"
#include "render/lobe_sampler.h"
#include "test_util.h"

namespace brdf {
namespace {

// The lobe's own frame: a power cosine about wo itself in wi (by reciprocity, about wi in wo).
// No list outside this file knows it; the integrators and samplers ask it for its axis.
constexpr LobeFrame kAboutWo{false, [](const Vec3& wo) { return wo; }, "angle from the light"};

// A back-scattering lobe, rho_r (n+2)/(2 pi) cos^n(beta), beta the angle between wi and wo: it
// peaks where light returns toward its source (retro-reflective tapes). At normal incidence the
// lobe is phong's about the normal, whose albedo is rho_r exactly; at oblique incidence part of
// it falls below the horizon, so rho_r bounds its albedo over every incidence.
struct BackscatterLobe {
  static constexpr const char* kName = "test-backscatter";
  static constexpr const char* kFormula = "rho_r (n+2)/(2pi) cos^n(beta)";
  static constexpr const char* kBoundFormula = "rho_r";
  static constexpr const char* kAdds = "back-scattering lowers";
  static constexpr bool kDiffuse = false;
  static constexpr int kRhoR = 0, kExponent = 3;
  static constexpr int kNumParams = 4;
  static constexpr int kShapeSlot = kExponent;
  static constexpr models::ShapeScale kShapeScale = models::ShapeScale::kExponent;
  static constexpr double kFitShapeMin = 1.0, kFitShapeMax = 1e4;
  static constexpr bool kTabulatedBound = false;
  static constexpr int kGradientSize = 2;
  static constexpr bool kVanishesAtZero = true;

  static std::vector<ParamInfo> Params() {
    return {{"rho_r", kRhoR, 3, 0.0, 1e9, 0.1, "back-scattering albedo (RGB)"},
            {"n_r", kExponent, 1, 0.0, 1e4, 10.0, "back-scattering exponent"}};
  }
  static LobeCoordinates Lobe(const double* params) { return {kAboutWo, params[kExponent]}; }
  static Rgb LobeWeight(const double* params) { return models::LoadRgb(params, kRhoR); }
  static double EquivalentExponent(const double* params) { return params[kExponent]; }
  template <typename Bound>
  static Rgb MaxAlbedo(const double* params, const Bound&) {
    return models::LoadRgb(params, kRhoR);
  }

  template <typename T>
  struct Part {
    T lobe;
  };
  template <typename T, typename D>
  static Part<T> Angular(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    const T& n = params[kExponent];
    return {(n + T(2)) * T(0.5 * kInvPi) * models::ClampedPow(D(wi.dot(wo)), n)};
  }
  template <typename T>
  static RgbT<T> Colour(const T* params, const Part<T>& part) {
    return models::LoadRgb(params, kRhoR) * part.lobe;
  }
  template <typename T, typename D>
  static RgbT<T> Eval(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    if (!models::AboveHorizon(wi, wo)) return RgbT<T>::Constant(T(0));
    return Colour(params, Angular(params, wi, wo));
  }
  struct Prepared {};
  static Prepared Prepare(const double*) { return {}; }
  struct Geometry {
    double cosine;
  };
  static Geometry GeometryOf(const Vec3& wi, const Vec3& wo) { return {wi.dot(wo)}; }
  static Rgb Value(const double* params, const Prepared& prepared, const Geometry& geometry) {
    Rgb f;
    double gradient[3][2];
    ValueAndGradient(params, prepared, geometry, &f, gradient);
    return f;
  }
  static void ValueAndGradient(const double* params, const Prepared&, const Geometry& geometry,
                               Rgb* f, double gradient[3][2]) {
    const double n = params[kExponent], cosine = geometry.cosine;
    const double power = models::ClampedPow(cosine, n);
    const double lobe = (n + 2) * 0.5 * kInvPi * power;
    const double slope = cosine > 0 ? 0.5 * kInvPi * power + lobe * std::log(cosine) : 0.0;
    for (int c = 0; c < 3; ++c) {
      (*f)[c] = params[kRhoR + c] * lobe;
      gradient[c][0] = lobe;
      gradient[c][1] = params[kRhoR + c] * slope;
    }
  }

  // Variables: q_c = logistic(s_c) budget_c = rho_r_c, n = exp(shape).
  static int NumVariables(bool grey) { return (grey ? 1 : 3) + 1; }
  static void VariableBounds(bool grey, double* lower, double* upper) {
    const int s = grey ? 1 : 3;
    for (int k = 0; k < s; ++k) {
      lower[k] = -models::kLogisticBound;
      upper[k] = models::kLogisticBound;
    }
    lower[s] = std::log(kFitShapeMin);
    upper[s] = std::log(kFitShapeMax);
  }
  // A share of any budget, down to nothing.
  static constexpr bool kFitsAnyBudget = true;
  template <typename Bound>
  static double LeastAlbedo(const Bound&) {
    return 0.0;
  }
  template <typename T, typename Bound>
  static void Map(const T* variables, bool grey, const T* budget, T* params, T* taken,
                  const Bound&) {
    using std::exp;
    const int s = grey ? 1 : 3;
    for (int c = 0; c < 3; ++c) {
      taken[c] = models::Logistic(variables[grey ? 0 : c]) * budget[c];
      params[kRhoR + c] = taken[c];
    }
    params[kExponent] = exp(variables[s]);
  }
  template <typename Bound>
  static void Unmap(const double* params, bool grey, const double* budget, double* variables,
                    double* taken, const Bound&) {
    double s[3];
    for (int c = 0; c < 3; ++c) {
      taken[c] = params[kRhoR + c];
      s[c] = models::BoundedLogit(budget[c] > 0 ? taken[c] / budget[c] : 1.0);
    }
    models::PackShares(s, std::log(params[kExponent]), grey, variables);
  }
  // The peak is at wi = wo: read its height above the floor.
  template <typename Bound>
  static void Guess(const models::PeakSample& peak, const models::TermStart& start,
                    const double* budget, const Bound&, double* variables, double* taken) {
    const double peak_per_rho = (start.shape + 2) * 0.5 * kInvPi;
    for (int c = 0; c < 3; ++c) {
      const double rho =
          std::clamp(std::max(peak.channel_max[c] - peak.diffuse[c], 1e-6) / peak_per_rho, 1e-6,
                     0.9 * budget[c]);
      variables[c] = models::Logit(rho / budget[c]);
      taken[c] = rho;
    }
    variables[3] = std::log(start.shape);
  }
  static std::vector<models::TermStart> Starts(const models::StartShapes&) {
    return {{3.0, true}, {30.0, true}, {300.0, true}};
  }
};

using LambertBackscatter = models::Composition<models::Lambert, BackscatterLobe>;

// Readings of `model` over a grid of incidences and outgoing directions, the retro direction
// among them.
Measurement Readings(const Model& model) {
  Measurement measurement;
  measurement.format = "synthetic";
  for (double theta_i_deg = 0; theta_i_deg <= 70; theta_i_deg += 10) {
    const Vec3 wi = SphericalDirection(DegToRad(theta_i_deg), 0.3);
    for (double theta_o_deg = 1; theta_o_deg < 88; theta_o_deg += 3) {
      for (double phi_o_deg = 0; phi_o_deg < 360; phi_o_deg += 12) {
        Sample sample;
        sample.wi = wi;
        sample.wo = SphericalDirection(DegToRad(theta_o_deg), DegToRad(phi_o_deg));
        sample.value = model.Eval(sample.wi, sample.wo);
        measurement.samples.push_back(sample);
      }
    }
  }
  return measurement;
}

TEST(NewTerm, ComposedEvaluationIsReciprocalAndZeroBelowTheHorizon) {
  const double params[] = {0.3, 0.2, 0.1, 0.2, 0.4, 0.6, 25.0};
  std::mt19937 rng(5);
  for (int k = 0; k < 200; ++k) {
    const Vec3 wi = testing::RandomUpperDirection(&rng);
    const Vec3 wo = testing::RandomUpperDirection(&rng);
    const Rgb forward = LambertBackscatter::Eval<double>(params, wi, wo);
    const Rgb backward = LambertBackscatter::Eval<double>(params, wo, wi);
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(forward[c], backward[c]);
    const Vec3 below(wo.x(), wo.y(), -wo.z());
    EXPECT_TRUE((LambertBackscatter::Eval<double>(params, wi, below) == 0).all());
  }
  // The composition's table names both terms' parameters at their slots.
  const ModelInfo info = MakeModelInfo<LambertBackscatter>("lambert+test-backscatter");
  EXPECT_EQ(info.terms, "lambert+test-backscatter");
  ASSERT_NE(info.FindParam("rho_r"), nullptr);
  EXPECT_EQ(info.FindParam("rho_r")->slot, 3);
  EXPECT_EQ(info.shape_slot(), 6);
  EXPECT_EQ(info.bound_formula, "rho_d + rho_r");
}

// The fitter's closed-form Jacobian of the new term agrees with automatic differentiation of
// the same residuals through the parameterization.
TEST(NewTerm, ObjectiveJacobianMatchesAutomaticDifferentiation) {
  const ModelInfo info = MakeModelInfo<LambertBackscatter>("lambert+test-backscatter");
  const Model truth(info, {0.3, 0.2, 0.1, 0.2, 0.4, 0.6, 25.0});
  const fitters::PreparedSamples prepared = fitters::PrepareSamples(Readings(truth));
  const std::vector<fitters::FitSample> samples(prepared.samples.begin(),
                                                prepared.samples.begin() + 200);
  const fitters::FitObjective<LambertBackscatter> objective(samples, fitters::Loss::kLog, false);
  const std::vector<double> x = {0.1, -0.3, 0.5, -1.0, -0.4, 0.2, std::log(12.0)};
  ceres::DynamicAutoDiffCostFunction<testing::DynamicBatchResidual<LambertBackscatter>> automatic(
      new testing::DynamicBatchResidual<LambertBackscatter>{
          fitters::BatchResidual<LambertBackscatter>(false, fitters::Loss::kLog, samples.data(),
                                                     200)});
  automatic.AddParameterBlock(7);
  automatic.SetNumResiduals(600);
  std::vector<double> residuals(600), jacobian(600 * 7);
  const double* blocks[] = {x.data()};
  double* jacobians[] = {jacobian.data()};
  ASSERT_TRUE(automatic.Evaluate(blocks, residuals.data(), jacobians));
  double largest = 0;
  for (double v : jacobian) largest = std::max(largest, std::abs(v));
  int rows = 0;
  objective.ForEachRow(objective.At(x.data()),
                       [&](int64_t row, const Eigen::VectorXd& j, double residual) {
                         EXPECT_NEAR(residual, residuals[row], 1e-13);
                         for (int k = 0; k < 7; ++k) {
                           EXPECT_NEAR(j[k], jacobian[row * 7 + k], 1e-12 * largest);
                         }
                         ++rows;
                       });
  EXPECT_EQ(rows, 600);
}

// Noise-free readings of lambert + the new lobe: the fit recovers every parameter.
TEST(NewTerm, FitRecoversTheGeneratingParameters) {
  const ModelInfo info = MakeModelInfo<LambertBackscatter>("lambert+test-backscatter");
  const Model truth(info, {0.3, 0.2, 0.1, 0.2, 0.4, 0.6, 25.0});
  const fitters::PreparedSamples prepared = fitters::PrepareSamples(Readings(truth));
  fitters::FitOptions options;
  options.loss = fitters::Loss::kLog;
  const fitters::FitResult fit =
      fitters::FitComposition<LambertBackscatter>(info, prepared, options, nullptr);
  EXPECT_TRUE(fit.converged) << fit.termination;
  for (int p = 0; p < LambertBackscatter::kNumParams; ++p) {
    EXPECT_NEAR(fit.model.params()[p], truth.params()[p], 1e-4 * truth.params()[p])
        << "parameter " << p << ": " << fit.model.ToString();
  }
  EXPECT_TRUE(fit.stderr_available) << fit.stderr_note;
}

// The new lobe's frame reaches every integrator and sampler: its albedo by the lobe quadrature
// and by importance sampling equals phong's (a power cosine about the mirror direction has the
// same share above the horizon at every incidence) even for a lobe a hundredth of a radian
// wide, which the quadrature finds only about its axis; the render's float sampler and
// `brdf energy`'s sampler draw exactly the lobe's density (chi-square); the lobe's diagnostics
// name its angle.
TEST(NewTerm, ItsOwnLobeFrameGuidesTheIntegratorsAndTheSamplers) {
  const ModelInfo info = MakeModelInfo<LambertBackscatter>("lambert+test-backscatter");
  for (double n : {20.0, 1e4}) {
    const Model backscatter(info, {0, 0, 0, 1, 1, 1, n});
    const Model phong = ParseModel("phong:rho_d=0:rho_s=1:n=" + std::to_string(n));
    AlbedoOptions options;
    options.theta_steps = 18;
    const AlbedoCurve curve = ModelAlbedoCurve(backscatter, options);
    const AlbedoCurve reference = ModelAlbedoCurve(phong, options);
    ASSERT_EQ(curve.points.size(), reference.points.size());
    for (size_t k = 0; k < curve.points.size(); ++k) {
      EXPECT_NEAR(curve.points[k].estimate.albedo[0], reference.points[k].estimate.albedo[0], 2e-5)
          << "n " << n << " theta " << curve.points[k].theta_deg;
    }
    options.method = AlbedoMethod::kImportance;
    options.samples = 1 << 14;
    const AlbedoEstimate sampled = ModelDirectionalAlbedo(backscatter, DegToRad(50), options, 1);
    const double exact = ModelDirectionalAlbedo(phong, DegToRad(50), AlbedoOptions{}).albedo[0];
    EXPECT_NEAR(sampled.albedo[0], exact, 4 * sampled.error[0] + 1e-9) << n;
  }
  const LobeCoordinates lobe = Model(info, {0, 0, 0, 1, 1, 1, 40.0}).Lobe();
  const Vec3 wo = SphericalDirection(0.7, 1.1);
  const auto density = [&](const Vec3& wi) { return StrategyPdf(lobe, wo, wi); };
  EXPECT_LT(testing::DirectionChiSquareZ(
                [&](const Point2& u) { return SampleStrategy(lobe, wo, u); }, density, 400000, 3),
            4.0);
  const LobeTechnique technique(lobe);
  const LobeSampler sampler(technique, wo.cast<float>());
  EXPECT_LT(testing::DirectionChiSquareZ(
                [&](const Point2& u) -> Vec3 {
                  return sampler.Sample(static_cast<float>(u.x()), static_cast<float>(u.y()))
                      .cast<double>();
                },
                density, 400000, 4),
            4.0);
  EXPECT_STREQ(lobe.frame.offset_name, "angle from the light");
}

// Two lobes: a clear coat (a second ggx lobe) over a base lobe. The composition names the coat's
// parameters by its position, evaluates to the sum of its terms, and its fit variables are the
// terms' in order (the coat's share grey).
using CoatedGgx = models::Composition<models::Lambert, models::GgxLobe, models::GgxLobe>;

TEST(TwoLobes, AreTheSumOfTheirTermsWithPositionalNames) {
  const ModelInfo info = MakeModelInfo<CoatedGgx>("lambert+ggx+ggx");
  EXPECT_EQ(info.terms, "lambert+ggx+ggx");
  ASSERT_EQ(info.lobes.size(), 2u);
  ASSERT_NE(info.FindParam("f0_2"), nullptr);
  ASSERT_NE(info.FindParam("alpha_2"), nullptr);
  EXPECT_EQ(info.FindParam("f0_2")->slot, 7);
  EXPECT_EQ(info.FindParam("alpha_2")->slot, 10);
  EXPECT_EQ(info.lobes[1].shape_slot, 10);
  EXPECT_EQ(fitters::VariableLayout<CoatedGgx>::Count(false), 3 + 4 + 2);
  const double coated[] = {0.3, 0.2, 0.1, 0.6, 0.4, 0.2, 0.35, 0.04, 0.05, 0.06, 0.06};
  const double base[] = {0.3, 0.2, 0.1, 0.6, 0.4, 0.2, 0.35};
  const double coat[] = {0, 0, 0, 0.04, 0.05, 0.06, 0.06};
  std::mt19937 rng(11);
  for (int k = 0; k < 100; ++k) {
    const Vec3 wi = testing::RandomUpperDirection(&rng);
    const Vec3 wo = testing::RandomUpperDirection(&rng);
    const Rgb f = CoatedGgx::Eval<double>(coated, wi, wo);
    const Rgb sum =
        models::Ggx::Eval<double>(base, wi, wo) + models::Ggx::Eval<double>(coat, wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], sum[c], 1e-14 * sum[c]);
    const Rgb backward = CoatedGgx::Eval<double>(coated, wo, wi);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], backward[c], 1e-14 * f[c]);
  }
}

}  // namespace
}  // namespace brdf
