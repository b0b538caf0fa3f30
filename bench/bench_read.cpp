// Reading speed of every reader: a full 34,992,012-byte MERL table (generated from an analytic
// model, since no MERL file ships with the project) and the real Cornell and Zemax files.
// Run through bench/read_bench, which also measures peak memory per file.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "io/formats.h"
#include "io/merl.h"
#include "models/model_string.h"

namespace brdf {
namespace {

// A MERL table of blinn-phong values; written once per process.
const std::string& MerlPath() {
  static const std::string path = [] {
    const char* from_env = std::getenv("BRDFKIT_BENCH_MERL");
    std::string file =
        from_env ? from_env
                 : (std::filesystem::temp_directory_path() / "brdfkit-bench.binary").string();
    if (!std::filesystem::exists(file)) {
      const Model model = ParseModel("blinn-phong:rho_d=0.3,0.2,0.1:rho_s=0.4:m=300");
      const MerlTable table =
          MerlTable::Tabulate([&](const Vec3& wi, const Vec3& wo) { return model.Eval(wi, wo); });
      table.Write(file);
    }
    return file;
  }();
  return path;
}

void BM_MerlTableRead(benchmark::State& state) {
  const std::string& path = MerlPath();
  for (auto _ : state) benchmark::DoNotOptimize(MerlTable::Read(path));
  state.SetBytesProcessed(state.iterations() * MerlTable::kFileBytes);
}
BENCHMARK(BM_MerlTableRead)->Unit(benchmark::kMillisecond)->UseRealTime();

// Table plus the 1,458,000 (wi, wo) direction pairs of a Measurement.
void BM_MerlToMeasurement(benchmark::State& state) {
  const std::string& path = MerlPath();
  for (auto _ : state) benchmark::DoNotOptimize(ReadMeasurement(path));
  state.SetBytesProcessed(state.iterations() * MerlTable::kFileBytes);
}
BENCHMARK(BM_MerlToMeasurement)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ReadFile(benchmark::State& state, const char* relative) {
  const std::string path = std::string(BRDFKIT_DATA_DIR) + "/" + relative;
  for (auto _ : state) benchmark::DoNotOptimize(ReadMeasurement(path));
  state.SetBytesProcessed(state.iterations() * std::filesystem::file_size(path));
}
BENCHMARK_CAPTURE(BM_ReadFile, astm_cayman, "cornell-astm/cayman.astm")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_ReadFile, pbrt_cayman, "cornell-pbrt-v2/cayman.brdf")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_ReadFile, zemax, "zemax-bsdf/test_13_planesymmetric_brdf_zemax.bsdf")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace brdf

BENCHMARK_MAIN();
