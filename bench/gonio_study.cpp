// Speed versus accuracy of the virtual gonioreflectometer (docs/gonio.md,
// docs/speed-accuracy.md), written as CSV:
//   gonio_study aperture     — aperture points vs error of a lobe's aperture average, for
//                              three lobe/detector configurations;
//   gonio_study acquisition  — raster sphere (vs mesh segments) and ray-traced height field
//                              (vs rays) cost per sample and error against the analytic model.
// `is_default` marks what the instrument does unless told otherwise: the lobe-width rule's
// points, Instrument's sphere segments, SurfaceSpec's rays per incidence. Times are medians of
// `kRepeats` runs of wall-clock time. `--quick` runs a few points once (a smoke test). Run
// through bench/gonio_bench.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "core/angles.h"
#include "gonio/aperture.h"
#include "gonio/measure.h"
#include "gonio/model_sample.h"
#include "gonio/rasterizer.h"
#include "gonio/sphere_acquisition.h"
#include "gonio/surface_sample.h"
#include "gonio/traced_surface.h"
#include "gonio_test_util.h"
#include "models/model_string.h"

namespace brdf::gonio {
namespace {

constexpr int kRepeats = 5;
bool quick = false;  // --quick

double MedianSeconds(const std::function<void()>& run) {
  const int repeats = quick ? 1 : kRepeats;
  std::vector<double> seconds;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    run();
    seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  return seconds[repeats / 2];
}

// A phong lobe read through a detector from a point-like source, at the mirror direction and
// 1–4° off it; `density` scales the lobe-width rule's points. Reference: a 2000×2000 midpoint
// rule in polar coordinates about each detector axis (tests/gonio_test_util.h).
void ApertureConfiguration(const char* label, const std::string& model_text,
                           double detector_solid_angle_sr) {
  Instrument instrument = testing::IdealInstrument();
  instrument.detector_solid_angle_sr = detector_solid_angle_sr;
  instrument.source_angular_radius_deg = 0;
  const Model model = ParseModel(model_text);
  const Vec3 wi = SphericalDirection(DegToRad(30), 0);
  std::vector<Vec3> detectors;
  for (double offset : {0.0, 1.0, 2.0, 3.0, 4.0}) {
    detectors.push_back(SphericalDirection(DegToRad(30 + offset), kPi));
  }
  const double cone = std::acos(instrument.DetectorCosHalfAngle());
  std::vector<double> reference;
  for (const Vec3& axis : detectors) {
    reference.push_back(testing::ApertureAverageByGrid(model, wi, axis, cone, 2000));
  }
  ModelSample sample(model, instrument);
  const int default_points = sample.detector_points();  // as constructed: the rule
  const std::vector<double> densities =
      quick ? std::vector<double>{0.5, 1.0, 2.0}
            : std::vector<double>{0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5, 2.0, 3.0};
  struct Row {
    double density;
    int points;
    double worst, seconds;
  };
  std::vector<Row> rows;
  for (double density : densities) {
    sample.SetApertureDensity(instrument, density);
    const int points = sample.detector_points();
    double worst = 0;
    for (size_t k = 0; k < detectors.size(); ++k) {
      const double reading = sample.Reading(instrument, wi, detectors[k])[0];
      worst = std::max(worst, std::abs(reading - reference[k]) / reference[k]);
    }
    const double seconds = MedianSeconds([&] {
                             for (int r = 0; r < 200; ++r)
                               sample.Reading(instrument, wi, detectors[r % 5]);
                           }) /
                           200;
    rows.push_back({density, points, worst, seconds});
  }
  // Densities that give the same points are the same quadrature: one row, the largest density.
  for (size_t k = 0; k < rows.size(); ++k) {
    if (k + 1 < rows.size() && rows[k + 1].points == rows[k].points) continue;
    std::printf("%s,%g,%d,%d,%.6g,%.6g\n", label, rows[k].density, rows[k].points,
                rows[k].points == default_points ? 1 : 0, rows[k].worst, rows[k].seconds);
  }
}

// Lobe width ~1/sqrt(n) rad against the detector's radius: 0.57° through 3.2° (the sharp case
// the rule was written for), 1.8° through 3.2°, and 5.7° through 1.0° (a broad lobe, a small
// detector: the rule's floor).
void ApertureStudy() {
  std::printf(
      "configuration,density,detector_points,is_default,max_relative_error,"
      "seconds_per_reading\n");
  ApertureConfiguration("phong n=1e4 / 0.01 sr", "phong:rho_d=0:rho_s=1:n=10000", 0.01);
  if (quick) return;
  ApertureConfiguration("phong n=1e3 / 0.01 sr", "phong:rho_d=0:rho_s=1:n=1000", 0.01);
  ApertureConfiguration("phong n=1e2 / 0.001 sr", "phong:rho_d=0:rho_s=1:n=100", 0.001);
}

// Blinn-phong (m = 200) acquired two ways, errors against the analytic reference:
//  raster — a 256×256 view of the sphere at 60° light, vs mesh segments; reference = the model
//           at each sample's (wi, wo);
//  traced — a height field flat to 1e-3 rms slope whose facets carry the same blinn-phong,
//           at 30° incidence into the 17 in-plane detectors of a 10° schedule, vs rays;
//           reference = the analytic sample read through the same (ideal) instrument.
void AcquisitionStudy() {
  const Model model = ParseModel("blinn-phong:rho_d=0.3:rho_s=0.5:m=200");
  std::printf(
      "method,parameter,samples,seconds,seconds_per_sample,rms_relative_error,is_default\n");
  const std::vector<int> segment_counts =
      quick ? std::vector<int>{32, 256} : std::vector<int>{16, 32, 64, 128, 256, 512};
  for (int segments : segment_counts) {
    Instrument instrument = testing::IdealInstrument();
    instrument.camera_resolution = 256;
    instrument.sphere_segments = segments;
    const SphereAcquisition acquisition(model, instrument);
    SphereAcquisition::View view;
    const double seconds = MedianSeconds([&] {
      const GBuffer gbuffer = Rasterize(acquisition.mesh(), acquisition.camera());
      view = acquisition.Shade(gbuffer, DegToRad(60), 1, 0);
    });
    double sum = 0;
    for (const Sample& s : view.samples) {
      const double truth = model.Eval(s.wi, s.wo)[0];
      sum += std::pow((s.value[0] - truth) / truth, 2);
    }
    const size_t n = view.samples.size();
    std::printf("raster,%d,%zu,%.6g,%.6g,%.6g,%d\n", segments, n, seconds, seconds / n,
                std::sqrt(sum / n), segments == Instrument{}.sphere_segments ? 1 : 0);
  }
  const Instrument instrument = testing::IdealInstrument();
  const Schedule schedule = MakeSchedule("inplane:step=10");
  const Incidence& incidence = schedule.incidences[3];  // 30°
  std::vector<Vec3> detectors;
  for (const Detector& d : incidence.detectors) detectors.push_back(d.wo);
  const ModelSample analytic(model, instrument);
  SurfaceSpec spec;
  spec.heightfield.kind = "gaussian";
  spec.heightfield.rms_slope = 1e-3;
  spec.heightfield.resolution = 64;
  spec.base = model.ToString();
  const auto sample = MakeSurfaceSample(spec, instrument);
  const auto& traced = dynamic_cast<const TracedSurfaceSample&>(*sample);
  const std::vector<int64_t> ray_counts =
      quick ? std::vector<int64_t>{10000, 100000}
            : std::vector<int64_t>{10000, 30000, 100000, 300000, 1000000, 3000000};
  for (int64_t rays : ray_counts) {
    std::vector<Rgb> readings;
    uint64_t index = 0;
    const double seconds = MedianSeconds([&] {
      const auto trace =
          traced.TraceIncidence(instrument, incidence.wi, detectors, 1, index++, rays);
      readings = trace.detector_power;
      for (Rgb& r : readings) r /= trace.incident * instrument.detector_solid_angle_sr;
    });
    double sum = 0;
    for (size_t k = 0; k < detectors.size(); ++k) {
      const double truth = analytic.Reading(instrument, incidence.wi, detectors[k])[0];
      sum += std::pow((readings[k][0] - truth) / truth, 2);
    }
    std::printf("traced,%lld,%zu,%.6g,%.6g,%.6g,%d\n", static_cast<long long>(rays),
                detectors.size(), seconds, seconds / detectors.size(),
                std::sqrt(sum / detectors.size()),
                rays == SurfaceSpec{}.rays_per_incidence ? 1 : 0);
  }
}

}  // namespace
}  // namespace brdf::gonio

int main(int argc, char** argv) {
  const std::string study = argc > 1 ? argv[1] : "";
  brdf::gonio::quick = argc > 2 && std::string(argv[2]) == "--quick";
  if (study == "aperture") {
    brdf::gonio::ApertureStudy();
  } else if (study == "acquisition") {
    brdf::gonio::AcquisitionStudy();
  } else {
    std::fprintf(stderr, "usage: gonio_study aperture|acquisition [--quick]\n");
    return 2;
  }
  return 0;
}
