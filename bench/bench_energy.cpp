// Speed and accuracy of the albedo methods on full curves (90 incidence angles, 0..89 degrees,
// in parallel as `brdf energy` runs them). Two families of benchmarks:
//   BM_Target/<model>     the default quadrature, for the target "|error| <= 1e-4 over the
//                         whole curve for exponents 1..1e4 in <= 50 ms on 2 cores";
//   BM_Sweep/<model>/<method>/<budget>
//                         error against time for every method over a range of budgets
//                         (tolerance, samples, grid cells), and the uniform grid for contrast.
// Each reports `max_error`: the largest |albedo - reference| over angles and channels, the
// reference being the lobe quadrature at tolerance 1e-10 (itself checked against the closed
// forms and against importance sampling in tests/energy_test.cpp), and `is_default`: 1 when
// the options are AlbedoOptions' defaults (what `brdf energy` and `brdf fit` run).
// Run through bench/energy_bench, which writes docs/bench/energy_*.csv and the chart.
#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/format.h"
#include "energy/albedo.h"
#include "energy/lobe_quadrature.h"
#include "energy/model_terms.h"
#include "models/model_string.h"

namespace brdf {
namespace {

// The models of the chart: one per lobe frame, exponents from a broad lobe to a sharp one.
const std::vector<std::string>& TargetModels() {
  static const std::vector<std::string> models = [] {
    std::vector<std::string> list;
    for (const char* exponent : {"1", "10", "100", "1000", "10000"}) {
      list.push_back(std::string("phong:rho_d=0.2:rho_s=0.8:n=") + exponent);
      list.push_back(std::string("blinn-phong-exact:rho_d=0.2:rho_s=0.8:m=") + exponent);
    }
    return list;
  }();
  return models;
}

std::vector<Rgb> CurveValues(const AlbedoCurve& curve) {
  std::vector<Rgb> values;
  for (const AlbedoPoint& point : curve.points) values.push_back(point.estimate.albedo);
  return values;
}

const std::vector<Rgb>& Reference(const std::string& model) {
  static std::map<std::string, std::vector<Rgb>> cache;
  auto found = cache.find(model);
  if (found != cache.end()) return found->second;
  AlbedoOptions options;
  options.quadrature.tolerance = 1e-10;
  options.quadrature.max_intervals = 2000;
  return cache[model] = CurveValues(ModelAlbedoCurve(ParseModel(model), options));
}

double MaxError(const std::vector<Rgb>& values, const std::vector<Rgb>& reference) {
  double error = 0;
  for (size_t k = 0; k < values.size(); ++k) {
    error = std::max(error, (values[k] - reference[k]).abs().maxCoeff());
  }
  return error;
}

// The uniform theta/phi midpoint grid over the same 90 angles, in parallel like the others.
std::vector<Rgb> GridCurve(const Model& model, int theta_cells) {
  const std::vector<double> thetas = AlbedoOptions{}.ThetaDegrees();
  const BrdfFunction brdf = ModelBrdf(model);
  std::vector<Rgb> values(thetas.size());
  tbb::parallel_for(size_t{0}, thetas.size(), [&](size_t k) {
    values[k] = IntegrateOnUniformGrid(brdf, SphericalDirection(DegToRad(thetas[k]), 0.0),
                                       theta_cells, 4 * theta_cells)
                    .albedo;
  });
  return values;
}

bool IsDefault(const AlbedoOptions& options) {
  const AlbedoOptions defaults;
  if (options.method != defaults.method || options.theta_steps != defaults.theta_steps ||
      options.theta_max_deg != defaults.theta_max_deg) {
    return false;
  }
  if (options.method == AlbedoMethod::kQuadrature) {
    return options.quadrature.tolerance == defaults.quadrature.tolerance &&
           options.quadrature.max_intervals == defaults.quadrature.max_intervals;
  }
  return options.samples == defaults.samples;
}

void RunCurve(benchmark::State& state, const std::string& model_text,
              const AlbedoOptions& options) {
  const Model model = ParseModel(model_text);
  const std::vector<Rgb>& reference = Reference(model_text);
  AlbedoCurve curve;
  for (auto _ : state) {
    curve = ModelAlbedoCurve(model, options);
    benchmark::DoNotOptimize(curve.max_albedo);
  }
  state.counters["max_error"] = MaxError(CurveValues(curve), reference);
  state.counters["evaluations"] = static_cast<double>(curve.evaluations);
  state.counters["is_default"] = IsDefault(options) ? 1 : 0;
}

void RunGrid(benchmark::State& state, const std::string& model_text, int theta_cells) {
  const Model model = ParseModel(model_text);
  const std::vector<Rgb>& reference = Reference(model_text);
  std::vector<Rgb> values;
  for (auto _ : state) {
    values = GridCurve(model, theta_cells);
    benchmark::DoNotOptimize(values.data());
  }
  state.counters["max_error"] = MaxError(values, reference);
  state.counters["evaluations"] = 90.0 * theta_cells * 4 * theta_cells;
  state.counters["is_default"] = 0;
}

void RegisterAll() {
  for (const std::string& model : TargetModels()) {
    benchmark::RegisterBenchmark(
        ("BM_Target/" + model).c_str(),
        [model](benchmark::State& state) { RunCurve(state, model, AlbedoOptions{}); })
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime()
        ->UseRealTime();
    // The interval cap stays the default one, so the sweep passes through the default.
    for (double tolerance : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-8}) {
      AlbedoOptions options;
      options.quadrature.tolerance = tolerance;
      const std::string budget = Format("%g", tolerance);
      benchmark::RegisterBenchmark(
          ("BM_Sweep/" + model + "/quadrature/" + budget).c_str(),
          [model, options](benchmark::State& state) { RunCurve(state, model, options); })
          ->Unit(benchmark::kMillisecond)
          ->MeasureProcessCPUTime()
          ->UseRealTime();
    }
    for (AlbedoMethod method : {AlbedoMethod::kMonteCarlo, AlbedoMethod::kImportance}) {
      for (int64_t samples : {256, 2048, 16384, 131072}) {
        AlbedoOptions options;
        options.method = method;
        options.samples = samples;
        benchmark::RegisterBenchmark(
            ("BM_Sweep/" + model + "/" + AlbedoMethodName(method) + "/" + std::to_string(samples))
                .c_str(),
            [model, options](benchmark::State& state) { RunCurve(state, model, options); })
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime()
            ->UseRealTime();
      }
    }
    for (int theta_cells : {16, 45, 90, 180}) {
      benchmark::RegisterBenchmark(
          ("BM_Sweep/" + model + "/grid/" + std::to_string(theta_cells)).c_str(),
          [model, theta_cells](benchmark::State& state) { RunGrid(state, model, theta_cells); })
          ->Unit(benchmark::kMillisecond)
          ->MeasureProcessCPUTime()
          ->UseRealTime();
    }
  }
}

}  // namespace
}  // namespace brdf

int main(int argc, char** argv) {
  brdf::RegisterAll();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
