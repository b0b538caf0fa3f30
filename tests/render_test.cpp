// The preview renderer against physics (DESIGN §8): the white furnace, directional lights
// against f E cos(theta_i), importance sampling against its own pdf, determinism.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "core/angles.h"
#include "core/colour.h"
#include "core/errors.h"
#include "core/rng.h"
#include "core/simd.h"
#include "energy/albedo.h"
#include "io/formats.h"
#include "io/merl.h"
#include "models/model_string.h"
#include "render/environment.h"
#include "render/lights.h"
#include "render/material.h"
#include "render/sphere.h"
#include "test_util.h"

namespace brdf {
namespace {

TEST(Render, WhiteFurnaceLambertRendersItsAlbedo) {
  // A Lambertian sphere of albedo 0.8 under a uniform environment of radiance 1 reflects
  // exactly 0.8 everywhere: Lo = (0.8/pi) * integral of cos = 0.8.
  const std::unique_ptr<Material> material = LoadMaterial("lambert:rho_d=0.8");
  const Environment furnace = Environment::Uniform(Rgb::Ones());
  RenderOptions options;
  options.size = 48;
  options.spp = 32;
  const RenderResult result = RenderSphere(*material, {}, &furnace, options);
  ASSERT_GT(result.sphere_pixels, 1500);
  int64_t checked = 0;
  for (int y = 0; y < options.size; ++y) {
    for (int x = 0; x < options.size; ++x) {
      const float* rgba = result.radiance.pixel(x, y);
      if (rgba[3] == 0.0f) continue;
      const double error = result.luminance_std_error[y * options.size + x];
      ASSERT_GT(error, 0.0);
      for (int c = 0; c < 3; ++c) {
        // 5 standard errors: over ~1800 pixels a false alarm has probability ~1e-3.
        ASSERT_NEAR(rgba[c], 0.8, 5.0 * error + 1e-6) << x << "," << y;
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, result.sphere_pixels);
}

TEST(Render, WhiteFurnaceConservingMaterialsNeverExceedOne) {
  const Environment furnace = Environment::Uniform(Rgb::Ones());
  RenderOptions options;
  options.size = 40;
  options.spp = 64;
  // Albedos up to 0.9 (lambert:rho_d=1, exactly 1, would cross 1 + 3 sigma in 0.1% of pixels
  // by chance alone; the 0.8 furnace above checks the estimator's accuracy instead).
  for (const char* spec : {"phong:rho_d=0.3:rho_s=0.6:n=20",
                           "blinn-phong-exact:rho_d=0.2:rho_s=0.7:m=80", "lambert:rho_d=0.9"}) {
    const RenderResult result = RenderSphere(*LoadMaterial(spec), {}, &furnace, options);
    for (int64_t i = 0; i < result.radiance.pixel_count(); ++i) {
      const float* rgba = &result.radiance.rgba[i * 4];
      if (rgba[3] == 0.0f) continue;
      EXPECT_LE(Luminance(Rgb(rgba[0], rgba[1], rgba[2])),
                1.0 + 3.0 * result.luminance_std_error[i] + 1e-6)
          << spec << " pixel " << i;
    }
  }
}

TEST(Render, WhiteFurnaceSharpLobesRenderTheirDirectionalAlbedo) {
  // Under a uniform environment of radiance 1 a pixel shows the directional albedo at its
  // viewing angle, which `brdf energy`'s quadrature computes independently. Lobes this sharp
  // (0.6 and 0.3 degrees wide) are found only by drawing from the lobe: with the environment
  // and the cosine alone the standard error of a pixel would be far above 2 %.
  const Environment furnace = Environment::Uniform(Rgb::Ones());
  RenderOptions options;
  options.size = 40;
  options.spp = 16;
  for (const char* spec :
       {"phong:rho_d=0:rho_s=0.9:n=10000", "blinn-phong-exact:rho_d=0.1:rho_s=0.8:m=40000"}) {
    const Model model = ParseModel(spec);
    AlbedoOptions albedo_options;
    albedo_options.theta_max_deg = 89.0;
    albedo_options.theta_steps = 90;  // 1-degree steps
    const AlbedoCurve curve = ModelAlbedoCurve(model, albedo_options);
    const RenderResult result = RenderSphere(*LoadMaterial(spec), {}, &furnace, options);
    double relative_error_sum = 0.0;
    int checked = 0;
    for (int y = 0; y < options.size; ++y) {
      for (int x = 0; x < options.size; ++x) {
        const std::optional<Vec3> normal = SphereNormal(x, y, options.size);
        if (!normal) continue;
        const double theta_deg = std::acos(normal->z()) * 180.0 / kPi;
        if (theta_deg > 60.0) continue;
        const size_t k = static_cast<size_t>(theta_deg);
        const double t = theta_deg - static_cast<double>(k);
        const double expected = (1.0 - t) * curve.points[k].estimate.albedo[0] +
                                t * curve.points[k + 1].estimate.albedo[0];
        const float* rgba = result.radiance.pixel(x, y);
        const double error = result.luminance_std_error[y * options.size + x];
        EXPECT_NEAR(rgba[0], expected, 5.0 * error + 0.002 * expected)
            << spec << " " << x << "," << y;
        relative_error_sum += error / expected;
        ++checked;
      }
    }
    ASSERT_GT(checked, 500);
    EXPECT_LT(relative_error_sum / checked, 0.02) << spec;
  }
}

// A composition's two lobes in either order are the same material, and the renderer draws from
// the sharper whichever comes first: both orders render the same white-furnace image, equally
// clean (7.6 % relative standard error per pixel at 16 spp). Drawing from the first lobe only,
// the order with the sharp lobe second left it to the environment and the cosine techniques:
// 12.5 %, with fireflies.
TEST(Render, TwoLobesRenderAsCleanInEitherOrder) {
  const Environment furnace = Environment::Uniform(Rgb::Ones());
  RenderOptions options;
  options.size = 40;
  options.spp = 16;
  const char* kOrders[] = {"lambert+ggx+ggx:rho_d=0.1:f0=0.04:alpha=0.005:f0_2=0.04:alpha_2=0.3",
                           "lambert+ggx+ggx:rho_d=0.1:f0=0.04:alpha=0.3:f0_2=0.04:alpha_2=0.005"};
  const RenderResult sharp_first = RenderSphere(*LoadMaterial(kOrders[0]), {}, &furnace, options);
  const RenderResult sharp_second = RenderSphere(*LoadMaterial(kOrders[1]), {}, &furnace, options);
  double first_error = 0, second_error = 0;
  int checked = 0;
  for (int y = 0; y < options.size; ++y) {
    for (int x = 0; x < options.size; ++x) {
      const std::optional<Vec3> normal = SphereNormal(x, y, options.size);
      if (!normal || normal->z() < 0.5) continue;
      const size_t k = static_cast<size_t>(y * options.size + x);
      const double a = sharp_first.radiance.pixel(x, y)[1],
                   b = sharp_second.radiance.pixel(x, y)[1];
      const double error_a = sharp_first.luminance_std_error[k];
      const double error_b = sharp_second.luminance_std_error[k];
      EXPECT_NEAR(a, b, 5.0 * std::hypot(error_a, error_b)) << x << "," << y;
      first_error += error_a / a;
      second_error += error_b / b;
      ++checked;
    }
  }
  ASSERT_GT(checked, 500);
  EXPECT_LT(first_error / checked, 0.1);
  EXPECT_LT(second_error / checked, 0.1);
  EXPECT_NEAR(second_error / first_error, 1.0, 0.25);
}

TEST(Render, DirectionalLightGivesFTimesIrradianceTimesCosine) {
  const Model model = ParseModel("blinn-phong:rho_d=0.5,0.3,0.1:rho_s=0.2:m=40");
  const std::unique_ptr<Material> material = LoadMaterial(model.ToString());
  const DirectionalLight light = ParseDirectionalLight("dir:theta=30:phi=60:lux=683");
  ASSERT_NEAR(light.irradiance[0], 1.0, 1e-12);  // 683 lx at 683 lm/W
  RenderOptions options;
  options.size = 64;
  const RenderResult result = RenderSphere(*material, {light}, nullptr, options);
  const Vec3 wo_world(0, 0, 1);
  int checked = 0;
  for (const auto& [x, y] : std::vector<std::pair<int, int>>{
           {32, 32}, {40, 20}, {10, 30}, {50, 50}, {45, 12}, {20, 5}}) {
    // The camera convention of sphere.h, written out again here.
    const double u = (2.0 * x + 1) / 64 - 1, v = 1 - (2.0 * y + 1) / 64;
    const Vec3 n(u, v, std::sqrt(1 - u * u - v * v));
    const double cos_theta_i = n.dot(light.direction);
    // Any tangent frame will do for an isotropic model: Gram-Schmidt from +x.
    const Vec3 t = (Vec3(1, 0, 0) - n.x() * n).normalized();
    const Vec3 b = n.cross(t);
    const auto local = [&](const Vec3& w) { return Vec3(w.dot(t), w.dot(b), w.dot(n)); };
    const Rgb expected = cos_theta_i > 0 ? Rgb(model.Eval(local(light.direction), local(wo_world)) *
                                               light.irradiance * cos_theta_i)
                                         : Rgb::Zero();
    const float* rgba = result.radiance.pixel(x, y);
    ASSERT_EQ(rgba[3], 1.0f);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(rgba[c], expected[c], 1e-5 * expected[c] + 1e-9) << x << "," << y;
    }
    checked += cos_theta_i > 0;
  }
  EXPECT_GE(checked, 4);
  // No environment: no noise.
  for (float error : result.luminance_std_error) EXPECT_EQ(error, 0.0f);
}

TEST(Render, SameSeedSameImageAnyThreadCountDifferentSeedDifferentNoise) {
  const std::unique_ptr<Material> material = LoadMaterial("phong:rho_d=0.4:rho_s=0.3:n=30");
  Image sky(16, 8);
  for (int64_t i = 0; i < sky.pixel_count(); ++i) {
    for (int c = 0; c < 3; ++c) sky.rgba[i * 4 + c] = 0.1f + 0.01f * static_cast<float>(i % 13);
  }
  const Environment environment(sky);
  RenderOptions options;
  options.size = 24;
  options.spp = 4;
  const RenderResult a = RenderSphere(*material, {}, &environment, options);
  RenderResult b;
  {
    // One thread instead of all of them: the random streams belong to pixels, not threads.
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    b = RenderSphere(*material, {}, &environment, options);
  }
  EXPECT_EQ(a.radiance.rgba, b.radiance.rgba);
  options.seed = 99;
  const RenderResult c = RenderSphere(*material, {}, &environment, options);
  EXPECT_NE(a.radiance.rgba, c.radiance.rgba);
}

// The batch loops' AVX2 paths (the pixel, the lobe's densities, the tabulated interpolant's
// places; core/simd.h) against the baseline's: the same float operations in the same order, so
// the same image bytes, for a power-cosine lobe, a distribution's lobe and a measurement.
TEST(Render, SameImageWithAndWithoutTheAvx2Paths) {
  const bool was = SetAvx2Enabled(true);
  if (!Avx2Enabled()) GTEST_SKIP() << "no AVX2 on this processor: one path only";
  testing::ScratchDir dir;
  const Model glossy = ParseModel("blinn-phong:rho_d=0.2:rho_s=0.5:m=300");
  WriteMeasurement(testing::ScatteredSamplesOf(glossy), dir.File("glossy.csv"));
  // A dim sky with one bright pixel: the lobes' samples find it, the others mostly miss it.
  Image sky(32, 16);
  for (int64_t i = 0; i < sky.pixel_count(); ++i) {
    for (int c = 0; c < 3; ++c) sky.rgba[i * 4 + c] = i == 100 ? 500.0f : 0.05f + 0.01f * (i % 7);
  }
  const Environment environment(sky);
  RenderOptions options;
  options.size = 40;
  options.spp = 24;  // a batch of 16 and one of 8
  for (const std::string& spec :
       {glossy.ToString(), std::string("ggx:rho_d=0.1:alpha=0.05"), dir.File("glossy.csv")}) {
    const std::unique_ptr<Material> material = LoadMaterial(spec);
    SetAvx2Enabled(false);
    const RenderResult baseline = RenderSphere(*material, {}, &environment, options);
    SetAvx2Enabled(true);
    const RenderResult avx2 = RenderSphere(*material, {}, &environment, options);
    EXPECT_EQ(baseline.radiance.rgba, avx2.radiance.rgba) << spec;
    EXPECT_EQ(baseline.luminance_std_error, avx2.luminance_std_error) << spec;
  }
  SetAvx2Enabled(was);
}

// A Lambertian measurement, in the MERL layout and as scattered samples, renders like the
// model it was made from: the interpolation schemes are exact for a constant BRDF.
TEST(Render, MeasuredLambertRendersLikeTheModel) {
  const Model lambert = ParseModel("lambert:rho_d=0.6,0.4,0.2");
  const Rgb f = lambert.Eval(Vec3(0, 0, 1), Vec3(0, 0, 1));
  testing::ScratchDir dir;
  MerlTable table;
  for (int64_t cell = 0; cell < MerlTable::kCells; ++cell) {
    for (int c = 0; c < 3; ++c) table.raw(c, cell) = f[c] / MerlTable::kScale[c];
  }
  table.Write(dir.File("lambert.binary"));
  Measurement scattered;
  scattered.format = "native-csv";
  for (double theta_i : {0.1, 0.6, 1.2}) {
    for (double theta_o : {0.2, 0.7, 1.3}) {
      Sample sample;
      sample.wi = SphericalDirection(theta_i, 0.0);
      sample.wo = SphericalDirection(theta_o, 2.0);
      sample.value = f;
      scattered.samples.push_back(sample);
    }
  }
  WriteMeasurement(scattered, dir.File("lambert.csv"));

  RenderOptions options;
  options.size = 32;
  const std::vector<DirectionalLight> lights = {
      ParseDirectionalLight("dir:theta=35:phi=120:irradiance=3")};
  const RenderResult expected =
      RenderSphere(*LoadMaterial(lambert.ToString()), lights, nullptr, options);
  for (const std::string& file : {dir.File("lambert.binary"), dir.File("lambert.csv")}) {
    const RenderResult measured = RenderSphere(*LoadMaterial(file), lights, nullptr, options);
    EXPECT_EQ(measured.missing_lookups, 0) << file;
    ASSERT_EQ(measured.radiance.rgba.size(), expected.radiance.rgba.size());
    for (size_t i = 0; i < expected.radiance.rgba.size(); ++i) {
      ASSERT_NEAR(measured.radiance.rgba[i], expected.radiance.rgba[i],
                  1e-5 * expected.radiance.rgba[i] + 1e-7)
          << file << " " << i;
    }
  }
}

TEST(Render, MeasuredGlossyDataGetALobeToSampleDiffuseDataNone) {
  // Scattered samples of blinn-phong m = 100 on a 2.5-degree grid: the table's half-vector
  // profile has the lobe's half width (cos^100 = 1/2 at 6.7 deg), read to the resolution of
  // the 2.8-degree cells, so the estimated exponent lies within a factor of two of 100.
  testing::ScratchDir dir;
  for (const char* spec : {"blinn-phong:rho_d=0.2:rho_s=0.5:m=100", "lambert:rho_d=0.5"}) {
    const Model model = ParseModel(spec);
    const std::string file = dir.File(std::string(spec).substr(0, 5) + ".csv");
    WriteMeasurement(testing::ScatteredSamplesOf(model, 2.5, 2.5), file);
    const std::optional<LobeCoordinates> lobe = LoadMaterial(file)->SpecularLobe();
    if (model.name() == "lambert") {
      EXPECT_FALSE(lobe.has_value());
    } else {
      ASSERT_TRUE(lobe.has_value());
      EXPECT_TRUE(lobe->frame.half_vector);
      EXPECT_GT(lobe->exponent, 50.0);
      EXPECT_LT(lobe->exponent, 200.0);
    }
  }
}

TEST(Environment, SampledDensityMatchesPdfAndIntegratesToOne) {
  // A map with one bright pixel and a gradient: samples must follow pdf(omega).
  Image map(32, 16);
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 32; ++x) {
      for (int c = 0; c < 3; ++c) map.pixel(x, y)[c] = 0.05f + 0.02f * x;
    }
  }
  for (int c = 0; c < 3; ++c) map.pixel(20, 5)[c] = 50.0f;
  const Environment environment(map);
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Integral of pdf over the sphere by uniform sampling of the sphere: 1.
  double integral = 0.0;
  const int n = 400000;
  for (int k = 0; k < n; ++k) {
    const double z = 1 - 2 * unit(random), phi = 2 * kPi * unit(random);
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    integral += environment.Pdf(Vec3(r * std::cos(phi), r * std::sin(phi), z)) * 4 * kPi;
  }
  EXPECT_NEAR(integral / n, 1.0, 0.02);
  // Sampled directions report the pdf that Pdf() gives them, and the radiance of the map.
  for (int k = 0; k < 2000; ++k) {
    const Environment::Sample sample = environment.SampleDirection(unit(random), unit(random));
    ASSERT_NEAR(sample.direction.norm(), 1.0, 1e-12);
    ASSERT_NEAR(sample.pdf, environment.Pdf(sample.direction), 1e-6 * sample.pdf);
    ASSERT_EQ(sample.radiance[0], environment.Radiance(sample.direction)[0]);
  }
  // Estimating the map's irradiance-like integral of L: importance sampling and uniform
  // sampling agree.
  double by_importance = 0.0, by_uniform = 0.0;
  for (int k = 0; k < n; ++k) {
    const Environment::Sample sample = environment.SampleDirection(unit(random), unit(random));
    by_importance += sample.radiance[0] / sample.pdf;
    const double z = 1 - 2 * unit(random), phi = 2 * kPi * unit(random);
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    by_uniform += environment.Radiance(Vec3(r * std::cos(phi), r * std::sin(phi), z))[0] * 4 * kPi;
  }
  EXPECT_NEAR(by_importance / n, by_uniform / n, 0.03 * by_uniform / n);
}

TEST(Environment, UniformSpecAndBadSpecs) {
  const Environment uniform = Environment::Load("uniform:0.5,1,2");
  EXPECT_EQ(uniform.Radiance(Vec3(0, 1, 0))[2], 2.0);
  EXPECT_THROW(Environment::Load("uniform:-1"), UsageError);
  EXPECT_THROW(Environment::Load("uniform:a"), UsageError);
  EXPECT_THROW(Environment::Load("no-such-file.exr"), InputError);
}

TEST(Lights, PresetsAndParsing) {
  EXPECT_NEAR(PresetLight("sun").irradiance[1], 100000.0 / kLumensPerWattAt555nm, 1e-9);
  EXPECT_NEAR(PresetLight("moonless").irradiance[0], 0.001 / kLumensPerWattAt555nm, 1e-15);
  const DirectionalLight light = ParseDirectionalLight("dir:theta=90:phi=90:irradiance=2");
  EXPECT_NEAR(light.direction.y(), 1.0, 1e-12);  // theta 90 from the viewer, phi 90 = up
  EXPECT_EQ(light.irradiance[0], 2.0);
  EXPECT_THROW(ParseDirectionalLight("point:theta=1"), UsageError);
  EXPECT_THROW(ParseDirectionalLight("dir:theta=10"), UsageError);  // no strength
  EXPECT_THROW(ParseDirectionalLight("dir:theta=10:lux=-3"), UsageError);
  EXPECT_THROW(PresetLight("disco"), UsageError);
}

}  // namespace
}  // namespace brdf
