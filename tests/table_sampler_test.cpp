// The importance sampler of dense tables (render/table_sampler.h) against the table it is built
// from: a chi-square test of its draws against its own density, the density against the table's
// f cos(theta_i) (the estimate f cos / pdf nearly constant over the lobe, far more so than
// with cosine sampling), and the rendered sphere of a glossy MERL table in the white furnace:
// its albedo within the noise, with far less noise than without the sampler.
#include "render/table_sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/angles.h"
#include "core/colour.h"
#include "io/merl.h"
#include "models/model_string.h"
#include "render/environment.h"
#include "render/material.h"
#include "render/sphere.h"
#include "test_util.h"

namespace brdf {
namespace {

// A glossy table: Lambert plus a normalized Blinn-Phong lobe, in closed form.
Rgb Glossy(const Vec3& wi, const Vec3& wo) {
  if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
  const double cos_h = (wi + wo).normalized().z();
  const double lobe = (200.0 + 2.0) / (8.0 * kPi) * std::pow(std::max(0.0, cos_h), 200.0);
  return Rgb(0.2, 0.1, 0.05) / kPi + Rgb::Constant(0.5 * lobe);
}

TEST(TableSampler, DrawsFollowItsDensityChiSquare) {
  const TableSampler sampler(Glossy);
  for (double theta_o : {0.3, 1.1}) {
    const Vec3 wo = SphericalDirection(theta_o, 0.7);  // phi_o below
    // Bins of the half vector h: in u = sqrt(theta_h / (pi/2)), half a sampler row wide up to
    // u = 1/2 (so that the draws inside a row are checked too) and four rows wide beyond; in
    // phi_h - phi_o, two sampler columns wide. Inside a bin the density of h is then constant,
    // but for the horizon's cut, and the expected counts are the density integrated on a 16 x 16
    // grid of midpoints (dwi = 4 (wo.h) dwh, dwh = pi u sin(theta_h) du dphi, from theta_h =
    // u^2 pi / 2).
    constexpr int kFineU = TableSampler::kThetaBins, kCoarseU = TableSampler::kThetaBins / 8;
    constexpr int kU = kFineU + kCoarseU, kPhi = TableSampler::kPhiBins / 2, kSub = 16;
    auto u_edge = [&](int row) {
      return row <= kFineU ? 0.5 * row / kFineU : 0.5 + 0.5 * (row - kFineU) / kCoarseU;
    };
    const double phi_o = 0.7;
    const int bins = kU * kPhi + 1;  // the last: wi below the horizon
    std::vector<double> expected(bins, 0.0);
    auto bin_of_h = [&](const Vec3& h) {
      const double u = std::sqrt(std::acos(std::clamp(h.z(), -1.0, 1.0)) / (0.5 * kPi));
      int row = u < 0.5 ? static_cast<int>(u * 2 * kFineU)
                        : kFineU + static_cast<int>((u - 0.5) * 2 * kCoarseU);
      row = std::clamp(row, 0, kU - 1);
      double phi = std::atan2(h.y(), h.x()) - phi_o;
      phi -= 2 * kPi * std::floor(phi / (2 * kPi));
      const int column = std::min(static_cast<int>(phi / (2 * kPi) * kPhi), kPhi - 1);
      return row * kPhi + column;
    };
    double total = 0.0;
    for (int row = 0; row < kU; ++row) {
      const double u0 = u_edge(row), u1 = u_edge(row + 1);
      for (int column = 0; column < kPhi; ++column) {
        double integral = 0.0;
        for (int a = 0; a < kSub; ++a) {
          const double u = u0 + (a + 0.5) / kSub * (u1 - u0);
          const double theta_h = u * u * 0.5 * kPi;
          for (int b = 0; b < kSub; ++b) {
            const double phi = phi_o + (column + (b + 0.5) / kSub) * 2 * kPi / kPhi;
            const Vec3 h = SphericalDirection(theta_h, phi);
            const Vec3 wi = 2.0 * wo.dot(h) * h - wo;
            const double jacobian = 4.0 * wo.dot(h) * kPi * u * std::sin(theta_h);
            integral += sampler.Pdf(wo, wi) * jacobian;
          }
        }
        integral *= (u1 - u0) / kSub * (2 * kPi / kPhi) / kSub;
        expected[row * kPhi + column] = integral;
        total += integral;
      }
    }
    EXPECT_LE(total, 1.0 + 1e-3) << theta_o;
    expected.back() = std::max(0.0, 1.0 - total);

    const int draws = 1000000;
    std::vector<double> counts(bins, 0.0);
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int k = 0; k < draws; ++k) {
      const Vec3 wi = sampler.Sample(wo, unit(random), unit(random));
      if (wi.z() <= 0.0) {
        ++counts.back();
        continue;
      }
      ++counts[bin_of_h((wi + wo).normalized())];
    }
    // Pearson's statistic over bins expecting at least 5 draws, the rest pooled.
    double chi_square = 0.0, pooled_count = 0.0, pooled_expected = 0.0;
    int degrees = -1;
    for (int bin = 0; bin < bins; ++bin) {
      const double e = expected[bin] * draws;
      if (e < 5.0) {
        pooled_count += counts[bin];
        pooled_expected += e;
        continue;
      }
      chi_square += (counts[bin] - e) * (counts[bin] - e) / e;
      ++degrees;
    }
    if (pooled_expected >= 5.0) {
      chi_square +=
          (pooled_count - pooled_expected) * (pooled_count - pooled_expected) / pooled_expected;
      ++degrees;
    }
    ASSERT_GT(degrees, 100) << theta_o;
    // The 99.9th percentile of chi-square with k degrees of freedom, Wilson-Hilferty.
    const double z = 3.09, k = degrees;
    const double limit = k * std::pow(1.0 - 2.0 / (9.0 * k) + z * std::sqrt(2.0 / (9.0 * k)), 3);
    EXPECT_LT(chi_square, limit) << "theta_o " << theta_o << ", " << degrees << " dof";
  }
}

TEST(TableSampler, DensityFollowsTheTable) {
  // Drawn from the table, f cos / pdf varies little over the draws (it would be constant for a
  // sampler exactly proportional to the table), and its mean is the directional albedo that
  // cosine sampling finds with far more noise.
  const TableSampler sampler(Glossy);
  const Vec3 wo = SphericalDirection(0.5, 2.0);
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int draws = 200000;
  double sum = 0.0, squares = 0.0, cosine_sum = 0.0, cosine_squares = 0.0;
  for (int k = 0; k < draws; ++k) {
    const Vec3 wi = sampler.Sample(wo, unit(random), unit(random));
    const double pdf = sampler.Pdf(wo, wi);
    const double value = wi.z() > 0.0 && pdf > 0.0 ? Luminance(Glossy(wi, wo)) * wi.z() / pdf : 0;
    sum += value;
    squares += value * value;
    // Cosine sampling: f cos / (cos / pi) = pi f.
    const double r = std::sqrt(unit(random)), phi = 2 * kPi * unit(random);
    const Vec3 wc(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1 - r * r)));
    const double cosine_value = kPi * Luminance(Glossy(wc, wo));
    cosine_sum += cosine_value;
    cosine_squares += cosine_value * cosine_value;
  }
  const double mean = sum / draws, cosine_mean = cosine_sum / draws;
  const double deviation = std::sqrt(squares / draws - mean * mean);
  const double cosine_deviation = std::sqrt(cosine_squares / draws - cosine_mean * cosine_mean);
  const double cosine_error = cosine_deviation / std::sqrt(draws);
  EXPECT_NEAR(mean, cosine_mean, 4.0 * cosine_error + 4.0 * deviation / std::sqrt(draws));
  EXPECT_LT(deviation / mean, 0.15);
  EXPECT_GT(cosine_deviation / deviation, 10.0);
}

// A material without its sampler: the renderer then has the environment and cosine only.
class WithoutSampler : public Material {
 public:
  explicit WithoutSampler(const Material& material) : material_(material) {}
  Rgb Eval(const Vec3& wi, const Vec3& wo) const override { return material_.Eval(wi, wo); }
  std::string Describe() const override { return material_.Describe(); }

 private:
  const Material& material_;
};

// The directional albedo of `material` (luminance) at viewing angle theta_o, by quadrature in
// the half vector: u = sqrt(theta_h / (pi/2)) on a 400-point midpoint grid (fine where a glossy
// lobe is), 120 points in phi_h; dwi = 4 (wo.h) pi u sin(theta_h) du dphi_h.
double Albedo(const Material& material, double theta_o) {
  const Vec3 wo = SphericalDirection(theta_o, 0.0);
  constexpr int kU = 400, kPhi = 120;
  double sum = 0.0;
  for (int a = 0; a < kU; ++a) {
    const double u = (a + 0.5) / kU, theta_h = u * u * 0.5 * kPi;
    for (int b = 0; b < kPhi; ++b) {
      const Vec3 h = SphericalDirection(theta_h, (b + 0.5) / kPhi * 2 * kPi);
      const Vec3 wi = 2.0 * wo.dot(h) * h - wo;
      if (wi.z() <= 0.0) continue;
      sum +=
          Luminance(material.Eval(wi, wo)) * wi.z() * 4.0 * wo.dot(h) * kPi * u * std::sin(theta_h);
    }
  }
  return sum / kU * (2 * kPi / kPhi);
}

TEST(TableSampler, MerlSphereInTheFurnaceRendersItsAlbedoWithLessNoise) {
  // Under a uniform environment of radiance 1 a pixel shows the directional albedo at its
  // viewing angle. A glossy MERL table rendered with its sampler matches the albedo within 5
  // standard errors everywhere; without it (environment and cosine only, as before the
  // sampler) the true error, against the albedo, is several times larger at equal samples.
  testing::ScratchDir dir;
  MerlTable::Tabulate(Glossy).Write(dir.File("glossy.binary"));
  const std::unique_ptr<Material> table = LoadMaterial(dir.File("glossy.binary"));
  ASSERT_NE(table->MakeSampler(), nullptr);
  const WithoutSampler bare(*table);
  const Environment furnace = Environment::Uniform(Rgb::Ones());
  RenderOptions options;
  options.size = 24;
  options.spp = 64;
  const RenderResult sampled = RenderSphere(*table, {}, &furnace, options);
  const RenderResult unsampled = RenderSphere(bare, {}, &furnace, options);
  EXPECT_EQ(sampled.missing_lookups, 0);
  std::vector<double> albedo;  // at 0, 1, ..., 71 degrees
  for (int degrees = 0; degrees <= 71; ++degrees) {
    albedo.push_back(Albedo(*table, degrees * kPi / 180));
  }
  auto luminance = [](const RenderResult& result, int x, int y) {
    const float* rgba = result.radiance.pixel(x, y);
    return Luminance(Rgb(rgba[0], rgba[1], rgba[2]));
  };
  double squares_sampled = 0.0, squares_unsampled = 0.0;
  int checked = 0;
  for (int y = 0; y < options.size; ++y) {
    for (int x = 0; x < options.size; ++x) {
      const std::optional<Vec3> normal = SphereNormal(x, y, options.size);
      if (!normal) continue;
      const double theta_deg = std::acos(normal->z()) * 180.0 / kPi;
      if (theta_deg >= 70.0) continue;
      const int k = static_cast<int>(theta_deg);
      const double t = theta_deg - k;
      const double expected = (1.0 - t) * albedo[k] + t * albedo[k + 1];
      const double sigma = sampled.luminance_std_error[y * options.size + x];
      const double a = luminance(sampled, x, y), b = luminance(unsampled, x, y);
      EXPECT_NEAR(a, expected, 5.0 * sigma + 0.003 * expected) << x << "," << y;
      squares_sampled += (a - expected) * (a - expected);
      squares_unsampled += (b - expected) * (b - expected);
      ++checked;
    }
  }
  ASSERT_GT(checked, 300);
  EXPECT_GT(std::sqrt(squares_unsampled / squares_sampled), 3.0);
}

}  // namespace
}  // namespace brdf
