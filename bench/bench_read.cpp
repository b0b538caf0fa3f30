// Reading speed of every reader: a full 34,992,012-byte MERL table (generated from an analytic
// model, since no MERL file ships with the project) and the real Cornell, Zemax, RGL-EPFL and
// ALTA files; and evaluations per second of the dense-table evaluators (the RGL inverse warp,
// with the MERL cell lookup as its peer) on 2 threads. Run through bench/read_bench, which also
// measures peak memory per file.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/angles.h"
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
#define BRDFKIT_READ_RGL(name)                                              \
  BENCHMARK_CAPTURE(BM_ReadFile, rgl_##name, "rgl-bsdf/" #name "_rgb.bsdf") \
      ->Unit(benchmark::kMillisecond)                                       \
      ->UseRealTime();
BRDFKIT_READ_RGL(cc_ibiza_sunset)
BRDFKIT_READ_RGL(cc_iris_purple_gem)
BRDFKIT_READ_RGL(cg_sunflower)
BRDFKIT_READ_RGL(colodur_napoli_4f)
BRDFKIT_READ_RGL(paper_white)
BRDFKIT_READ_RGL(satin_rosaline)
BRDFKIT_READ_RGL(vch_golden_yellow)
#undef BRDFKIT_READ_RGL
BENCHMARK_CAPTURE(BM_ReadFile, alta_3m_jaune, "alta-retro/retro-3M-jaune.dat")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_ReadFile, alta_gray_tape, "alta-retro/retro-gray-tape.dat")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Random direction pairs in the upper hemisphere, the same for every evaluator.
const std::vector<std::pair<Vec3, Vec3>>& DirectionPairs() {
  static const std::vector<std::pair<Vec3, Vec3>> pairs = [] {
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::vector<std::pair<Vec3, Vec3>> list(1 << 16);
    for (auto& pair : list) {
      pair.first = SphericalDirection(std::acos(uniform(random)), 2 * kPi * uniform(random));
      pair.second = SphericalDirection(std::acos(uniform(random)), 2 * kPi * uniform(random));
    }
    return list;
  }();
  return pairs;
}

void BM_Evaluate(benchmark::State& state, const Measurement* measurement) {
  const auto& pairs = DirectionPairs();
  size_t k = static_cast<size_t>(state.thread_index()) * 7919;
  for (auto _ : state) {
    const auto& pair = pairs[k++ & (pairs.size() - 1)];
    benchmark::DoNotOptimize(measurement->tabulated->Eval(pair.first, pair.second));
  }
  state.SetItemsProcessed(state.iterations());
}
const Measurement& Loaded(const std::string& path) {
  static std::map<std::string, Measurement> loaded;
  auto it = loaded.find(path);
  if (it == loaded.end()) it = loaded.emplace(path, ReadMeasurement(path)).first;
  return it->second;
}
const std::string kData = BRDFKIT_DATA_DIR;
BENCHMARK_CAPTURE(BM_Evaluate, rgl_paper_white, &Loaded(kData + "/rgl-bsdf/paper_white_rgb.bsdf"))
    ->Threads(2)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Evaluate, rgl_cg_sunflower, &Loaded(kData + "/rgl-bsdf/cg_sunflower_rgb.bsdf"))
    ->Threads(2)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Evaluate, merl_lookup, &Loaded(MerlPath()))->Threads(2)->UseRealTime();

}  // namespace
}  // namespace brdf

BENCHMARK_MAIN();
