// Speed of the virtual gonioreflectometer's three paths (docs/gonio.md): Embree tracing of a
// 512×512 height field (ray segments per second), the analytic full 5° hemisphere with
// aperture integration, and one rasterized 512×512 view of the sphere. Run through
// bench/gonio_bench, which takes medians of repeated runs.
#include <benchmark/benchmark.h>

#include <ctime>

#include "core/angles.h"
#include "gonio/measure.h"
#include "gonio/rasterizer.h"
#include "gonio/schedule.h"
#include "gonio/sphere_acquisition.h"
#include "gonio/surface_sample.h"
#include "gonio/traced_surface.h"
#include "models/model_string.h"

namespace brdf::gonio {
namespace {

// 512×512 Gaussian height field, up to 8 bounces; one incidence at 30° binned into the full
// 5° hemisphere of detectors. Arg 0: gold facets (specular), 1: white Lambertian facets.
void BM_TraceHeightField512(benchmark::State& state) {
  SurfaceSpec spec;
  spec.heightfield.kind = "gaussian";
  spec.heightfield.rms_slope = 0.5;
  spec.heightfield.resolution = 512;
  spec.bounces = 8;
  spec.base =
      state.range(0) == 0 ? "conductor:ior=0.18,0.42,1.37:k=3.42,2.35,1.77" : "lambert:rho_d=0.9";
  const Instrument instrument;
  const auto sample = MakeSurfaceSample(spec, instrument);
  const auto& traced = dynamic_cast<const TracedSurfaceSample&>(*sample);
  const Schedule schedule = MakeSchedule("hemisphere:theta_i_step=30");
  const Incidence& incidence = schedule.incidences[1];
  std::vector<Vec3> detectors;
  for (const Detector& d : incidence.detectors) detectors.push_back(d.wo);
  const int64_t rays = int64_t{1} << 20;
  int64_t segments = 0;
  uint64_t index = 0;
  const std::clock_t cpu_start = std::clock();  // process CPU time, all threads
  for (auto _ : state) {
    const auto trace = traced.TraceIncidence(instrument, incidence.wi, detectors, 1, index++, rays);
    segments += trace.segments;
  }
  state.counters["segments_per_s"] =
      benchmark::Counter(static_cast<double>(segments), benchmark::Counter::kIsRate);
  // Rate per CPU-second of all threads: what each core delivers even when the machine is shared.
  const double cpu_seconds = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  state.counters["segments_per_cpu_s"] = static_cast<double>(segments) / cpu_seconds;
  state.counters["segments_per_ray"] =
      static_cast<double>(segments) / (static_cast<double>(rays) * state.iterations());
}
BENCHMARK(BM_TraceHeightField512)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// `brdf measure --sample model:... --schedule hemisphere` without the file write: 22,016
// readings, each integrated over source and detector apertures, calibrated, with noise.
// Arg: the blinn-phong exponent (200: 7×7 aperture points; 10000: 7×24 by the lobe rule).
void BM_AnalyticHemisphere(benchmark::State& state) {
  MeasureOptions options;
  options.sample = "model:blinn-phong:rho_d=0.3:rho_s=0.5:m=" + std::to_string(state.range(0));
  const Schedule schedule = MakeSchedule("hemisphere");
  for (auto _ : state) benchmark::DoNotOptimize(Measure(options, schedule));
}
BENCHMARK(BM_AnalyticHemisphere)
    ->Arg(200)
    ->Arg(10000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// One 512×512 view: rasterize the 256-segment sphere (65,024 triangles) and shade every pixel
// (calibration against the reference sphere, noise). Arg 0: rasterize + shade; 1: rasterize.
void BM_RasterView512(benchmark::State& state) {
  Instrument instrument;
  instrument.camera_resolution = 512;
  const SphereAcquisition acquisition(ParseModel("blinn-phong:rho_d=0.3:rho_s=0.5:m=200"),
                                      instrument);
  uint64_t view = 0;
  for (auto _ : state) {
    const GBuffer gbuffer = Rasterize(acquisition.mesh(), acquisition.camera());
    if (state.range(0) == 0) {
      benchmark::DoNotOptimize(acquisition.Shade(gbuffer, DegToRad(60), 1, view++));
    } else {
      benchmark::DoNotOptimize(gbuffer);
    }
  }
}
BENCHMARK(BM_RasterView512)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace brdf::gonio

BENCHMARK_MAIN();
