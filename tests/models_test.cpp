// Physics of the reflectance models of DESIGN §2 and of their runtime registry: reciprocity,
// the horizon, albedo integrals by brute-force quadrature against the closed forms the model
// headers promise, automatic derivatives against ceres::GradientChecker, and the registry's
// parameter tables.
#include <ceres/autodiff_cost_function.h>
#include <ceres/gradient_checker.h>
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "core/angles.h"
#include "core/errors.h"
#include "core/vec.h"
#include "models/blinn_phong.h"
#include "models/blinn_phong_exact.h"
#include "models/lambert.h"
#include "models/phong.h"
#include "models/registry.h"
#include "test_util.h"

namespace brdf {
namespace {

using models::BlinnPhong;
using models::BlinnPhongExact;
using Lambert = models::LambertModel;
// The slots of a one-lobe model (rho_d, rho_s, exponent), as every power-cosine model has them.
using LobedSlots = models::Phong;
using models::Phong;
using testing::RandomUpperDirection;

template <typename M>
constexpr bool kIsLobed = std::is_base_of_v<models::SingleLobeSlots, M>;

// ---------------------------------------------------------------------------------------------
// Sampling and quadrature helpers.

// Parameter sets that exercise each model: coloured albedos, and exponents from a broad lobe to
// a sharp one (the range of real materials in the registry's comment).
template <typename M>
std::vector<std::vector<double>> ParameterSets() {
  if constexpr (kIsLobed<M>) {
    return {{0.5, 0.5, 0.5, 0.04, 0.04, 0.04, 1.0},
            {0.8, 0.2, 0.1, 0.3, 0.5, 0.9, 37.5},
            {0.0, 0.1, 0.2, 1.0, 0.7, 0.2, 1000.0}};
  } else {
    return {{0.5, 0.5, 0.5}, {0.8, 0.2, 0.1}, {1.0, 0.0, 0.3}};
  }
}

// Lobe-only parameters: rho_d = 0, rho_s = (1, 0.5, 0.25) so that each channel checks the
// lobe's linearity in rho_s as well as its shape.
std::vector<double> LobeOnlyParams(double exponent) {
  std::vector<double> params(LobedSlots::kNumParams, 0.0);
  params[LobedSlots::kRhoS + 0] = 1.0;
  params[LobedSlots::kRhoS + 1] = 0.5;
  params[LobedSlots::kRhoS + 2] = 0.25;
  params[LobedSlots::kExponent] = exponent;
  return params;
}
const Rgb kLobeRhoS(1.0, 0.5, 0.25);

// Gauss–Legendre rule on [-1, 1], by Newton's method on the Legendre polynomial P_n.
struct GaussRule {
  std::vector<double> nodes, weights;
};

GaussRule GaussLegendre(int n) {
  GaussRule rule;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(kPi * (i + 0.75) / (n + 0.5));  // Tricomi's initial guess
    double derivative = 0.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p_prev = 1.0, p = x;
      for (int k = 2; k <= n; ++k) {
        const double p_next = ((2.0 * k - 1.0) * x * p - (k - 1.0) * p_prev) / k;
        p_prev = p;
        p = p_next;
      }
      derivative = n * (x * p - p_prev) / (x * x - 1.0);
      const double step = p / derivative;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    rule.nodes.push_back(x);
    rule.weights.push_back(2.0 / ((1.0 - x * x) * derivative * derivative));
  }
  return rule;
}

const GaussRule& Gauss16() {
  static const GaussRule rule = GaussLegendre(16);
  return rule;
}

// Composite Gauss–Legendre (16 nodes per panel) of an RGB-valued function over [a, b]. The
// panels keep the rule accurate for sharp lobes: at n = 1000 a phong lobe is ~0.03 rad wide,
// several panels at the 400 used below.
template <typename F>
Rgb IntegrateComposite(const F& integrand, double a, double b, int panels) {
  const GaussRule& rule = Gauss16();
  const double width = (b - a) / panels;
  Rgb sum = Rgb::Zero();
  for (int panel = 0; panel < panels; ++panel) {
    const double centre = a + (panel + 0.5) * width;
    for (size_t k = 0; k < rule.nodes.size(); ++k) {
      const Rgb value = integrand(centre + 0.5 * width * rule.nodes[k]);
      sum += (0.5 * width * rule.weights[k]) * value;
    }
  }
  return sum;
}

// Directional albedo at normal incidence, a = ∫_H f(n, wo) cos(theta_o) dwo (DESIGN §1). With
// wi on the normal every model here is symmetric about the normal (phong: alpha = theta_o;
// blinn: theta_h = theta_o / 2), so the phi integral is 2π times the phi = 0 value and one
// dimension in theta suffices; the tests check that symmetry separately.
template <typename M>
Rgb NormalIncidenceAlbedo(const std::vector<double>& params, int panels) {
  const Vec3 normal(0.0, 0.0, 1.0);
  const auto integrand = [&](double theta_o) -> Rgb {
    const Rgb f = M::Eval(params.data(), normal, SphericalDirection(theta_o, 0.0));
    return f * (std::cos(theta_o) * std::sin(theta_o));
  };
  return 2.0 * kPi * IntegrateComposite(integrand, 0.0, 0.5 * kPi, panels);
}

// Directional albedo for a fixed wi over a theta × phi grid of the hemisphere: composite
// Gauss–Legendre in theta_o, the trapezoid rule in phi_o (spectrally accurate for a periodic
// integrand).
template <typename M>
Rgb HemisphereAlbedo(const std::vector<double>& params, const Vec3& wi, int theta_panels,
                     int phi_nodes) {
  const double phi_step = 2.0 * kPi / phi_nodes;
  const auto integrand = [&](double theta_o) -> Rgb {
    Rgb ring = Rgb::Zero();
    for (int j = 0; j < phi_nodes; ++j) {
      ring += M::Eval(params.data(), wi, SphericalDirection(theta_o, j * phi_step));
    }
    return ring * (phi_step * std::cos(theta_o) * std::sin(theta_o));
  };
  return IntegrateComposite(integrand, 0.0, 0.5 * kPi, theta_panels);
}

void ExpectRgbNear(const Rgb& actual, const Rgb& expected, double tolerance,
                   const std::string& what) {
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(actual[c], expected[c], tolerance) << what << ", channel " << c;
  }
}

// ---------------------------------------------------------------------------------------------
// The quadrature itself, so that the albedo tests below check the models and not the tool.

TEST(ModelQuadrature, GaussLegendreIsExactForPolynomialsOfDegree31) {
  const GaussRule& rule = Gauss16();
  double weight_sum = 0.0;
  for (double w : rule.weights) weight_sum += w;
  EXPECT_NEAR(weight_sum, 2.0, 1e-14);
  // ∫_{-1}^{1} x^k dx = 2/(k+1) for even k, 0 for odd k; 16 nodes are exact up to k = 31.
  for (int k = 0; k <= 31; ++k) {
    double sum = 0.0;
    for (size_t i = 0; i < rule.nodes.size(); ++i) {
      sum += rule.weights[i] * std::pow(rule.nodes[i], k);
    }
    EXPECT_NEAR(sum, k % 2 == 0 ? 2.0 / (k + 1) : 0.0, 1e-14) << "x^" << k;
  }
}

TEST(ModelQuadrature, HemisphereOfCosineIsPi) {
  // ∫ cos(theta) dw = π over the hemisphere (DESIGN §1): lambert with rho_d = π·(1,1,1)/π.
  const std::vector<double> unit_albedo = {1.0, 1.0, 1.0};
  const Rgb albedo = HemisphereAlbedo<Lambert>(unit_albedo, Vec3(0, 0, 1), 8, 16);
  ExpectRgbNear(albedo, Rgb::Ones(), 1e-14, "lambert rho_d = 1");
}

// ---------------------------------------------------------------------------------------------
// Properties every model has (typed over the four templated structs).

template <typename M>
class ModelProperties : public ::testing::Test {};
using AllModels = ::testing::Types<Lambert, Phong, BlinnPhong, BlinnPhongExact>;
TYPED_TEST_SUITE(ModelProperties, AllModels);

// Helmholtz reciprocity f(wi, wo) = f(wo, wi) (DESIGN §1: albedo may be integrated over either
// direction only because of it).
TYPED_TEST(ModelProperties, Reciprocity) {
  using M = TypeParam;
  std::mt19937 rng(20240611);
  int compared_nonzero = 0;
  for (const std::vector<double>& params : ParameterSets<M>()) {
    for (int pair = 0; pair < 1000; ++pair) {
      const Vec3 wi = RandomUpperDirection(&rng);
      const Vec3 wo = RandomUpperDirection(&rng);
      const Rgb forward = M::Eval(params.data(), wi, wo);
      const Rgb backward = M::Eval(params.data(), wo, wi);
      for (int c = 0; c < 3; ++c) {
        const double scale = std::max(std::abs(forward[c]), std::abs(backward[c]));
        EXPECT_LE(std::abs(forward[c] - backward[c]), 1e-12 * scale)
            << M::kName << " wi=" << wi.transpose() << " wo=" << wo.transpose();
        if (scale > 0.0) ++compared_nonzero;
      }
    }
  }
  // The comparison must not be vacuous (every value zero).
  EXPECT_GT(compared_nonzero, 3 * 1000);
}

TYPED_TEST(ModelProperties, ZeroBelowAndOnTheHorizon) {
  using M = TypeParam;
  std::mt19937 rng(7);
  const auto expect_zero = [](const Rgb& f, const char* what) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(f[c], 0.0) << M::kName << ": " << what;
  };
  for (const std::vector<double>& params : ParameterSets<M>()) {
    for (int pair = 0; pair < 200; ++pair) {
      const Vec3 wi = RandomUpperDirection(&rng);
      const Vec3 wo = RandomUpperDirection(&rng);
      const Vec3 wi_below(wi.x(), wi.y(), -wi.z());
      const Vec3 wo_below(wo.x(), wo.y(), -wo.z());
      // Sanity: above the horizon these pairs are not all zero (rho_d > 0 in every set but one
      // channel), so the zeros below are the horizon's doing.
      EXPECT_GT(M::Eval(params.data(), wi, wo).maxCoeff(), 0.0);
      expect_zero(M::Eval(params.data(), wi_below, wo), "wi below");
      expect_zero(M::Eval(params.data(), wi, wo_below), "wo below");
      expect_zero(M::Eval(params.data(), wi_below, wo_below), "both below");
      // Below-horizon wo at the mirror of wi (phong's peak) and wo = wi (blinn's peak).
      expect_zero(M::Eval(params.data(), wi_below, MirrorDirection(wi_below)), "mirror below");
      expect_zero(M::Eval(params.data(), wi_below, wi_below), "wi = wo below");
      // Exactly on the horizon (z = 0) counts as below (common.h, AboveHorizon).
      const Vec3 wi_grazing(wi.x(), wi.y(), 0.0);
      const Vec3 wo_grazing(wo.x(), wo.y(), 0.0);
      expect_zero(M::Eval(params.data(), wi_grazing.normalized(), wo), "wi grazing");
      expect_zero(M::Eval(params.data(), wi, wo_grazing.normalized()), "wo grazing");
      expect_zero(M::Eval(params.data(), Vec3(1, 0, 0), Vec3(-1, 0, 0)), "grazing mirror");
    }
  }
}

// Relative tolerance between two evaluations of the same formula that may round differently:
// Eigen vectorises the double dot products but not the Jet ones, so the lobe cosine can differ
// by an ulp, and x^e multiplies that relative error by e.
template <typename M>
double RoundingTolerance(const std::vector<double>& params) {
  double amplification = 1.0;
  if constexpr (kIsLobed<M>) amplification += params[LobedSlots::kExponent];
  return 8.0 * std::numeric_limits<double>::epsilon() * amplification;
}

// The f value of a Jet evaluation is the double evaluation: one templated definition serves
// both (STYLE rule 3), so a fit minimises the very function `brdf energy` integrates.
TYPED_TEST(ModelProperties, JetValueMatchesDouble) {
  using M = TypeParam;
  using Jet = ceres::Jet<double, M::kNumParams>;
  std::mt19937 rng(11);
  for (const std::vector<double>& params : ParameterSets<M>()) {
    const double tolerance = RoundingTolerance<M>(params);
    Jet jet_params[M::kNumParams];
    for (int k = 0; k < M::kNumParams; ++k) jet_params[k] = Jet(params[k], k);
    for (int pair = 0; pair < 100; ++pair) {
      const Vec3 wi = RandomUpperDirection(&rng);
      const Vec3 wo = RandomUpperDirection(&rng);
      const Vec3T<Jet> wi_jet = wi.cast<Jet>();
      const Vec3T<Jet> wo_jet = wo.cast<Jet>();
      const RgbT<Jet> f_jet = M::Eval(jet_params, wi_jet, wo_jet);
      const Rgb f = M::Eval(params.data(), wi, wo);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(f_jet[c].a, f[c], tolerance * f[c]) << M::kName;
    }
  }
}

// Residual functor for the gradient check: the three channels of f at one (wi, wo) pair, the
// model's whole parameter array as the single parameter block.
template <typename M>
struct EvalResidual {
  Vec3 wi, wo;

  template <typename T>
  bool operator()(const T* params, T* residuals) const {
    const Vec3T<T> wi_t = wi.cast<T>();
    const Vec3T<T> wo_t = wo.cast<T>();
    const RgbT<T> f = M::Eval(params, wi_t, wo_t);
    for (int c = 0; c < 3; ++c) residuals[c] = f[c];
    return true;
  }
};

// Direction pairs away from the lobe peak and its tail, where pow(x, e) is smooth in both x
// and e: cos(alpha) (phong) and cos(theta_h) (blinn) both in (0.3, 0.99).
std::vector<std::pair<Vec3, Vec3>> OffPeakPairs(int count) {
  std::mt19937 rng(3);
  std::vector<std::pair<Vec3, Vec3>> pairs;
  while (static_cast<int>(pairs.size()) < count) {
    const Vec3 wi = RandomUpperDirection(&rng);
    const Vec3 wo = RandomUpperDirection(&rng);
    const double cos_alpha = MirrorDirection(wi).dot(wo);
    const double cos_theta_h = models::BlinnPhongLobe::CosThetaHalf(wi, wo);
    if (cos_alpha > 0.3 && cos_alpha < 0.99 && cos_theta_h > 0.3 && cos_theta_h < 0.99) {
      pairs.emplace_back(wi, wo);
    }
  }
  return pairs;
}

// Parameter points for the gradient check: the lobe must not be negligible next to the
// diffuse term, or the finite differences of a ~1e-11 lobe drown in the rounding of
// rho_d/π and the check compares noise. With cos in (0.3, 0.99), exponents up to 12 keep the
// lobe above ~1e-7; one point has rho_d = 0 so that the lobe is all there is.
template <typename M>
std::vector<std::vector<double>> GradientPoints() {
  if constexpr (kIsLobed<M>) {
    return {{0.5, 0.5, 0.5, 0.04, 0.04, 0.04, 1.0},
            {0.8, 0.2, 0.1, 0.3, 0.5, 0.9, 3.5},
            {0.0, 0.0, 0.0, 1.0, 0.7, 0.2, 12.0}};
  } else {
    return ParameterSets<M>();
  }
}

TYPED_TEST(ModelProperties, AutodiffGradientMatchesGradientChecker) {
  using M = TypeParam;
  using CostFunction = ceres::AutoDiffCostFunction<EvalResidual<M>, 3, M::kNumParams>;
  const std::vector<const ceres::Manifold*>* euclidean = nullptr;
  // Ridders' first step is this fraction of the parameter. Ceres's default (1e-2, i.e. 0.12
  // in m = 12) returned the plain central difference here, 2.4e-4 off for blinn-phong's
  // d f/d m (the autodiff value agrees with the hand derivative below to 1e-12); a smaller
  // first step lets the extrapolation converge.
  ceres::NumericDiffOptions numeric_options;
  numeric_options.ridders_relative_initial_step_size = 1e-3;
  for (const auto& [wi, wo] : OffPeakPairs(4)) {
    const CostFunction cost(new EvalResidual<M>{wi, wo});
    const ceres::GradientChecker checker(&cost, euclidean, numeric_options);
    for (const std::vector<double>& params : GradientPoints<M>()) {
      const double* blocks[] = {params.data()};
      ceres::GradientChecker::ProbeResults results;
      EXPECT_TRUE(checker.Probe(blocks, 1e-7, &results))
          << M::kName << " wi=" << wi.transpose() << " wo=" << wo.transpose() << "\n"
          << results.error_log;
      // The residuals are the double evaluation.
      const Rgb f = M::Eval(params.data(), wi, wo);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(results.residuals[c], f[c], RoundingTolerance<M>(params) * f[c]);
      }
      // f is linear in rho_d with slope 1/π, channel by channel.
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 3; ++k) {
          EXPECT_NEAR(results.jacobians[0](c, M::kRhoD + k), c == k ? kInvPi : 0.0, 1e-15);
        }
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Lobed models: the exponent derivative against the hand-differentiated formula.

template <typename M>
class ModelLobe : public ::testing::Test {};
using LobedModels = ::testing::Types<Phong, BlinnPhong, BlinnPhongExact>;
TYPED_TEST_SUITE(ModelLobe, LobedModels);

// Lobe per unit rho_s, k(e) x^e, with its exponent derivative (k' + k ln x) x^e, written out from
// the model headers' formulas independently of their code.
struct LobeValue {
  double value, d_exponent;
};

template <typename M>
LobeValue ExpectedLobe(const Vec3& wi, const Vec3& wo, double e) {
  double cosine = 0.0, k = 0.0, dk = 0.0;
  if constexpr (std::is_same_v<M, Phong>) {
    cosine = MirrorDirection(wi).dot(wo);
    k = (e + 2.0) / (2.0 * kPi);
    dk = 1.0 / (2.0 * kPi);
  } else {
    cosine = (wi + wo).normalized().z();
    if constexpr (std::is_same_v<M, BlinnPhong>) {
      k = (e + 8.0) / (8.0 * kPi);
      dk = 1.0 / (8.0 * kPi);
    } else {
      const double denominator = std::pow(2.0, -e / 2.0) + e;
      const double d_denominator = 1.0 - 0.5 * std::log(2.0) * std::pow(2.0, -e / 2.0);
      k = (e + 2.0) * (e + 4.0) / (8.0 * kPi * denominator);
      dk = k * (1.0 / (e + 2.0) + 1.0 / (e + 4.0) - d_denominator / denominator);
    }
  }
  const double power = std::pow(cosine, e);
  return {k * power, (dk + k * std::log(cosine)) * power};
}

TYPED_TEST(ModelLobe, JacobianMatchesHandDerivative) {
  using M = TypeParam;
  for (const auto& [wi, wo] : OffPeakPairs(4)) {
    for (double exponent : {1.0, 10.0, 85.0}) {
      std::vector<double> params = LobeOnlyParams(exponent);
      params[M::kRhoD + 1] = 0.3;
      const ceres::AutoDiffCostFunction<EvalResidual<M>, 3, M::kNumParams> cost(
          new EvalResidual<M>{wi, wo});
      const double* blocks[] = {params.data()};
      double residuals[3];
      double jacobian[3 * M::kNumParams];  // row-major: residual × parameter
      double* jacobians[] = {jacobian};
      ASSERT_TRUE(cost.Evaluate(blocks, residuals, jacobians));
      const LobeValue lobe = ExpectedLobe<M>(wi, wo, exponent);
      for (int c = 0; c < 3; ++c) {
        const double rho_s = kLobeRhoS[c];
        const double rho_d = params[M::kRhoD + c];
        EXPECT_NEAR(residuals[c], rho_d * kInvPi + rho_s * lobe.value, 1e-13 * residuals[c]);
        // ∂f_c/∂rho_s_c is the lobe; other channels' rho_s do not touch channel c.
        for (int k = 0; k < 3; ++k) {
          EXPECT_NEAR(jacobian[c * M::kNumParams + M::kRhoS + k], c == k ? lobe.value : 0.0,
                      1e-13 * lobe.value);
        }
        EXPECT_NEAR(jacobian[c * M::kNumParams + M::kExponent], rho_s * lobe.d_exponent,
                    1e-12 * std::abs(rho_s * lobe.d_exponent) + 1e-300)
            << M::kName << " e=" << exponent;
      }
    }
  }
}

// At normal incidence every lobe is symmetric about the normal, which NormalIncidenceAlbedo
// relies on.
TYPED_TEST(ModelLobe, NormalIncidenceLobeIsAxisymmetric) {
  using M = TypeParam;
  const std::vector<double> params = LobeOnlyParams(30.0);
  const Vec3 normal(0, 0, 1);
  for (double theta_o = 0.05; theta_o < 0.5 * kPi; theta_o += 0.1) {
    const Rgb reference = M::Eval(params.data(), normal, SphericalDirection(theta_o, 0.0));
    for (double phi_o : {0.7, 2.0, 3.5, 5.9}) {
      const Rgb f = M::Eval(params.data(), normal, SphericalDirection(theta_o, phi_o));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], reference[c], 1e-13 * reference[c]);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Albedo integrals.

TEST(ModelLambert, IsRhoDOverPi) {
  const std::vector<double> params = {0.8, 0.2, 0.1};
  std::mt19937 rng(5);
  for (int pair = 0; pair < 100; ++pair) {
    const Rgb f =
        Lambert::Eval(params.data(), RandomUpperDirection(&rng), RandomUpperDirection(&rng));
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(f[c], params[c] / kPi);
  }
  // Just above the horizon it is still rho_d/π: only z <= 0 is cut.
  const Rgb grazing = Lambert::Eval(params.data(), Vec3(1, 0, 1e-12).normalized(), Vec3(0, 0, 1));
  for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(grazing[c], params[c] / kPi);
}

TEST(ModelLambert, AlbedoIsRhoDAtEveryIncidence) {
  const std::vector<double> params = {0.8, 0.2, 0.1};
  for (double theta_i_deg : {0.0, 30.0, 60.0, 89.0}) {
    const Vec3 wi = SphericalDirection(DegToRad(theta_i_deg), 1.0);
    ExpectRgbNear(HemisphereAlbedo<Lambert>(params, wi, 8, 16), Rgb(0.8, 0.2, 0.1), 1e-13,
                  "theta_i = " + std::to_string(theta_i_deg));
  }
}

// Number of theta panels for the 1D normal-incidence integrals, and a coarser count for the
// convergence check: the two must agree far below the 1e-5 tolerance, so that what is tested
// is the model and not the discretisation.
constexpr int kNormalPanels = 400;
constexpr int kCoarsePanels = 200;

template <typename M>
Rgb ConvergedNormalAlbedo(double exponent) {
  const std::vector<double> params = LobeOnlyParams(exponent);
  const Rgb fine = NormalIncidenceAlbedo<M>(params, kNormalPanels);
  const Rgb coarse = NormalIncidenceAlbedo<M>(params, kCoarsePanels);
  ExpectRgbNear(fine, coarse, 1e-10, std::string(M::kName) + " quadrature not converged");
  return fine;
}

// Lafortune & Willems 1994: (n+2)/(2π) makes the normal-incidence lobe albedo exactly rho_s.
TEST(ModelPhong, NormalIncidenceAlbedoIsRhoS) {
  for (double n : {1.0, 10.0, 100.0, 1000.0}) {
    ExpectRgbNear(ConvergedNormalAlbedo<Phong>(n), kLobeRhoS, 1e-5, "n = " + std::to_string(n));
  }
}

// blinn_phong_exact.h: dividing by the normal-incidence integral makes that albedo rho_s.
TEST(ModelBlinnPhongExact, NormalIncidenceAlbedoIsRhoS) {
  for (double m : {1.0, 10.0, 100.0, 1000.0}) {
    ExpectRgbNear(ConvergedNormalAlbedo<BlinnPhongExact>(m), kLobeRhoS, 1e-5,
                  "m = " + std::to_string(m));
  }
}

// The real-time (m+8)/(8π) factor is an approximation; its normal-incidence albedo is the
// closed form (m+8)(2^(-m/2)+m)/((m+2)(m+4)), which the quadrature must reproduce.
TEST(ModelBlinnPhong, NormalIncidenceAlbedoMatchesClosedForm) {
  for (double m : {1.0, 10.0, 100.0, 1000.0}) {
    const double closed_form = (m + 8.0) * (std::pow(2.0, -m / 2.0) + m) / ((m + 2.0) * (m + 4.0));
    EXPECT_DOUBLE_EQ(models::BlinnPhongNormalAlbedo(m), closed_form);
    ExpectRgbNear(ConvergedNormalAlbedo<BlinnPhong>(m), closed_form * kLobeRhoS, 1e-5,
                  "m = " + std::to_string(m));
  }
  // Hand values: m = 0 is rho_s/π (albedo 1); large m tends to (m+8)m/((m+2)(m+4)) -> 1.
  EXPECT_DOUBLE_EQ(models::BlinnPhongNormalAlbedo(0.0), 1.0);
  EXPECT_NEAR(models::BlinnPhongNormalAlbedo(1e6), 1.0, 1e-5);
}

// DESIGN §2: the approximation overshoots, reaching 1.0752 rho_s near m = 8.8, so the energy
// constraint must use that true maximum. The quadrature confirms the overshoot independently.
TEST(ModelBlinnPhong, NormalIncidenceAlbedoPeaksAt1p0752NearM8p8) {
  double best_m = 0.0, best_albedo = 0.0;
  for (int step = 0; step <= 2900; ++step) {
    const double m = 1.0 + 0.01 * step;
    const double albedo = models::BlinnPhongNormalAlbedo(m);
    if (albedo > best_albedo) {
      best_albedo = albedo;
      best_m = m;
    }
  }
  EXPECT_NEAR(best_albedo, 1.0752, 1e-4);
  EXPECT_NEAR(best_m, 8.8, 0.1);
  // An interior maximum, not an end of the grid.
  EXPECT_LT(models::BlinnPhongNormalAlbedo(1.0), best_albedo);
  EXPECT_LT(models::BlinnPhongNormalAlbedo(30.0), best_albedo);
  const Rgb quadrature = ConvergedNormalAlbedo<BlinnPhong>(best_m);
  ExpectRgbNear(quadrature, best_albedo * kLobeRhoS, 1e-5, "at the maximum");
  EXPECT_GT(quadrature[0], 1.075);  // rho_s = 1 reflects more than it receives
}

// Off the normal part of the lobe falls below the horizon and the rest is weighted by a
// smaller cos(theta_o), so the lobe albedo is below rho_s and falls as theta_i grows.
TEST(ModelPhong, ObliqueAlbedoIsBelowRhoSAndDecreasing) {
  const std::vector<double> params = LobeOnlyParams(10.0);
  Rgb previous = Rgb::Zero();
  for (double theta_i_deg : {0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0}) {
    const Vec3 wi = SphericalDirection(DegToRad(theta_i_deg), 0.4);
    const Rgb albedo = HemisphereAlbedo<Phong>(params, wi, 48, 192);
    const Rgb coarse = HemisphereAlbedo<Phong>(params, wi, 24, 96);
    const std::string where = "theta_i = " + std::to_string(theta_i_deg);
    ExpectRgbNear(albedo, coarse, 1e-8, where + " (quadrature not converged)");
    if (theta_i_deg == 0.0) {
      // The 2D grid agrees with the 1D result at normal incidence.
      ExpectRgbNear(albedo, kLobeRhoS, 1e-8, where);
    } else {
      for (int c = 0; c < 3; ++c) {
        EXPECT_LT(albedo[c], kLobeRhoS[c] - 1e-4) << where;
        EXPECT_LT(albedo[c], previous[c] - 1e-4) << where;
        EXPECT_GT(albedo[c], 0.0) << where;
      }
    }
    previous = albedo;
  }
}

// ---------------------------------------------------------------------------------------------
// The runtime registry.

TEST(Registry, ListsTheModelsOfDesignInOrder) {
  std::vector<std::string> names;
  for (const ModelInfo& info : ModelRegistry()) names.push_back(info.name);
  EXPECT_EQ(names, (std::vector<std::string>{"lambert", "phong", "blinn-phong", "blinn-phong-exact",
                                             "ggx", "beckmann", "lambert+retro", "eon", "eon+ggx",
                                             "ggx-aniso", "lambert+ggx+ggx", "lambert+retro+ggx"}));
  // The ladder `--model auto` climbs: the first six but blinn-phong-exact (it ties blinn-phong),
  // and a second ggx lobe.
  std::vector<std::string> ladder;
  for (const ModelInfo& info : ModelRegistry()) {
    if (info.auto_candidate) ladder.push_back(info.name);
  }
  EXPECT_EQ(ladder, (std::vector<std::string>{"lambert", "phong", "blinn-phong", "ggx", "beckmann",
                                              "lambert+ggx+ggx"}));
}

TEST(Registry, ParameterSlotsCoverTheArrayExactlyOnce) {
  for (const ModelInfo& info : ModelRegistry()) {
    ASSERT_GT(info.num_params, 0) << info.name;
    std::vector<std::string> owner(info.num_params);
    for (const ParamInfo& param : info.params) {
      EXPECT_TRUE(param.channels == 1 || param.channels == 3) << info.name << "." << param.name;
      for (int c = 0; c < param.channels; ++c) {
        const int slot = param.slot + c;
        ASSERT_GE(slot, 0) << info.name << "." << param.name;
        ASSERT_LT(slot, info.num_params) << info.name << "." << param.name;
        EXPECT_EQ(owner[slot], "") << info.name << ": slot " << slot << " is both " << owner[slot]
                                   << " and " << param.name;
        owner[slot] = param.name;
      }
      EXPECT_LE(param.lower, param.default_value) << info.name << "." << param.name;
      EXPECT_LE(param.default_value, param.upper) << info.name << "." << param.name;
      EXPECT_EQ(info.FindParam(param.name), &param);
    }
    for (int slot = 0; slot < info.num_params; ++slot) {
      EXPECT_NE(owner[slot], "") << info.name << ": slot " << slot << " has no parameter";
    }
    EXPECT_EQ(info.DefaultParams().size(), static_cast<size_t>(info.num_params));
  }
}

TEST(Registry, VisitModelTypeGivesTheMatchingStruct) {
  std::mt19937 rng(13);
  for (const ModelInfo& info : ModelRegistry()) {
    const std::vector<double> defaults = info.DefaultParams();
    const Vec3 wi = RandomUpperDirection(&rng);
    const Vec3 wo = RandomUpperDirection(&rng);
    VisitModelType(info.name, [&](auto model) {
      using M = decltype(model);
      EXPECT_EQ(M::kNumParams, info.num_params) << info.name;
      EXPECT_EQ(std::string(M::kName), info.name);
      // The registry names the struct's slots.
      EXPECT_EQ(info.FindParam("rho_d")->slot, M::kRhoD) << info.name;
      if constexpr (kIsLobed<M>) {
        EXPECT_EQ(info.params[1].slot, M::kRhoS) << info.name;  // rho_s or f0
        EXPECT_EQ(info.params.back().slot, M::kExponent) << info.name;
        EXPECT_EQ(info.shape_slot(), M::kShape) << info.name;
      }
      // And its evaluator is the struct's.
      const Rgb registry_f = info.eval(defaults.data(), wi, wo);
      const Rgb struct_f = M::Eval(defaults.data(), wi, wo);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(registry_f[c], struct_f[c]) << info.name;
    });
  }
}

TEST(Registry, UnknownModelThrowsUsageErrorListingTheKnownOnes) {
  try {
    FindModel("nope");
    ADD_FAILURE() << "FindModel(\"nope\") did not throw";
  } catch (const UsageError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("nope"), std::string::npos) << message;
    for (const ModelInfo& info : ModelRegistry()) {
      EXPECT_NE(message.find(info.name), std::string::npos) << message;
    }
  }
  EXPECT_THROW(VisitModelType("nope", [](auto) { return 0; }), UsageError);
  EXPECT_THROW(FindModel(""), UsageError);
  EXPECT_THROW(FindModel("Phong"), UsageError);  // names are case-sensitive
}

// ClampedPow in doubles remembers its last results (models/common.h): whatever the order of the
// calls, repeated or new bases, colliding table slots, exponents that change between calls, and
// from several threads at once, it returns std::pow's bits, and 0 at or below zero.
TEST(Models, RememberedPowIsPowBitForBit) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // A few hundred bases, as a gridded table's lobe cosines repeat, and a few exponents.
  std::vector<double> bases(300), exponents = {1.0, 80.0, 80.0000000001, 1e4, 0.5};
  for (double& base : bases) base = unit(rng);
  bases[0] = 1.0;
  bases[1] = std::numeric_limits<double>::denorm_min();
  bases[2] = std::numeric_limits<double>::quiet_NaN();
  const auto check = [&](uint64_t seed, int calls) {
    std::mt19937_64 order(seed);
    for (int k = 0; k < calls; ++k) {
      const double x = bases[order() % bases.size()];
      const double e = exponents[order() % exponents.size()];
      const double expected = std::pow(x, e);
      const double got = models::ClampedPow(x, e);
      if (std::isnan(expected)) {
        ASSERT_TRUE(std::isnan(got)) << x << " " << e;
      } else {
        ASSERT_EQ(got, expected) << x << " " << e;  // bit for bit (no -0 can arise here)
      }
    }
  };
  check(1, 200000);
  // Runs of one base at one exponent, then the next: the order of a fit's pass over a table.
  for (double e : exponents) {
    for (double x : bases) {
      for (int repeat = 0; repeat < 3; ++repeat) {
        if (!std::isnan(x)) {
          ASSERT_EQ(models::ClampedPow(x, e), std::pow(x, e)) << x << " " << e;
        }
      }
    }
  }
  EXPECT_EQ(models::ClampedPow(0.0, 3.0), 0.0);
  EXPECT_EQ(models::ClampedPow(-0.25, 2.0), 0.0);
  EXPECT_EQ(models::ClampedPow(-0.0, 2.0), 0.0);
  // Every thread has its own memory: threads racing over the same bases stay exact.
  std::vector<std::thread> threads;
  for (uint64_t seed = 2; seed < 6; ++seed) threads.emplace_back(check, seed, 50000);
  for (std::thread& thread : threads) thread.join();
}

}  // namespace
}  // namespace brdf
