// The preview's single-precision hot path against its double reference (core/float_math.h,
// lobe_sampler.h, the float environment draw and the float evaluators): polynomials against
// libm; each sampler against its own pdf (a chi-square test over bins of the lobe's polar
// angle, the pdf integrating to one, the environment's importance-sampled integral against
// uniform sampling); the float pdfs against StrategyPdf, the float evaluators against Eval.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "core/angles.h"
#include "core/float_math.h"
#include "core/sampling.h"
#include "energy/monte_carlo.h"
#include "io/formats.h"
#include "models/common.h"
#include "models/model_string.h"
#include "render/environment.h"
#include "render/lobe_sampler.h"
#include "render/material.h"
#include "test_util.h"

namespace brdf {
namespace {

// A uniform direction on the sphere.
Vec3 UniformSphere(std::mt19937_64& random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double z = 1.0 - 2.0 * unit(random), phi = 2.0 * kPi * unit(random);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

TEST(RenderFloat, PolynomialsMatchLibmToAFewFloatUlps) {
  double worst_sincos = 0.0, worst_atan2 = 0.0;
  for (int k = 0; k <= 100000; ++k) {
    const float t = static_cast<float>(k) / 100000.0f;
    float sine, cosine;
    SinCosTurn(t, &sine, &cosine);
    worst_sincos = std::max({worst_sincos, std::abs(sine - std::sin(2.0 * kPi * t)),
                             std::abs(cosine - std::cos(2.0 * kPi * t))});
  }
  std::mt19937_64 random(1);
  std::uniform_real_distribution<float> coordinate(-1.0f, 1.0f);
  for (int k = 0; k < 200000; ++k) {
    const float y = coordinate(random), x = coordinate(random);
    worst_atan2 = std::max(worst_atan2, std::abs(Atan2(y, x) - std::atan2(double{y}, double{x})));
  }
  // The axes and the origin, exactly where libm puts them.
  EXPECT_EQ(Atan2(0.0f, 0.0f), 0.0f);
  EXPECT_NEAR(Atan2(1.0f, 0.0f), kPi / 2, 1e-7);
  EXPECT_NEAR(Atan2(0.0f, -1.0f), kPi, 1e-7);
  EXPECT_NEAR(Atan2(-1.0f, -1.0f), -0.75 * kPi, 1e-7);
  // 1e-6 rad: a thousandth of a 4k environment's pixel (1.5e-3 rad).
  EXPECT_LT(worst_sincos, 1e-6);
  EXPECT_LT(worst_atan2, 1e-6);
  for (float d : {1e-9f, 1e-6f, 1e-3f, 0.1f, 0.9f}) {
    EXPECT_NEAR(LogOneMinus(d), std::log1p(-double{d}), 2e-7 * std::abs(std::log1p(-double{d})));
  }
  for (float x : {-20.0f, -1.0f, -0.5f, -0.25f, -1e-3f, -1e-8f}) {
    EXPECT_NEAR(ExpMinusOne(x), std::expm1(double{x}), 3e-7 * std::abs(std::expm1(double{x})));
  }
  // -inf (log 0 in the power cosine's warp) gives -1: the lobe's rim.
  EXPECT_EQ(ExpMinusOne(-std::numeric_limits<float>::infinity()), -1.0f);
  // exp over the range a density's exponent takes (0 down to the normal floats' end, then 0)
  // and log over every binade of (0, 1] and beyond: a few float ulps relative.
  double worst_exp = 0.0, worst_log = 0.0;
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int k = 0; k < 200000; ++k) {
    const float x = -87.0f * unit(random);
    worst_exp = std::max(worst_exp, std::abs(ExpNonPositive(x) / std::exp(double{x}) - 1.0));
    const float w = std::ldexp(0.5f + unit(random), -static_cast<int>(k % 127)) * 2.0f;
    worst_log = std::max(worst_log, std::abs(LogPositive(w) - std::log(double{w})) /
                                        std::max(1.0, std::abs(std::log(double{w}))));
  }
  EXPECT_LT(worst_exp, 5e-7);
  EXPECT_LT(worst_log, 3e-7);
  EXPECT_EQ(ExpNonPositive(0.0f), 1.0f);
  EXPECT_EQ(ExpNonPositive(-100.0f), 0.0f);
  EXPECT_EQ(ExpNonPositive(-std::numeric_limits<float>::infinity()), 0.0f);
  EXPECT_EQ(LogPositive(1.0f), 0.0f);
}

// The lobes the renderer draws from: power cosines in each frame, up to a sharp one, and the
// microfacet normals of ggx and beckmann (their own distributions: ggx's visible normals drawn
// and weighed in float, beckmann's normals in double).
std::vector<std::pair<std::string, LobeCoordinates>> Lobes() {
  return {{"normal e=5", {kNormalFrame, 5.0}},
          {"mirror e=50", ParseModel("phong:n=50").Lobe()},
          {"retro e=40", ParseModel("lambert+retro:n_r=40").Lobe()},
          {"half e=300", {kHalfVectorFrame, 300.0}},
          {"half e=20000", {kHalfVectorFrame, 20000.0}},
          {"ggx", ParseModel("ggx:alpha=0.1").Lobe()},
          {"beckmann", ParseModel("beckmann:alpha=0.2").Lobe()}};
}

TEST(RenderFloat, LobeSamplerDrawsItsOwnPdfWhichIsStrategyPdf) {
  const Vec3 wo_double = SphericalDirection(0.6, 0.4);
  const Vec3f wo = wo_double.cast<float>();
  for (const auto& [name, lobe] : Lobes()) {
    const LobeTechnique technique(lobe);
    const LobeSampler sampler(technique, wo);
    std::mt19937_64 random(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    // The float pdf is energy/monte_carlo.cpp's StrategyPdf.
    for (int k = 0; k < 2000; ++k) {
      const Vec3f wi = sampler.Sample(unit(random), unit(random));
      const double reference = StrategyPdf(lobe, wo_double, wi.cast<double>().normalized());
      ASSERT_NEAR(sampler.Pdf(wi), reference, 1e-3 * reference + 1e-6) << name;
    }
    // Chi-square over 20 bins of equal probability in the polar angle about the lobe's axis
    // (for a half-vector lobe, of the half vector): the lobe's mass beyond the drawn angle is
    // uniform for a correct sampler. (Visible normals depend on wo and have no such closed
    // form; energy/monte_carlo.cpp draws them, and its own tests check it.)
    if (lobe.distribution != nullptr && lobe.distribution->sample_visible != nullptr) continue;
    const int draws = 200000, bins = 20;
    std::vector<int> counts(bins, 0);
    for (int k = 0; k < draws; ++k) {
      const Vec3 w = sampler.Sample(unit(random), unit(random)).cast<double>().normalized();
      // The axes written out, not asked of the frame: the mirror direction, wo, the normal.
      double cos_beta = w.z();
      if (name.rfind("mirror", 0) == 0) cos_beta = w.dot(MirrorDirection(wo_double));
      if (name.rfind("retro", 0) == 0) cos_beta = w.dot(wo_double);
      if (lobe.frame.half_vector) cos_beta = (w + wo_double).normalized().z();
      const double mass = LobeMassBeyond(lobe, cos_beta);
      ++counts[std::clamp(static_cast<int>((1.0 - mass) * bins), 0, bins - 1)];
    }
    double chi_square = 0.0;
    const double expected = static_cast<double>(draws) / bins;
    for (int count : counts) chi_square += (count - expected) * (count - expected) / expected;
    // 19 degrees of freedom: the 99.9th percentile is 43.8.
    EXPECT_LT(chi_square, 43.8) << name;
  }
}

// The float visible-normal draw (the renderer's) is the double one (energy/monte_carlo.cpp's,
// whose tests check it against its density) to float precision, for the same uniforms, from
// normal to grazing views and from smooth to rough: the same warp, not merely a similar one.
TEST(RenderFloat, FloatVisibleNormalDrawIsTheDoubleOne) {
  const LobeDistribution& ggx = *ParseModel("ggx:alpha=0.1").Lobe().distribution;
  ASSERT_NE(ggx.sample_visible_float, nullptr);
  std::mt19937_64 random(19);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0;
  for (double alpha : {0.01, 0.035, 0.2, 1.0}) {
    for (double theta_o : {0.0, 0.5, 1.2, 1.55}) {
      const Vec3 wo = SphericalDirection(theta_o, 0.7);
      for (int k = 0; k < 2000; ++k) {
        // Uniforms that are floats already, so that both draws start from the same numbers.
        const float u0 = static_cast<float>(unit(random)), u1 = static_cast<float>(unit(random));
        const Vec3 expected = ggx.sample_visible(wo, u0, u1, alpha);
        Vec3f drawn_float;
        ggx.sample_visible_float(wo.cast<float>(), &u0, &u1, 1, &drawn_float.x(), &drawn_float.y(),
                                 &drawn_float.z(), static_cast<float>(alpha));
        const Vec3 drawn = drawn_float.cast<double>();
        ASSERT_NEAR(drawn.norm(), 1.0, 1e-6);
        worst = std::max(worst, (drawn - expected).norm());
      }
    }
  }
  // 1e-4 rad at worst (float's digits of sqrt(1 - p^2) near the projected disk's rim): a
  // fifteenth of a 4k environment's pixel (1.5e-3 rad), far below the noise.
  EXPECT_LT(worst, 2e-4);
}

TEST(RenderFloat, LobePdfIntegratesToOneOverTheSphere) {
  const Vec3f wo = SphericalDirection(0.3, 2.0).cast<float>();
  std::mt19937_64 random(11);
  for (const auto& [name, lobe] : Lobes()) {
    if (lobe.frame.half_vector && lobe.distribution == nullptr && lobe.exponent > 1000.0) {
      continue;  // too sharp for uniform sampling; the chi-square test covers it
    }
    const LobeTechnique technique(lobe);
    const LobeSampler sampler(technique, wo);
    double integral = 0.0;
    double squares = 0.0;
    const int n = 1000000;
    for (int k = 0; k < n; ++k) {
      const double value = sampler.Pdf(UniformSphere(random).cast<float>()) * 4.0 * kPi;
      integral += value;
      squares += value * value;
    }
    // Within 5 standard errors of the uniform-sampling estimate (a few per cent).
    const double mean = integral / n;
    const double standard_error = std::sqrt((squares / n - mean * mean) / n);
    EXPECT_NEAR(mean, 1.0, 5.0 * standard_error) << name;
    EXPECT_LT(standard_error, 0.01) << name;
  }
}

TEST(RenderFloat, MisPdfIsThePdfInsideTheCoreAndNegligibleOutside) {
  const Vec3f wo = SphericalDirection(0.5, 1.0).cast<float>();
  std::mt19937_64 random(13);
  for (const auto& [name, lobe] : Lobes()) {
    const LobeTechnique technique(lobe);
    const LobeSampler sampler(technique, wo);
    for (int k = 0; k < 20000; ++k) {
      const Vec3f wi = UniformSphere(random).cast<float>();
      const float pdf = sampler.Pdf(wi), weighted = sampler.MisPdf(wi);
      if (weighted > 0.0f) {
        // The pdf itself, or for a distribution its table, within the interpolation's error.
        if (lobe.distribution == nullptr) {
          ASSERT_EQ(weighted, pdf) << name;
        } else {
          ASSERT_NEAR(weighted, pdf, 0.01 * pdf + 1e-6) << name;
        }
      } else {
        // Outside the core the lobe's density of its axis variable (wi, or the half vector)
        // is below a thousandth of the cosine's peak.
        const double axis_density =
            lobe.frame.half_vector ? LobeDensity(lobe, (wi + wo).normalized().z()) : pdf;
        ASSERT_LT(axis_density, LobeTechnique::kCoreDensity * 1.01) << name;
      }
    }
  }
}

TEST(RenderFloat, EnvironmentFloatDrawFollowsItsPdf) {
  Image map(64, 32);
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 64; ++x) {
      for (int c = 0; c < 3; ++c) map.pixel(x, y)[c] = 0.05f + 0.01f * x + 0.02f * c;
    }
  }
  for (int c = 0; c < 3; ++c) map.pixel(40, 9)[c] = 200.0f;  // a sun
  const Environment environment(map);
  std::mt19937_64 random(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const int n = 400000;
  double by_importance = 0.0, by_uniform = 0.0;
  int relocated = 0;
  for (int k = 0; k < n; ++k) {
    const uint64_t bits = random();
    float u, v, x, y, z, sin_theta;
    const uint32_t pixel =
        environment.DrawFloat(environment.SlotOf(bits), bits, unit(random), &u, &v);
    Environment::DirectionAt(u, v, &x, &y, &z, &sin_theta);
    const Environment::Texel& texel = environment.texel(pixel);
    const float pdf = Environment::PdfFloat(texel, sin_theta);
    ASSERT_GT(pdf, 0.0f);
    by_importance += texel.rgb[1] / pdf;
    // The direction lies in the pixel drawn, with the double pdf there (up to directions within
    // rounding of a pixel's edge).
    float located_sin_theta;
    const Vec3 direction = Vec3(x, y, z).normalized();
    relocated += environment.LocateFloat(x, y, z, &located_sin_theta) != pixel ||
                 std::abs(pdf - environment.Pdf(direction)) > 1e-3 * pdf;
    const Vec3 w = UniformSphere(random);
    by_uniform += environment.Radiance(w)[1] * 4.0 * kPi;
  }
  EXPECT_LT(relocated, n / 10000);
  EXPECT_NEAR(by_importance / n, by_uniform / n, 0.02 * by_uniform / n);
}

TEST(RenderFloat, FloatEvaluatorsAgreeWithEval) {
  testing::ScratchDir dir;
  // Scattered samples of a glossy model: the tabulated interpolant (a float copy of its table).
  const std::string file = dir.File("glossy.csv");
  WriteMeasurement(testing::ScatteredSamplesOf(ParseModel("blinn-phong:rho_d=0.2:rho_s=0.5:m=60")),
                   file);
  std::mt19937_64 random(17);
  for (const std::string& spec :
       {std::string("phong:rho_d=0.3:rho_s=0.5:n=400"), std::string("ggx:alpha=0.05"),
        std::string("beckmann:alpha=0.3"), std::string("blinn-phong-exact:m=40000"), file}) {
    const std::unique_ptr<Material> material = LoadMaterial(spec);
    for (int k = 0; k < 5000; ++k) {
      Vec3 wi = UniformSphere(random), wo = UniformSphere(random);
      wi.z() = std::abs(wi.z());
      wo.z() = std::abs(wo.z());
      if (k % 2 == 0) wi = Reflect(wo, (Vec3(0, 0, 1) + 0.05 * UniformSphere(random)).normalized());
      const Vec3f wi_float = wi.cast<float>(), wo_float = wo.cast<float>();
      // Against Eval at the float directions: the difference is then float arithmetic alone.
      const Rgb expected = material->Eval(wi_float.cast<double>(), wo_float.cast<double>());
      const RgbF value = material->EvalFloat(wi_float, wo_float);
      for (int c = 0; c < 3; ++c) {
        ASSERT_NEAR(value[c], expected[c], 1e-3 * std::abs(expected[c]) + 1e-6)
            << spec << " " << wi.transpose() << " " << wo.transpose();
      }
    }
  }
}

TEST(RenderFloat, PolynomialPowerIsPow) {
  // exp(e ln x) in float: a few float ulps, plus the rounding of e ln x, which the power scales
  // by |e ln x| (the same order as rounding x itself to float costs, models/common.h).
  for (float e : {0.0f, 0.5f, 1.0f, 8.0f, 200.0f, 5000.0f, 16000.0f}) {
    for (int k = 1; k <= 16000; ++k) {
      const float x = 1.0f - std::ldexp(static_cast<float>(k), -14) * (k % 3 == 0 ? 1e-3f : 1.0f);
      const double expected = std::pow(double{x}, double{e});
      if (!(expected > 1e-30)) continue;
      const double log_size = std::abs(e * std::log(double{x}));
      ASSERT_NEAR(models::ClampedPow(x, e), expected, 0x1.0p-21 * (1.0 + log_size) * expected)
          << x << "^" << e;
    }
  }
  EXPECT_EQ(models::ClampedPow(0.0f, 2.0f), 0.0f);
  EXPECT_EQ(models::ClampedPow(-0.5f, 2.0f), 0.0f);
  EXPECT_EQ(models::ClampedPow(1.0f, 300.0f), 1.0f);
}

TEST(RenderFloat, BatchEvaluationIsEvalFloat) {
  std::mt19937_64 random(23);
  for (const std::string& spec :
       {std::string("blinn-phong:rho_d=0.3:rho_s=0.5:m=200"), std::string("phong:n=400"),
        std::string("ggx:rho_d=0.1:f0=0.9,0.5,0.2:alpha=0.05"), std::string("beckmann:alpha=0.3"),
        std::string("lambert:rho_d=0.4")}) {
    const std::unique_ptr<Material> material = LoadMaterial(spec);
    for (int trial = 0; trial < 200; ++trial) {
      Vec3 wo = UniformSphere(random);
      wo.z() = std::abs(wo.z());
      // 24 directions (a chunk of 16 and one of 8), some below the horizon, some near the
      // mirror direction.
      float x[24], y[24], z[24];
      for (int k = 0; k < 24; ++k) {
        Vec3 wi = UniformSphere(random);
        if (k % 3 == 0)
          wi = Reflect(wo, (Vec3(0, 0, 1) + 0.03 * UniformSphere(random)).normalized());
        x[k] = static_cast<float>(wi.x()), y[k] = static_cast<float>(wi.y());
        z[k] = static_cast<float>(wi.z());
      }
      const Vec3f wo_float = wo.cast<float>();
      RgbF batch[24];
      material->EvalFloatBatch(x, y, z, wo_float, 24, batch);
      for (int k = 0; k < 24; ++k) {
        const RgbF single = material->EvalFloat(Vec3f(x[k], y[k], z[k]), wo_float);
        for (int c = 0; c < 3; ++c) ASSERT_EQ(batch[k][c], single[c]) << spec << " " << k;
      }
    }
  }
}

}  // namespace
}  // namespace brdf
