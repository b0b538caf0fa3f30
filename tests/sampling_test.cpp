// The warps of energy/sampling.h against their pdfs: moments of the drawn directions match the
// densities' closed forms, the pdfs integrate to one, and the half-vector Jacobian maps the
// density of h onto the density of wi (its reciprocal integrates to the solid angle reached).
#include "core/sampling.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/angles.h"
#include "core/rng.h"
#include "energy/monte_carlo.h"

namespace brdf {
namespace {

constexpr int kDraws = 200000;

TEST(Sampling, CosineHemisphereMomentsAndPdf) {
  Rng random(0, 3);
  double sum_cos = 0, sum_cos_cubed_over_pdf = 0;
  for (int k = 0; k < kDraws; ++k) {
    const Vec3 w = SampleCosineHemisphere(random.Uniform2D());
    ASSERT_NEAR(w.norm(), 1.0, 1e-12);
    ASSERT_GE(w.z(), 0.0);
    sum_cos += w.z();
    sum_cos_cubed_over_pdf += std::pow(w.z(), 3) / CosineHemispherePdf(w.z());
  }
  // E[cos] under cos/pi is ∫ cos^2 dω / pi = 2/3; ∫ cos^3 dω = 2 pi / 4.
  EXPECT_NEAR(sum_cos / kDraws, 2.0 / 3.0, 3e-3);
  EXPECT_NEAR(sum_cos_cubed_over_pdf / kDraws, 0.5 * kPi, 5e-3);
}

TEST(Sampling, PowerCosineLobeMomentMatchesItsDensity) {
  for (double exponent : {1.0, 10.0, 1000.0}) {
    Rng random(static_cast<uint64_t>(exponent), 5);
    double sum_cos = 0;
    for (int k = 0; k < kDraws; ++k)
      sum_cos += SamplePowerCosineLobe(random.Uniform2D(), exponent).z();
    // E[cos] = ∫ cos (e+1)/(2 pi) cos^e dω = (e+1)/(e+2).
    EXPECT_NEAR(sum_cos / kDraws, (exponent + 1) / (exponent + 2), 2e-3) << exponent;
  }
}

TEST(Sampling, PowerCosinePdfIntegratesToOne) {
  // Estimate ∫ pdf dω with uniform directions on the upper hemisphere (pdf 1/(2 pi)).
  Rng random(0, 7);
  double lobe = 0;
  for (int k = 0; k < kDraws; ++k) {
    const Point2 u = random.Uniform2D();
    const double cos_theta = 1.0 - u.x();
    const double sin_theta = std::sqrt(1.0 - cos_theta * cos_theta);
    const Vec3 w(sin_theta * std::cos(2 * kPi * u.y()), sin_theta * std::sin(2 * kPi * u.y()),
                 cos_theta);
    lobe += PowerCosineLobePdf(w.z(), 4.0) * 2 * kPi;
  }
  EXPECT_NEAR(lobe / kDraws, 1.0, 1e-2);
}

TEST(Sampling, HalfVectorJacobianMapsDensityOfHToDensityOfWi) {
  // Draw wi through h; E[1{wi above} / pdf(wi)] is the solid angle of the reachable upper
  // hemisphere, 2 pi, for any wo above the horizon.
  for (double theta_o_deg : {0.0, 35.0, 70.0}) {
    const Vec3 wo = SphericalDirection(DegToRad(theta_o_deg), 1.0);
    // Exponent 0 (h uniform) keeps 1/pdf = 8 pi (wo.h) bounded, so the estimate converges fast.
    const LobeCoordinates half_vector{kHalfVectorFrame, 0.0};
    Rng random(0, 11);
    double solid_angle = 0;
    for (int k = 0; k < kDraws; ++k) {
      const Vec3 wi = SampleStrategy(half_vector, wo, random.Uniform2D());
      ASSERT_NEAR(wi.norm(), 1.0, 1e-9);
      if (wi.z() > 0) solid_angle += 1.0 / StrategyPdf(half_vector, wo, wi);
    }
    EXPECT_NEAR(solid_angle / kDraws, 2 * kPi, 0.05) << theta_o_deg;
  }
}

TEST(Sampling, FrameIsOrthonormalAtThePoles) {
  for (const Vec3& z : {Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(0.6, 0, 0.8), Vec3(0, -1, 0)}) {
    const Frame frame = Frame::FromZ(z);
    EXPECT_NEAR(frame.x.dot(frame.y), 0.0, 1e-12);
    EXPECT_NEAR(frame.x.dot(frame.z), 0.0, 1e-12);
    EXPECT_NEAR(frame.x.norm(), 1.0, 1e-12);
    EXPECT_NEAR(frame.y.norm(), 1.0, 1e-12);
    EXPECT_TRUE(frame.FromLocal(Vec3::UnitZ()).isApprox(z));
    EXPECT_TRUE(frame.ToLocal(frame.FromLocal(Vec3(0.1, 0.2, 0.3))).isApprox(Vec3(0.1, 0.2, 0.3)));
  }
}

TEST(Sampling, RngIsUniformAndSeedDependent) {
  Rng random(0, 1), other(1, 1);
  double sum = 0;
  bool differs = false;
  for (int k = 0; k < kDraws; ++k) {
    const double u = random.Uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    differs |= u != other.Uniform();
  }
  EXPECT_NEAR(sum / kDraws, 0.5, 3e-3);
  EXPECT_TRUE(differs);
}

// Below(n) is uniform over {0, ..., n - 1}: Pearson's chi-square over the n bins, against the
// 99.9 % point of chi-square with n - 1 = 6 degrees of freedom (22.46).
TEST(Sampling, RngBelowIsUniformByChiSquare) {
  constexpr uint64_t kBins = 7;
  constexpr int kCount = 70000;
  Rng random(3, 42);
  std::vector<int> counts(kBins, 0);
  for (int k = 0; k < kCount; ++k) {
    const uint64_t value = random.Below(kBins);
    ASSERT_LT(value, kBins);
    ++counts[value];
  }
  const double expected = static_cast<double>(kCount) / kBins;
  double chi_square = 0;
  for (const int count : counts) chi_square += (count - expected) * (count - expected) / expected;
  EXPECT_LT(chi_square, 22.46);
}

// Box-Muller normals have mean 0 and variance 1; Poisson counts have their mean as variance.
TEST(Sampling, RngNormalAndPoissonMoments) {
  Rng random(5, 42);
  double sum = 0, square = 0;
  for (int k = 0; k < kDraws; ++k) {
    const double x = random.Normal();
    sum += x;
    square += x * x;
  }
  EXPECT_NEAR(sum / kDraws, 0.0, 5.0 / std::sqrt(kDraws));
  EXPECT_NEAR(square / kDraws, 1.0, 5.0 * std::sqrt(2.0 / kDraws));
  for (const double mean : {3.0, 50.0}) {
    double total = 0, total_square = 0;
    for (int k = 0; k < kDraws; ++k) {
      const double n = random.Poisson(mean);
      total += n;
      total_square += n * n;
    }
    const double m = total / kDraws;
    EXPECT_NEAR(m, mean, 5.0 * std::sqrt(mean / kDraws));
    EXPECT_NEAR(total_square / kDraws - m * m, mean, 0.05 * mean);
  }
}

}  // namespace
}  // namespace brdf
