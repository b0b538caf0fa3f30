// Speed versus accuracy of the virtual gonioreflectometer (docs/gonio.md), written as CSV:
//   gonio_study aperture     — aperture points vs error of a sharp lobe's aperture average;
//   gonio_study acquisition  — raster sphere (vs mesh segments) and ray-traced height field
//                              (vs rays) cost per sample and error against the analytic model.
// Times are medians of `kRepeats` runs of wall-clock time. Run through bench/gonio_bench.
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

double MedianSeconds(const std::function<void()>& run) {
  std::vector<double> seconds;
  for (int r = 0; r < kRepeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    run();
    seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  return seconds[kRepeats / 2];
}

// A phong lobe of width ~0.57° (n = 10^4) read through a 0.01 sr detector (3.2° radius) from a
// point-like source, at the mirror direction and 1–4° off it. Reference: a 2000×2000 midpoint
// rule in polar coordinates about each detector axis (tests/gonio_test_util.h).
void ApertureStudy() {
  Instrument instrument = testing::IdealInstrument();
  instrument.detector_solid_angle_sr = 0.01;
  instrument.source_angular_radius_deg = 0;
  const Model model = ParseModel("phong:rho_d=0:rho_s=1:n=10000");
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
  std::printf("density,detector_points,by_rule,max_relative_error,seconds_per_reading\n");
  for (double density : {0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5, 2.0, 3.0}) {
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
    std::printf("%g,%d,%d,%.6g,%.6g\n", density, points, density == 1.0 ? 1 : 0, worst, seconds);
  }
}

// Blinn-phong (m = 200) acquired two ways, errors against the analytic reference:
//  raster — a 256×256 view of the sphere at 60° light, vs mesh segments; reference = the model
//           at each sample's (wi, wo);
//  traced — a height field flat to 1e-3 rms slope whose facets carry the same blinn-phong,
//           at 30° incidence into the 17 in-plane detectors of a 10° schedule, vs rays;
//           reference = the analytic sample read through the same (ideal) instrument.
void AcquisitionStudy() {
  const Model model = ParseModel("blinn-phong:rho_d=0.3:rho_s=0.5:m=200");
  std::printf("method,parameter,samples,seconds,seconds_per_sample,rms_relative_error\n");
  for (int segments : {16, 32, 64, 128, 256, 512}) {
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
    std::printf("raster,%d,%zu,%.6g,%.6g,%.6g\n", segments, n, seconds, seconds / n,
                std::sqrt(sum / n));
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
  for (int64_t rays : {10000, 30000, 100000, 300000, 1000000, 3000000}) {
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
    std::printf("traced,%lld,%zu,%.6g,%.6g,%.6g\n", static_cast<long long>(rays), detectors.size(),
                seconds, seconds / detectors.size(), std::sqrt(sum / detectors.size()));
  }
}

}  // namespace
}  // namespace brdf::gonio

int main(int argc, char** argv) {
  const std::string study = argc > 1 ? argv[1] : "";
  if (study == "aperture") {
    brdf::gonio::ApertureStudy();
  } else if (study == "acquisition") {
    brdf::gonio::AcquisitionStudy();
  } else {
    std::fprintf(stderr, "usage: gonio_study aperture|acquisition\n");
    return 2;
  }
  return 0;
}
