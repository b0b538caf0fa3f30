// Image-based acquisition: the rasterizer covers the sphere's disk and interpolates positions
// perspective-correctly (on each pixel's ray); samples equal the model at their (wi, wo)
// within 1%; a fit recovers the parameters within 3%.
#include <gtest/gtest.h>

#include <cmath>

#include "core/angles.h"
#include "gonio/measure.h"
#include "gonio/rasterizer.h"
#include "gonio/sphere_acquisition.h"
#include "gonio_test_util.h"
#include "models/model_string.h"
#include "test_util.h"

namespace brdf::gonio {
namespace {

Instrument IdealCamera() {
  Instrument instrument = testing::IdealInstrument();
  instrument.camera_resolution = 128;
  return instrument;
}

TEST(GonioRasterTest, CoversTheDiskAndInterpolatesOnThePixelRays) {
  const Instrument instrument = IdealCamera();
  const Model model = ParseModel("lambert");
  const SphereAcquisition acquisition(model, instrument);
  const PinholeCamera& camera = acquisition.camera();
  const GBuffer gbuffer = Rasterize(acquisition.mesh(), camera);
  size_t covered = 0;
  double worst_off_ray = 0, worst_radius = 0;
  for (int y = 0; y < camera.resolution; ++y) {
    for (int x = 0; x < camera.resolution; ++x) {
      const size_t pixel = size_t(y) * camera.resolution + x;
      if (!gbuffer.covered(pixel)) continue;
      ++covered;
      const glm::dvec3 to_point = gbuffer.position[pixel] - camera.eye;
      const glm::dvec3 ray = camera.PixelRay(x, y);
      worst_off_ray = std::max(worst_off_ray, glm::length(glm::cross(to_point, ray)));
      worst_radius = std::max(worst_radius, std::abs(glm::length(gbuffer.position[pixel]) - 1));
    }
  }
  // The silhouette is a circle of angular radius asin(1/d) seen through the pinhole.
  const double d = instrument.camera_distance;
  const double radius_pixels =
      std::tan(std::asin(1 / d)) / std::tan(0.5 * camera.vertical_fov) * 0.5 * camera.resolution;
  EXPECT_NEAR(double(covered), kPi * radius_pixels * radius_pixels,
              0.01 * kPi * radius_pixels * radius_pixels);
  EXPECT_LT(worst_off_ray, 1e-9);  // perspective-correct: on the pixel's ray
  // Points lie on the mesh, inside the sphere by at most the sagitta of one segment.
  const double sagitta = 1 - std::cos(kPi / instrument.sphere_segments);
  EXPECT_LT(worst_radius, 2.5 * sagitta);
}

TEST(GonioRasterTest, SphereSamplesMatchTheModelAndAFitRecoversIt) {
  const Model model = ParseModel("blinn-phong:rho_d=0.3:rho_s=0.5:m=200");
  MeasureOptions options;
  options.sample = "sphere:" + model.ToString();
  options.instrument = IdealCamera();
  const Measurement m = Measure(options, MakeSchedule("inplane:step=15"));
  ASSERT_GT(m.samples.size(), 20000u);
  size_t within = 0;
  for (const Sample& s : m.samples) {
    const double truth = model.Eval(s.wi, s.wo)[0];
    within += std::abs(s.value[0] - truth) <= 0.01 * truth;
  }
  EXPECT_EQ(within, m.samples.size());

  // Fit blinn-phong: for a fixed exponent the model is linear in (rho_d, rho_s), solved in
  // closed form (relative least squares); the exponent is found by golden-section search on
  // log m. (The Ceres fitter is not available here; this is the same least-squares problem.)
  const auto solve = [&](double exponent, double* rho_d, double* rho_s) {
    double a11 = 0, a12 = 0, a22 = 0, b1 = 0, b2 = 0;
    for (const Sample& s : m.samples) {
      const double v = s.value[0], w = 1 / (v * v);
      const Vec3 h = (s.wi + s.wo).normalized();
      const double diffuse = kInvPi;
      const double lobe = (exponent + 8) / (8 * kPi) * std::pow(std::max(0.0, h.z()), exponent);
      a11 += w * diffuse * diffuse, a12 += w * diffuse * lobe, a22 += w * lobe * lobe;
      b1 += w * diffuse * v, b2 += w * lobe * v;
    }
    const double det = a11 * a22 - a12 * a12;
    *rho_d = (b1 * a22 - b2 * a12) / det;
    *rho_s = (a11 * b2 - a12 * b1) / det;
    double residual = 0;
    for (const Sample& s : m.samples) {
      const Vec3 h = (s.wi + s.wo).normalized();
      const double fit = *rho_d * kInvPi + *rho_s * (exponent + 8) / (8 * kPi) *
                                               std::pow(std::max(0.0, h.z()), exponent);
      residual += std::pow((fit - s.value[0]) / s.value[0], 2);
    }
    return residual;
  };
  double low = std::log(1.0), high = std::log(1e4);
  const double golden = 0.5 * (std::sqrt(5.0) - 1);
  double rho_d = 0, rho_s = 0;
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double x1 = high - golden * (high - low), x2 = low + golden * (high - low);
    if (solve(std::exp(x1), &rho_d, &rho_s) < solve(std::exp(x2), &rho_d, &rho_s)) {
      high = x2;
    } else {
      low = x1;
    }
  }
  const double exponent = std::exp(0.5 * (low + high));
  solve(exponent, &rho_d, &rho_s);
  EXPECT_NEAR(exponent, 200, 0.03 * 200);
  EXPECT_NEAR(rho_d, 0.3, 0.03 * 0.3);
  EXPECT_NEAR(rho_s, 0.5, 0.03 * 0.5);
}

TEST(GonioRasterTest, SphereRunIsIdenticalWithOneAndTwoThreads) {
  brdf::testing::ScratchDir dir;
  const std::string instrument =
      dir.Write("camera.json", R"({"camera": {"resolution": 48, "sphere_segments": 64}})");
  const std::string common = "measure --quiet --seed 9 --sample sphere:phong:n=50 --instrument " +
                             instrument + " --schedule inplane:step=30 --out ";
  ASSERT_EQ(brdf::testing::RunBrdf(common + dir.File("one.csv") + " --threads 1").exit_status, 0);
  ASSERT_EQ(brdf::testing::RunBrdf(common + dir.File("two.csv") + " --threads 2").exit_status, 0);
  const std::string one = brdf::testing::ReadFileText(dir.File("one.csv"));
  EXPECT_NE(one.find("rasterized at 48x48"), std::string::npos);
  EXPECT_EQ(one, brdf::testing::ReadFileText(dir.File("two.csv")));
}

// The merl schedule writes MERL .binary (the sphere's pixels binned into the half/difference
// cells), and only MERL .binary.
TEST(GonioRasterTest, MerlScheduleWritesMerlBinary) {
  brdf::testing::ScratchDir dir;
  const std::string instrument = dir.Write("camera.json", R"({"camera": {"resolution": 64}})");
  const std::string common =
      "measure --quiet --sample sphere:lambert:rho_d=0.5 --schedule merl --instrument " +
      instrument;
  const auto written = brdf::testing::RunBrdf(common + " --out " + dir.File("s.binary"));
  ASSERT_EQ(written.exit_status, 0) << written.err;
  EXPECT_EQ(brdf::testing::ReadFileText(dir.File("s.binary")).size(), 34992012u);
  const auto refused = brdf::testing::RunBrdf(common + " --out " + dir.File("s.csv"));
  EXPECT_EQ(refused.exit_status, 2);
  EXPECT_NE(refused.err.find("merl"), std::string::npos);
}

}  // namespace
}  // namespace brdf::gonio
