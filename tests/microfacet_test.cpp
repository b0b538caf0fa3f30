// The microfacet rungs (DESIGN §2): the distributions are normalized, the models reciprocal and
// zero below the horizon, their Jet derivatives right, the lobe with F = 1 loses energy to
// masking exactly as a brute-force integral says, the model strings reject what no material
// can have, and the fitter's energy bound keeps every reachable material at albedo <= 1 while
// reaching within 1 % of it.
#include <ceres/autodiff_cost_function.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/angles.h"
#include "core/errors.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "direction_chi_square.h"
#include "energy/albedo.h"
#include "energy/lobe_quadrature.h"
#include "energy/model_terms.h"
#include "energy/monte_carlo.h"
#include "fitters/microfacet_bound.h"
#include "fitters/parameterization.h"
#include "models/model_string.h"
#include "models/registry.h"

namespace brdf {
namespace {

using models::Beckmann;
using models::Ggx;

template <typename M>
class MicrofacetModel : public ::testing::Test {};
using MicrofacetModels = ::testing::Types<Ggx, Beckmann>;
// The model's lobe term (models/ggx.h, beckmann.h).
template <typename M>
using LobeTerm = typename M::template Term<1>;
TYPED_TEST_SUITE(MicrofacetModel, MicrofacetModels);

// ∫ D(h) cos(theta_h) dω_h = 1: the normal distribution's projected area is the surface's.
// Midpoint rule in theta_h over [0, π/2] (the azimuth integrates to 2π), fine enough to resolve
// the narrowest lobe tried.
TYPED_TEST(MicrofacetModel, NormalDistributionProjectsToUnitArea) {
  using M = TypeParam;
  for (double alpha : {0.02, 0.1, 0.3, 0.7, 1.2}) {
    const int cells = 400000;
    const double step = 0.5 * kPi / cells;
    double integral = 0;
    for (int k = 0; k < cells; ++k) {
      const double theta = (k + 0.5) * step;
      integral += LobeTerm<M>::D(std::cos(theta), alpha) * std::cos(theta) * std::sin(theta) * step;
    }
    EXPECT_NEAR(2 * kPi * integral, 1.0, 1e-6) << M::kName << " alpha " << alpha;
    // The lobe density the samplers and the quadrature use is the same D cos(theta_h), and its
    // mass-beyond function is its integral: check them against the same midpoint sums.
    const LobeCoordinates lobe =
        FindModel(M::kName).Lobe(std::vector<double>{0, 0, 0, 1, 1, 1, alpha}.data());
    double beyond = 0;
    for (int k = cells - 1; k >= 0; --k) {
      const double theta = (k + 0.5) * step;
      beyond += LobeDensity(lobe, std::cos(theta)) * std::sin(theta) * step * 2 * kPi;
      if (k % 40000 == 0) {
        const double at = k * step;
        EXPECT_NEAR(LobeMassBeyond(lobe, std::cos(at)), beyond, 2e-6) << M::kName << " " << at;
        const double mass = LobeMassBeyond(lobe, std::cos(at));
        // (Beckmann's Gaussian tail underflows to 0 far out: nothing to invert there.)
        if (mass > 1e-200) {
          EXPECT_NEAR(LobeCosAt(lobe, mass), std::cos(at), 1e-9) << at;
        }
      }
    }
  }
}

TYPED_TEST(MicrofacetModel, ReciprocalNonNegativeAndZeroBelowTheHorizon) {
  using M = TypeParam;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double params[] = {0.2, 0.1, 0.05, 0.04, 0.5, 0.9, 0.25};
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3 wi = SampleCosineHemisphere(Point2(uniform(rng), uniform(rng)));
    const Vec3 wo = SampleCosineHemisphere(Point2(uniform(rng), uniform(rng)));
    const Rgb forward = M::template Eval<double>(params, wi, wo);
    const Rgb backward = M::template Eval<double>(params, wo, wi);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(forward[c], backward[c], 1e-12 * std::max(1.0, forward[c]));
      EXPECT_GE(forward[c], params[c] / kPi);
    }
    const Vec3 below(wo.x(), wo.y(), -wo.z());
    EXPECT_TRUE((M::template Eval<double>(params, wi, below) == 0).all());
    EXPECT_TRUE((M::template Eval<double>(params, below, wo) == 0).all());
  }
}

// f at seven parameters for a few fixed direction pairs, as a Ceres cost: the Jets' derivatives
// (Beckmann's through erfc and exp) against central differences.
template <typename M>
struct EvalCost {
  std::vector<std::pair<Vec3, Vec3>> pairs;
  template <typename T>
  bool operator()(const T* params, T* residuals) const {
    for (size_t k = 0; k < pairs.size(); ++k) {
      const RgbT<T> f = M::template Eval<T>(params, pairs[k].first, pairs[k].second);
      for (int c = 0; c < 3; ++c) residuals[3 * k + c] = f[c];
    }
    return true;
  }
};

TYPED_TEST(MicrofacetModel, JetDerivativesMatchTheGradientChecker) {
  using M = TypeParam;
  auto* functor = new EvalCost<M>;
  for (const auto& [ti, to, phi] : {std::tuple{0.0, 0.1, 0.0}, std::tuple{0.3, 0.35, 3.0},
                                    std::tuple{1.2, 1.3, 3.1}, std::tuple{1.0, 1.45, 2.9}}) {
    functor->pairs.push_back({SphericalDirection(ti, 0.0), SphericalDirection(to, phi)});
  }
  const int residuals = 3 * static_cast<int>(functor->pairs.size());
  ceres::AutoDiffCostFunction<EvalCost<M>, ceres::DYNAMIC, 7> cost(functor, residuals);
  // Ridders' extrapolation from a step of 1e-4 of each parameter: the default 1e-2 step
  // carries alpha across the range where masking changes regime.
  ceres::NumericDiffOptions numeric_options;
  numeric_options.ridders_relative_initial_step_size = 1e-4;
  const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
  ceres::GradientChecker checker(&cost, no_manifolds, numeric_options);
  for (const std::vector<double>& point :
       {std::vector<double>{0.2, 0.1, 0.05, 0.04, 0.5, 0.9, 0.25},
        std::vector<double>{0.0, 0.3, 0.6, 0.9, 0.02, 0.3, 0.6}}) {
    const double* blocks[] = {point.data()};
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(blocks, 1e-6, &results)) << M::kName << results.error_log;
  }
}

// With f0 = 1 (F = 1) and rho_d = 0 the lobe's albedo is what masking and shadowing leave:
// below 1 (by the visible normals' normalization, G2 <= G1(wo) bounds it by 1). The values come
// from a brute-force midpoint sum over the half vector (dω_i = 4 (wo.h) dω_h), compared with `brdf
// energy`'s quadrature.
TYPED_TEST(MicrofacetModel, UnitFresnelLobeAlbedoMatchesBruteForceAndStaysBelowOne) {
  using M = TypeParam;
  const Model& unused = ParseModel(std::string(M::kName));  // the registry knows it
  (void)unused;
  for (double alpha : {0.1, 0.5}) {
    const Model lobe =
        ParseModel(std::string(M::kName) + ":rho_d=0:f0=1:alpha=" + std::to_string(alpha));
    for (double theta_deg : {0.0, 40.0, 70.0, 85.0}) {
      const Vec3 wo = SphericalDirection(DegToRad(theta_deg), 0.0);
      const int theta_cells = 3000, phi_cells = 720;
      const double d_theta = 0.5 * kPi / theta_cells, d_phi = 2 * kPi / phi_cells;
      double brute_force = 0;
      for (int i = 0; i < theta_cells; ++i) {
        const double theta_h = (i + 0.5) * d_theta;
        for (int j = 0; j < phi_cells; ++j) {
          const Vec3 h = SphericalDirection(theta_h, (j + 0.5) * d_phi);
          const double wo_dot_h = wo.dot(h);
          if (wo_dot_h <= 0) continue;
          const Vec3 wi = Reflect(wo, h);
          if (wi.z() <= 0) continue;
          brute_force +=
              lobe.Eval(wi, wo)[0] * wi.z() * 4 * wo_dot_h * std::sin(theta_h) * d_theta * d_phi;
        }
      }
      const AlbedoEstimate quadrature =
          ModelDirectionalAlbedo(lobe, DegToRad(theta_deg), AlbedoOptions{});
      EXPECT_NEAR(quadrature.albedo[0], brute_force, 2e-3)
          << M::kName << " alpha " << alpha << " theta " << theta_deg;
      // Below 1 up to the quadrature's error; a rough lobe loses a visible share.
      EXPECT_LE(quadrature.albedo[0], 1.0 + 2 * quadrature.error[0] + 1e-9);
      if (alpha >= 0.5) {
        EXPECT_LT(quadrature.albedo[0], 0.99);
      }
    }
  }
}

TEST(MicrofacetFresnel, SchlickAndTheExactFormAgreeAtTheEnds) {
  for (double n : {1.33, 1.5, 2.4}) {
    const double f0 = std::pow((n - 1) / (n + 1), 2);
    EXPECT_NEAR(models::FresnelReflectance(1.0, n, 0.0), f0, 1e-12);
    EXPECT_NEAR(models::SchlickFresnel(1.0, f0), f0, 1e-15);
    EXPECT_NEAR(models::SchlickFresnel(0.0, f0), 1.0, 1e-15);
    EXPECT_NEAR(models::FresnelReflectance(0.0, n, 0.0), 1.0, 1e-12);
    // In between, Schlick's approximation of a dielectric overestimates the reflectance by up to
    // 0.07 (near cos = 0.1, for n = 1.33 ... 2.4): what the microfacet models accept for speed,
    // and why the gonioreflectometer's facets use the exact form.
    for (double c = 0.0; c <= 1.0; c += 0.01) {
      EXPECT_NEAR(models::SchlickFresnel(c, f0), models::FresnelReflectance(c, n, 0.0), 0.075)
          << n << " " << c;
    }
  }
}

void ExpectUsageErrorNaming(const std::string& text, const std::string& key) {
  try {
    const Model model = ParseModel(text);
    ADD_FAILURE() << text << " parsed as " << model.ToString();
  } catch (const UsageError& error) {
    EXPECT_NE(std::string(error.what()).find(key), std::string::npos) << error.what();
  }
}

TEST(MicrofacetModelString, ImpossibleValuesAreUsageErrorsNamingTheKey) {
  for (const char* name : {"ggx", "beckmann"}) {
    const std::string model = name;
    ExpectUsageErrorNaming(model + ":alpha=0", "alpha");
    ExpectUsageErrorNaming(model + ":f0=-0.1", "f0");
    ExpectUsageErrorNaming(model + ":f0=1.5", "f0");
    ExpectUsageErrorNaming(model + ":f0=0.1,0.2,1.01", "f0");
    ExpectUsageErrorNaming(model + ":roughness=0.1", "roughness");
    const Model parsed = ParseModel(model + ":rho_d=0.2,0.1,0.1:f0=0.04:alpha=0.08");
    EXPECT_EQ(ParseModel(parsed.ToString()).params(), parsed.params());
  }
}

// The fitter's parameterization (parameterization.h) for model M: 10,000 random points of the
// variables, integrated over the 90 incidence angles of the energy check (0 ... 89 deg) and the
// bound's own grazing angles. The lobe's albedo is linear in f0 (Schlick) and rho_d adds exactly
// rho_d (DESIGN §1), so each point's curve is rho_d + E_0 + f0 (E_1 - E_0) from two integrals
// per angle and alpha: 200 random alphas, 50 points each. A few points are also integrated
// whole, as `brdf energy` does.
template <typename M>
void ExpectRandomParameterizationPointsConserve() {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> shape(std::log(models::kMinFitRoughness),
                                               std::log(models::kMaxFitRoughness));
  std::uniform_real_distribution<double> logit(-12, 12);
  const ModelInfo& info = FindModel(M::kName);
  LobeQuadratureOptions quadrature;
  quadrature.tolerance = 1e-7;
  quadrature.max_intervals = 400;
  double worst = 0;
  for (int a = 0; a < 200; ++a) {
    const double log_alpha = shape(rng);
    const double alpha = std::exp(log_alpha);
    std::vector<double> thetas;
    for (int k = 0; k < 90; ++k) thetas.push_back(DegToRad(k));
    for (double t : {0.5, 1.0, 1.5, 2.0, 3.0, 5.0, 20.0, 100.0, 1000.0}) {
      thetas.push_back(std::atan(t / alpha));
    }
    std::vector<double> e0, e1;
    const Model lobe(info, {0, 0, 0, 0, 1, 0, alpha});
    for (double theta : thetas) {
      const AlbedoEstimate estimate = IntegrateInLobeCoordinates(
          ModelBrdf(lobe), SphericalDirection(theta, 0.0), lobe.Lobe(), quadrature);
      e0.push_back(estimate.albedo[0]);
      e1.push_back(estimate.albedo[1]);
    }
    for (int point = 0; point < 50; ++point) {
      // The variables d[3], s[3], ln alpha (parameterization.h).
      double x[7];
      for (int c = 0; c < 3; ++c) {
        x[c] = logit(rng);
        x[3 + c] = logit(rng);
      }
      x[6] = log_alpha;
      // Push some points against the budget: d large means rho_d takes all the lobe leaves.
      if (point % 5 == 0) x[0] = x[1] = x[2] = 40;
      double params[M::kNumParams];
      fitters::ComputeParams<M, double>(false, x, params);
      for (int c = 0; c < 3; ++c) {
        const double rho_d = params[M::kRhoD + c], f0 = params[M::kF0 + c];
        ASSERT_GE(rho_d, 0.0);
        ASSERT_GE(f0, 0.0);
        ASSERT_LE(f0, 1.0);
        for (size_t k = 0; k < thetas.size(); ++k) {
          const double albedo = rho_d + e0[k] + f0 * (e1[k] - e0[k]);
          worst = std::max(worst, albedo);
          ASSERT_LE(albedo, 1.0 + 1e-6)
              << M::kName << " alpha " << alpha << " f0 " << f0 << " theta " << RadToDeg(thetas[k]);
        }
      }
      if (point == 0 && a % 40 == 0) {
        const Model material(info, std::vector<double>(params, params + M::kNumParams));
        const AlbedoCurve curve = ModelAlbedoCurve(material, AlbedoOptions{});
        EXPECT_EQ(curve.verdict().conservation, Conservation::kConserving) << curve.Summary();
        EXPECT_LE(curve.max_albedo.maxCoeff(), 1.0 + 1e-6) << curve.Summary();
      }
    }
  }
  EXPECT_GT(worst, 0.98) << M::kName;  // the points do reach the budget
}

TEST(MicrofacetBound, TenThousandRandomGgxPointsConserve) {
  ExpectRandomParameterizationPointsConserve<Ggx>();
}
TEST(MicrofacetBound, TenThousandRandomBeckmannPointsConserve) {
  ExpectRandomParameterizationPointsConserve<Beckmann>();
}

// The bound gives away less than 1 %: with rho_d taking the whole budget (d = 40), the true
// maximum albedo over incidence is within 1 % of 1, for a smooth dielectric coat (maximum
// near grazing), a rough one and a metal (maximum at normal incidence).
template <typename M>
void ExpectBoundIsTight() {
  const ModelInfo& info = FindModel(M::kName);
  for (const auto& [alpha, f0] :
       {std::pair{0.05, 0.04}, std::pair{0.3, 0.04}, std::pair{0.3, 0.9}}) {
    const double x[7] = {
        40, 40, 40, fitters::Logit(f0), fitters::Logit(f0), fitters::Logit(f0), std::log(alpha)};
    double params[M::kNumParams];
    fitters::ComputeParams<M, double>(false, x, params);
    const Model material(info, std::vector<double>(params, params + M::kNumParams));
    double best = 0;
    for (double theta = 0; theta < 0.5 * kPi; theta += DegToRad(0.25)) {
      best = std::max(best, ModelDirectionalAlbedo(material, theta, AlbedoOptions{}).albedo[0]);
    }
    for (double t : {0.5, 0.8, 1.0, 1.3, 1.7, 2.2, 3.0, 10.0, 100.0, 1000.0}) {
      const double theta = std::atan(t / alpha);
      best = std::max(best, ModelDirectionalAlbedo(material, theta, AlbedoOptions{}).albedo[0]);
    }
    EXPECT_LE(best, 1.0 + 1e-6) << M::kName << " alpha " << alpha << " f0 " << f0;
    EXPECT_GE(best, 0.99) << M::kName << " alpha " << alpha << " f0 " << f0;
  }
}

// The table the build integrated (fitters/albedo_tables.cpp) is the one the quadrature gives
// now, node for node: 60 nodes spread over alpha and theta, each integrated afresh.
template <typename M>
void ExpectBuiltTableIsTheQuadrature() {
  const double* built = fitters::BuiltAlbedoTable(M::kName);
  ASSERT_NE(built, nullptr) << M::kName << ": the build made no table";
  using Table = fitters::MicrofacetAlbedoTable;
  const fitters::MicrofacetAlbedoTable& table = fitters::AlbedoTableOf<M>();
  for (int node = 0; node < Table::NodeCount(); node += 57) {
    const int j = node / Table::ThetaNodes(), k = node % Table::ThetaNodes();
    const auto [e0, e1] = Table::IntegrateNode(FindModel(M::kName), j, k);
    EXPECT_EQ(built[node], e0) << M::kName << " node " << node;
    EXPECT_EQ(built[Table::NodeCount() + node], e1) << M::kName << " node " << node;
    EXPECT_EQ(table.E0(j, k), e0);
    EXPECT_EQ(table.E1(j, k), e1);
  }
}

TEST(MicrofacetBound, BuiltGgxTableIsTheQuadrature) { ExpectBuiltTableIsTheQuadrature<Ggx>(); }
TEST(MicrofacetBound, BuiltBeckmannTableIsTheQuadrature) {
  ExpectBuiltTableIsTheQuadrature<Beckmann>();
}

TEST(MicrofacetBound, GgxBoundIsTightWithinOnePercent) { ExpectBoundIsTight<Ggx>(); }
TEST(MicrofacetBound, BeckmannBoundIsTightWithinOnePercent) { ExpectBoundIsTight<Beckmann>(); }

}  // namespace
}  // namespace brdf

namespace brdf {
namespace {

// Chi-square test (direction_chi_square.h) of what SampleStrategy draws (what `brdf energy
// --method importance` and the preview renderer draw: GGX's visible normals, Beckmann's
// D cos(theta_h)) against StrategyPdf.
double SamplerChiSquareZ(const LobeCoordinates& lobe, const Vec3& wo, int samples) {
  return testing::DirectionChiSquareZ([&](const Point2& u) { return SampleStrategy(lobe, wo, u); },
                                      [&](const Vec3& wi) { return StrategyPdf(lobe, wo, wi); },
                                      samples, 11);
}

TEST(MicrofacetSampling, SamplersMatchTheirPdfsByChiSquare) {
  for (const char* name : {"ggx", "beckmann"}) {
    for (double alpha : {0.1, 0.3, 0.7}) {
      const Model model =
          ParseModel(std::string(name) + ":rho_d=0:f0=1:alpha=" + std::to_string(alpha));
      const LobeCoordinates lobe = model.Lobe();
      for (double theta_deg : {0.0, 35.0, 75.0}) {
        const Vec3 wo = SphericalDirection(DegToRad(theta_deg), 0.3);
        // p < 1e-4 under the null hypothesis: z > 3.7.
        EXPECT_LT(SamplerChiSquareZ(lobe, wo, 200000), 3.7)
            << name << " alpha " << alpha << " theta_o " << theta_deg;
      }
    }
  }
}

// GGX's visible-normal density integrates to 1 over the half vectors and makes the importance
// estimate of the lobe's albedo agree with the quadrature.
TEST(MicrofacetSampling, VisibleNormalImportanceAgreesWithQuadrature) {
  const Model model = ParseModel("ggx:rho_d=0.2:f0=0.04,0.5,1:alpha=0.2");
  for (double theta_deg : {0.0, 45.0, 80.0}) {
    AlbedoOptions importance;
    importance.method = AlbedoMethod::kImportance;
    importance.samples = 200000;
    const AlbedoEstimate sampled =
        ModelDirectionalAlbedo(model, DegToRad(theta_deg), importance, 3);
    const AlbedoEstimate quadrature =
        ModelDirectionalAlbedo(model, DegToRad(theta_deg), AlbedoOptions{});
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(sampled.albedo[c], quadrature.albedo[c], 4 * sampled.error[c] + 1e-6)
          << theta_deg << " channel " << c;
    }
  }
}

}  // namespace
}  // namespace brdf
