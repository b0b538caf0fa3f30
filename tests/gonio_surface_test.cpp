// The micro-geometry sample: the flat analytic path (no BVH) for Lambertian and mirror facets,
// and the Embree path: a nearly flat traced mirror, energy conservation and reciprocity of a
// rough conductor within Monte Carlo error, determinism across thread counts.
#include <ImfRgbaFile.h>
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <complex>

#include "core/angles.h"
#include "core/errors.h"
#include "gonio/detector_lookup.h"
#include "gonio/measure.h"
#include "gonio/model_sample.h"
#include "gonio/rng.h"
#include "gonio/surface_sample.h"
#include "gonio/traced_surface.h"
#include "gonio_test_util.h"
#include "models/microfacet.h"
#include "test_util.h"

namespace brdf::gonio {
namespace {

using models::FresnelReflectance;
using testing::IdealInstrument;
using testing::OneIncidence;

// Unpolarized Fresnel reflectance of a dielectric of index n from air, written with real
// arithmetic (Hecht, Optics, §4.6) so that it checks the complex form used by the code.
double DielectricFresnel(double cos_i, double n) {
  const double sin_t = std::sqrt(1 - cos_i * cos_i) / n;
  const double cos_t = std::sqrt(1 - sin_t * sin_t);
  const double r_s = (cos_i - n * cos_t) / (cos_i + n * cos_t);
  const double r_p = (cos_t - n * cos_i) / (cos_t + n * cos_i);
  return 0.5 * (r_s * r_s + r_p * r_p);
}

// The tracer's real-arithmetic Fresnel equals the complex amplitudes |r_s|², |r_p|², and at
// normal incidence ((n−1)² + k²)/((n+1)² + k²).
TEST(GonioSurfaceTest, FresnelMatchesTheComplexAmplitudes) {
  for (const auto& [n, k] : std::vector<std::pair<double, double>>{
           {1.5, 0.0}, {1.33, 0.0}, {0.18, 3.42}, {1.35, 7.47}, {2.9, 3.0}}) {
    const double normal = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    EXPECT_NEAR(FresnelReflectance(1.0, n, k), normal, 1e-12);
    for (double theta_deg = 0; theta_deg < 90; theta_deg += 7.5) {
      const double cos_i = std::cos(DegToRad(theta_deg));
      const std::complex<double> eta(n, k);
      const std::complex<double> cos_t = std::sqrt(1.0 - (1 - cos_i * cos_i) / (eta * eta));
      const double r_s = std::norm((cos_i - eta * cos_t) / (cos_i + eta * cos_t));
      const double r_p = std::norm((eta * cos_i - cos_t) / (eta * cos_i + cos_t));
      EXPECT_NEAR(FresnelReflectance(cos_i, n, k), 0.5 * (r_s + r_p), 1e-12) << n << " " << k;
    }
    EXPECT_NEAR(FresnelReflectance(0.0, n, k), 1.0, 1e-12);  // grazing: total reflection
  }
}

TEST(GonioSurfaceTest, FlatLambertianReadsRhoOverPiWithoutABvh) {
  brdf::testing::ScratchDir dir;
  const std::string path =
      dir.Write("flat.json", R"({"heightfield": {"kind": "flat"}, "base": "lambert:rho_d=0.8"})");
  const Instrument instrument = IdealInstrument();
  const auto sample = MakeSurfaceSample(path, instrument);
  EXPECT_NE(dynamic_cast<const ModelSample*>(sample.get()), nullptr);  // analytic, not traced
  MeasureOptions options;
  options.sample = "surface:" + path;
  options.instrument = instrument;
  const Measurement measurement = Measure(options, MakeSchedule("inplane:step=10"));
  ASSERT_GT(measurement.samples.size(), 100u);
  for (const Sample& s : measurement.samples) {
    EXPECT_NEAR(s.value[1], 0.8 / kPi, 0.01 * 0.8 / kPi);
  }
  EXPECT_NE(measurement.metadata.at("modelled").find("no ray tracing"), std::string::npos);
}

TEST(GonioSurfaceTest, FlatMirrorPutsTheFresnelReflectanceInTheSpecularCell) {
  brdf::testing::ScratchDir dir;
  const std::string path =
      dir.Write("glass.json", R"({"heightfield": {"kind": "flat"}, "base": "dielectric:ior=1.5"})");
  const Instrument instrument = IdealInstrument();
  for (double theta_i_deg : {10.0, 45.0, 70.0}) {
    const Vec3 wi = SphericalDirection(DegToRad(theta_i_deg), 0);
    const Vec3 mirror = MirrorDirection(wi);
    const std::vector<Vec3> detectors = {
        mirror, SphericalDirection(DegToRad(theta_i_deg + 5), kPi),
        SphericalDirection(DegToRad(theta_i_deg), kPi + DegToRad(10)),
        SphericalDirection(DegToRad(theta_i_deg), 0.5 * kPi)};
    MeasureOptions options;
    options.sample = "surface:" + path;
    options.instrument = instrument;
    const Measurement m = Measure(options, OneIncidence(theta_i_deg, detectors));
    ASSERT_EQ(m.samples.size(), detectors.size());
    // Power fraction in the specular cell = f · Ω · cos(theta_o).
    const double in_cell = m.samples[0].value[0] * instrument.detector_solid_angle_sr * mirror.z();
    const double fresnel = DielectricFresnel(wi.z(), 1.5);
    EXPECT_NEAR(in_cell, fresnel, 0.01 * fresnel) << theta_i_deg;
    for (size_t k = 1; k < detectors.size(); ++k) EXPECT_EQ(m.samples[k].value[0], 0.0);
  }
}

// The same mirror traced with Embree (a height field flat to 1e-3 rms slope): one bounce per
// ray, so the specular cell holds the Fresnel reflectance to within the jitter of the facets.
TEST(GonioSurfaceTest, NearlyFlatTracedConductorMatchesFresnel) {
  SurfaceSpec spec;
  spec.heightfield.kind = "gaussian";
  spec.heightfield.rms_slope = 1e-3;
  spec.heightfield.resolution = 64;
  spec.base = "conductor:ior=0.18:k=3.42";
  spec.rays_per_incidence = 20000;
  const Instrument instrument = IdealInstrument();
  const auto sample = MakeSurfaceSample(spec, instrument);
  const auto* traced = dynamic_cast<const TracedSurfaceSample*>(sample.get());
  ASSERT_NE(traced, nullptr);
  const Vec3 wi = SphericalDirection(DegToRad(40), 0);
  const auto trace =
      traced->TraceIncidence(instrument, wi, {MirrorDirection(wi)}, 3, 0, spec.rays_per_incidence);
  const std::complex<double> eta(0.18, 3.42);
  const double cos_i = wi.z(), sin2 = 1 - cos_i * cos_i;
  const std::complex<double> cos_t = std::sqrt(1.0 - sin2 / (eta * eta));
  const double r_s = std::norm((cos_i - eta * cos_t) / (cos_i + eta * cos_t));
  const double r_p = std::norm((eta * cos_i - cos_t) / (eta * cos_i + cos_t));
  const double fresnel = 0.5 * (r_s + r_p);
  EXPECT_NEAR(trace.detector_power[0][0] / trace.incident, fresnel, 0.01 * fresnel);
  EXPECT_NEAR(trace.reflected[0] / trace.incident, fresnel, 0.01 * fresnel);
}

// A detector no path reached reads 0 with the Monte Carlo error of one escaped path (the mean
// escaping weight), not with no error at all; a detector that received every path keeps an
// error far below its power. Without the first, a fit weighted by sigma takes empty detectors
// for exact zeros (docs/gonio.md: the Beckmann validation).
TEST(GonioSurfaceTest, EmptyDetectorCarriesOnePathOfMonteCarloError) {
  SurfaceSpec spec;
  spec.heightfield.kind = "gaussian";
  spec.heightfield.rms_slope = 1e-3;
  spec.heightfield.resolution = 32;
  spec.base = "conductor:ior=0.18:k=3.42";
  const Instrument instrument = IdealInstrument();
  const auto sample = MakeSurfaceSample(spec, instrument);
  const auto* traced = dynamic_cast<const TracedSurfaceSample*>(sample.get());
  ASSERT_NE(traced, nullptr);
  const Vec3 wi = SphericalDirection(DegToRad(30), 0);
  const Vec3 far = SphericalDirection(DegToRad(60), 0);  // back-scatter: no mirror reaches it
  const auto trace =
      traced->TraceIncidence(instrument, wi, {MirrorDirection(wi), far}, 2, 0, 20000);
  ASSERT_EQ(trace.escaped, 20000);
  const double one_path = trace.reflected[0] / double(trace.escaped);
  EXPECT_EQ(trace.detector_power[1][0], 0.0);
  EXPECT_NEAR(trace.detector_power_standard_error[1][0], one_path, 1e-12 * one_path);
  EXPECT_NEAR(trace.detector_power[0][0], trace.reflected[0], 1e-9 * trace.reflected[0]);
  EXPECT_LT(trace.detector_power_standard_error[0][0], 1e-3 * trace.detector_power[0][0]);
}

TEST(GonioSurfaceTest, RoughConductorConservesEnergyAndIsReciprocal) {
  SurfaceSpec spec;
  spec.heightfield.kind = "gaussian";
  spec.heightfield.rms_slope = 0.4;
  spec.heightfield.resolution = 128;
  spec.base = "conductor:ior=0.18:k=3.42";
  const int64_t rays = 150000;
  // Equal source and detector cones make the cone-averaged readings reciprocal:
  // R(A→B) cos(theta_A) = R(B→A) cos(theta_B).
  Instrument instrument = IdealInstrument();
  instrument.detector_solid_angle_sr = 0.03;
  instrument.source_angular_radius_deg = RadToDeg(std::acos(instrument.DetectorCosHalfAngle()));
  const auto sample = MakeSurfaceSample(spec, instrument);
  const auto* traced = dynamic_cast<const TracedSurfaceSample*>(sample.get());
  ASSERT_NE(traced, nullptr);
  const std::vector<std::pair<Vec3, Vec3>> pairs = {
      {SphericalDirection(DegToRad(20), 0), SphericalDirection(DegToRad(50), DegToRad(180))},
      {SphericalDirection(DegToRad(35), 0), SphericalDirection(DegToRad(60), DegToRad(135))}};
  uint64_t index = 0;
  for (const auto& [a, b] : pairs) {
    const auto forward = traced->TraceIncidence(instrument, a, {b}, 5, index++, rays);
    const auto backward = traced->TraceIncidence(instrument, b, {a}, 5, index++, rays);
    for (const auto* trace : {&forward, &backward}) {
      EXPECT_LE(trace->reflected.maxCoeff(), trace->incident);        // reflected <= incident
      EXPECT_GT(trace->reflected.minCoeff(), 0.5 * trace->incident);  // a metal reflects most
    }
    const double f_ab = forward.detector_power[0][0] / forward.incident / b.z();
    const double f_ba = backward.detector_power[0][0] / backward.incident / a.z();
    // Monte Carlo error: about 1/sqrt(hits) relatively, hits ≈ power / mean path weight (≤ 1).
    const double hits_ab = forward.detector_power[0][0], hits_ba = backward.detector_power[0][0];
    ASSERT_GT(hits_ab, 300);
    ASSERT_GT(hits_ba, 300);
    const double sigma = std::hypot(f_ab / std::sqrt(hits_ab), f_ba / std::sqrt(hits_ba));
    EXPECT_NEAR(f_ab, f_ba, 4 * sigma);
  }
}

// A traced run's sigma includes its Monte Carlo standard error (from the spread of ray
// batches): two runs with different seeds differ by amounts of unit variance in those units.
TEST(GonioSurfaceTest, TracedSigmaCoversTheMonteCarloError) {
  brdf::testing::ScratchDir dir;
  const std::string path =
      dir.Write("rough.json",
                R"({"heightfield": {"kind": "gaussian", "rms_slope": 0.3, "resolution": 64},
          "base": "lambert:rho_d=0.8", "rays_per_incidence": 100000})");
  MeasureOptions options;
  options.sample = "surface:" + path;
  options.instrument = IdealInstrument();
  options.instrument.detector_solid_angle_sr = 0.03;
  const Schedule schedule =
      MakeSchedule("hemisphere:theta_i_step=30:theta_o_step=10:phi_o_step=30");
  options.seed = 1;
  const Measurement first = Measure(options, schedule);
  options.seed = 2;
  const Measurement second = Measure(options, schedule);
  ASSERT_EQ(first.samples.size(), second.samples.size());
  ASSERT_GT(first.samples.size(), 250u);
  double sum_squares = 0;
  for (size_t k = 0; k < first.samples.size(); ++k) {
    const double difference = first.samples[k].value[0] - second.samples[k].value[0];
    const double sigma = std::hypot(first.sigma[k][0], second.sigma[k][0]);
    ASSERT_GT(sigma, 0);  // the ideal detector adds no noise: this is Monte Carlo error alone
    sum_squares += difference * difference / (sigma * sigma);
  }
  const double variance = sum_squares / first.samples.size();
  EXPECT_GT(variance, 0.7);
  EXPECT_LT(variance, 1.35);
}

TEST(GonioSurfaceTest, TracedRunIsIdenticalWithOneAndTwoThreads) {
  brdf::testing::ScratchDir dir;
  const std::string surface = dir.Write(
      "rough.json",
      R"({"heightfield": {"kind": "v-grooves", "rms_slope": 0.5, "resolution": 32, "period": 8},
          "base": "lambert:rho_d=0.7", "rays_per_incidence": 20000})");
  const std::string common =
      "measure --quiet --seed 4 --sample surface:" + surface + " --schedule inplane:step=30 --out ";
  ASSERT_EQ(brdf::testing::RunBrdf(common + dir.File("one.csv") + " --threads 1").exit_status, 0);
  ASSERT_EQ(brdf::testing::RunBrdf(common + dir.File("two.csv") + " --threads 2").exit_status, 0);
  const std::string one = brdf::testing::ReadFileText(dir.File("one.csv"));
  EXPECT_NE(one.find("ray traced with Embree"), std::string::npos);
  EXPECT_EQ(one, brdf::testing::ReadFileText(dir.File("two.csv")));
  const std::string bad = dir.Write("bad.json", R"({"heightfield": {"kind": "fractal"}})");
  const brdf::testing::CommandResult result =
      brdf::testing::RunBrdf("measure --sample surface:" + bad + " --out " + dir.File("x.csv"));
  EXPECT_EQ(result.exit_status, 2);
  EXPECT_NE(result.err.find("heightfield.kind"), std::string::npos) << result.err;
}

// The cell look-up that bins escaping paths finds exactly the cones a test against every
// detector finds: on the 5° hemisphere (with detectors around the pole, across phi = 0 and at
// the horizon), for random directions, for directions on whole degrees, and for directions on
// the cells' own boundaries (x or y a multiple of 1/128) and at the disk's rim.
TEST(GonioSurfaceTest, DetectorLookupFindsEveryConeContainingTheDirection) {
  const Schedule hemisphere = MakeSchedule("hemisphere");  // outlives the loop over its detectors
  std::vector<Vec3> detectors;
  for (const Detector& d : hemisphere.incidences[6].detectors) detectors.push_back(d.wo);
  detectors.push_back(SphericalDirection(DegToRad(0.3), DegToRad(200)));
  detectors.push_back(SphericalDirection(DegToRad(88.9), DegToRad(359.7)));
  detectors.push_back(SphericalDirection(DegToRad(90), DegToRad(45)));  // on the horizon
  for (const double solid_angle : {1e-5, 0.001, 0.01, 0.05, 1.0}) {
    const double cos_half_angle = ConeCosHalfAngle(solid_angle);
    const DetectorLookup lookup(detectors, cos_half_angle);
    std::vector<Vec3> directions;
    Rng rng(0, 11);
    for (int k = 0; k < 30000; ++k)
      directions.push_back(SampleCosineHemisphere(Point2(rng.Uniform(), rng.Uniform())));
    for (int theta = 0; theta < 90; ++theta) {
      for (int phi = 0; phi < 360; phi += 3)
        directions.push_back(SphericalDirection(DegToRad(theta), DegToRad(phi)));
    }
    // On the grid's cell bounds (x or y a multiple of 1/128, and a bit either side), and near
    // the rim of the disk (grazing directions).
    for (int i = -128; i <= 128; i += 2) {
      for (int j = -128; j <= 128; j += 8) {
        for (const double nudge : {0.0, 1e-15, -1e-15}) {
          const double x = i / 128.0 + nudge, y = j / 128.0 * std::sqrt(1 - x * x) * 0.999;
          const double z2 = 1 - x * x - y * y;
          if (z2 > 0) directions.push_back(Vec3(x, y, std::sqrt(z2)).normalized());
          if (z2 > 0) directions.push_back(Vec3(y, x, std::sqrt(z2)).normalized());
        }
      }
    }
    for (int phi = 0; phi < 3600; ++phi) {
      directions.push_back(SphericalDirection(DegToRad(89.99), DegToRad(0.1 * phi)));
    }
    int64_t found_total = 0;
    for (const Vec3& w : directions) {
      std::vector<int> found, expected;
      lookup.ForEachContaining(w, [&](int k) { found.push_back(k); });
      for (size_t k = 0; k < detectors.size(); ++k) {
        if (w.dot(detectors[k]) >= cos_half_angle) expected.push_back(int(k));
      }
      std::sort(found.begin(), found.end());
      ASSERT_EQ(found, expected) << solid_angle << " at " << w.transpose();
      found_total += int64_t(found.size());
    }
    EXPECT_GT(found_total, 500);  // the test did look at cones, even the smallest
  }
}

// More rays than one sorted sweep of the tracer holds: the same trace, to the bit, on one
// thread and on two (which paths share an Embree stream does not depend on the threads).
TEST(GonioSurfaceTest, TraceOfManySweepsIsIdenticalWithOneAndTwoThreads) {
  SurfaceSpec spec;
  spec.heightfield.kind = "gaussian";
  spec.heightfield.rms_slope = 0.5;
  spec.heightfield.resolution = 32;
  spec.base = "lambert:rho_d=0.9";
  const Instrument instrument = IdealInstrument();
  const auto sample = MakeSurfaceSample(spec, instrument);
  const auto* traced = dynamic_cast<const TracedSurfaceSample*>(sample.get());
  ASSERT_NE(traced, nullptr);
  const Vec3 wi = SphericalDirection(DegToRad(50), 0);
  const std::vector<Vec3> detectors = {MirrorDirection(wi), Vec3(0, 0, 1)};
  const int64_t rays = 300000;  // 74 batches of 4096
  const auto trace = [&](int threads) {
    tbb::task_arena arena(threads);
    return arena.execute(
        [&] { return traced->TraceIncidence(instrument, wi, detectors, 9, 3, rays); });
  };
  const TracedSurfaceSample::Trace one = trace(1), two = trace(2);
  EXPECT_GT(one.segments, rays);
  EXPECT_EQ(one.segments, two.segments);
  EXPECT_EQ(one.escaped, two.escaped);
  EXPECT_EQ(one.paths_cut, two.paths_cut);
  EXPECT_EQ(one.incident, two.incident);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(one.reflected[c], two.reflected[c]);
  for (size_t k = 0; k < detectors.size(); ++k) {
    EXPECT_GT(one.detector_power[k][0], 0);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(one.detector_power[k][c], two.detector_power[k][c]);
      EXPECT_EQ(one.detector_power_standard_error[k][c], two.detector_power_standard_error[k][c]);
    }
  }
}

// A height map from an EXR file: v-grooves written by the test and read back as kind "file"
// give the same facets (and so the same slope) as the procedural grooves.
TEST(GonioSurfaceTest, ExrHeightMapIsReadAsWritten) {
  brdf::testing::ScratchDir dir;
  HeightFieldSpec grooves;
  grooves.kind = "v-grooves";
  grooves.rms_slope = 0.5;
  grooves.resolution = 32;
  grooves.period = 8;
  const HeightField expected = MakeHeightField(grooves);
  const int n = expected.resolution;
  std::vector<Imf::Rgba> pixels(size_t(n) * n);
  for (size_t k = 0; k < pixels.size(); ++k) pixels[k] = Imf::Rgba(expected.heights[k], 0, 0, 1);
  const std::string exr = dir.File("grooves.exr");
  {
    Imf::RgbaOutputFile file(exr.c_str(), n, n, Imf::WRITE_RGBA);
    file.setFrameBuffer(pixels.data(), 1, n);
    file.writePixels(n);
  }
  const std::string json =
      dir.Write("file.json",
                R"({"heightfield": {"kind": "file", "path": "grooves.exr"}, "base": "lambert"})");
  const SurfaceSpec spec = ReadSurfaceSpec(json);  // the path is relative to the JSON file
  const HeightField read = MakeHeightField(spec.heightfield);
  ASSERT_EQ(read.resolution, n);
  for (size_t k = 0; k < read.heights.size(); ++k) {
    EXPECT_NEAR(read.heights[k], expected.heights[k], 1e-3);  // EXR half precision
  }
  EXPECT_NEAR(read.RmsSlope(), 0.5, 0.005);
  const std::string missing =
      dir.Write("missing.json", R"({"heightfield": {"kind": "file", "path": "nope.exr"}})");
  EXPECT_THROW(MakeHeightField(ReadSurfaceSpec(missing).heightfield), InputError);
}

}  // namespace
}  // namespace brdf::gonio
