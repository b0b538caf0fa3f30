// The HDR pipeline and the preview renderer (docs/hdr.md): each pipeline stage on a 1080p
// image, OpenCV's Reinhard and GaussianBlur bloom in the same run, the four blurs at equal
// sigma (time, and the error of their impulse response against an exact Gaussian as a
// counter), OpenEXR writing against OpenCV's, and the env-lit preview with noise vs spp.
// Run through bench/hdr_bench.
#include <benchmark/benchmark.h>
#include <malloc.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_reduce.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/simd.h"
#include "hdr/bloom.h"
#include "hdr/blur.h"
#include "hdr/exposure.h"
#include "hdr/image_files.h"
#include "hdr/pipeline.h"
#include "hdr/tone_map.h"
#include "render/sphere.h"

namespace brdf {
namespace {

// The bloom the 1080p pipeline target is measured with: `brdf tonemap` blooms only when asked
// (--bloom), at ToneOptions' default sigma (13 px, the target); the docs and this
// benchmark ask for the dual filter, which rounds the sigma to a whole level.
constexpr BlurKind kPipelineBloom = BlurKind::kDual;
const double kBloomSigma = ToneOptions{}.bloom_sigma;

std::string DataFile(const std::string& relative) {
  return std::string(BRDFKIT_DATA_DIR) + "/" + relative;
}

// Debevec's Memorial Church stretched to 1920x1080 (bilinear): real HDR content at 1080p.
const Image& Frame1080() {
  static const Image frame = [] {
    const Image memorial = ReadHdrImage(DataFile("hdr/memorial.hdr"));
    cv::Mat source(memorial.height, memorial.width, CV_32FC4,
                   const_cast<float*>(memorial.rgba.data()));
    cv::Mat resized;
    cv::resize(source, resized, cv::Size(1920, 1080), 0, 0, cv::INTER_LINEAR);
    Image image(1920, 1080);
    std::memcpy(image.rgba.data(), resized.ptr<float>(), image.rgba.size() * sizeof(float));
    return image;
  }();
  return frame;
}

// The same frame as OpenCV wants it: BGR float.
const cv::Mat& Frame1080Bgr() {
  static const cv::Mat bgr = [] {
    const Image& image = Frame1080();
    cv::Mat rgba(image.height, image.width, CV_32FC4, const_cast<float*>(image.rgba.data()));
    cv::Mat out;
    cv::cvtColor(rgba, out, cv::COLOR_RGBA2BGR);
    return out;
  }();
  return bgr;
}

// --- The pipeline, stage by stage, then whole -------------------------------------------

void BM_Stage_Exposure(benchmark::State& state) {
  Image image = Frame1080();
  for (auto _ : state) {
    ApplyExposure(&image, 1.0);
    benchmark::DoNotOptimize(image.rgba.data());
  }
}
BENCHMARK(BM_Stage_Exposure)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void BM_Stage_SceneLuminance(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(MeasureSceneLuminance(Frame1080()));
}
BENCHMARK(BM_Stage_SceneLuminance)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_Stage_BrightPass(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(BrightPass(Frame1080(), 1.0));
}
BENCHMARK(BM_Stage_BrightPass)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_Stage_BloomBlurDual(benchmark::State& state) {
  const Image bright = BrightPass(Frame1080(), 1.0);
  for (auto _ : state) benchmark::DoNotOptimize(Blur(bright, kPipelineBloom, kBloomSigma));
  state.counters["sigma_px"] = DesignedSigma(kPipelineBloom, kBloomSigma);
}
BENCHMARK(BM_Stage_BloomBlurDual)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_Stage_AddBloom(benchmark::State& state) {
  Image image = Frame1080();
  const Image bloom = Frame1080();
  for (auto _ : state) {
    AddBloom(&image, bloom, 0.0);
    benchmark::DoNotOptimize(image.rgba.data());
  }
}
BENCHMARK(BM_Stage_AddBloom)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void BM_Stage_ToneMapReinhardExtended(benchmark::State& state) {
  const SceneLuminance scene = MeasureSceneLuminance(Frame1080());
  const ToneMapping mapping = PlanToneMapping(ToneOperator::kReinhardExtended, scene, 0.18, 0.0);
  Image image = Frame1080();
  for (auto _ : state) {
    ApplyToneMapping(&image, mapping);  // same work on every pass (no branch on the value)
    benchmark::DoNotOptimize(image.rgba.data());
  }
}
BENCHMARK(BM_Stage_ToneMapReinhardExtended)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_Stage_SrgbEncode8(benchmark::State& state) {
  Image image = Frame1080();
  ApplyToneMapping(&image, PlanToneMapping(ToneOperator::kReinhardExtended,
                                           MeasureSceneLuminance(image), 0.18, 0.0));
  for (auto _ : state) benchmark::DoNotOptimize(EncodeDisplay(image, TransferCurve{}));
}
BENCHMARK(BM_Stage_SrgbEncode8)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// The whole pipeline on the 1080p frame; `avx2` false runs the scalar (SSE2) paths of
// core/simd.h, the same bytes, for a same-run comparison.
void RunPipeline(benchmark::State& state, const ToneOptions& options, bool avx2) {
  // The frame is read and resized before the timed loop, not in its first iteration.
  const Image& frame = Frame1080();
  const bool was = SetAvx2Enabled(avx2);
  // The pipeline reads its input and writes only the 8-bit result (and the bloom's small
  // levels): no copy of the frame is needed.
  for (auto _ : state) benchmark::DoNotOptimize(RunTonePipeline(frame, options));
  SetAvx2Enabled(was);
}

ToneOptions PipelineBloomOptions() {
  ToneOptions options;
  options.bloom = kPipelineBloom;
  options.bloom_sigma = kBloomSigma;
  return options;
}

void BM_Pipeline_Total(benchmark::State& state) {
  RunPipeline(state, PipelineBloomOptions(), true);
}
BENCHMARK(BM_Pipeline_Total)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void BM_Pipeline_Total_Scalar(benchmark::State& state) {
  RunPipeline(state, PipelineBloomOptions(), false);
}
BENCHMARK(BM_Pipeline_Total_Scalar)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// The same without bloom: what `brdf tonemap` does unless asked for --bloom.
void BM_Pipeline_NoBloom(benchmark::State& state) { RunPipeline(state, ToneOptions(), true); }
BENCHMARK(BM_Pipeline_NoBloom)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_Pipeline_NoBloom_Scalar(benchmark::State& state) {
  RunPipeline(state, ToneOptions(), false);
}
BENCHMARK(BM_Pipeline_NoBloom_Scalar)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// One read of the 1080p float frame on all threads (a sum no compiler can drop): what one
// memory pass of the pipeline costs at least, in the same run.
void BM_FramePass(benchmark::State& state) {
  const Image& frame = Frame1080();
  const int64_t floats = static_cast<int64_t>(frame.rgba.size());
  for (auto _ : state) {
    const float sum = tbb::parallel_reduce(
        tbb::blocked_range<int64_t>(0, floats, 1 << 16), 0.0f,
        [&](const tbb::blocked_range<int64_t>& range, float partial) {
          float lanes[8] = {0, 0, 0, 0, 0, 0, 0, 0};
          for (int64_t i = range.begin(); i + 8 <= range.end(); i += 8) {
            for (int k = 0; k < 8; ++k) lanes[k] += frame.rgba[i + k];
          }
          for (float lane : lanes) partial += lane;
          return partial;
        },
        [](float a, float b) { return a + b; });
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK(BM_FramePass)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void BM_OpenCV_TonemapReinhard(benchmark::State& state) {
  const cv::Ptr<cv::TonemapReinhard> tonemap = cv::createTonemapReinhard();
  const cv::Mat& frame = Frame1080Bgr();  // made before the timed loop
  cv::Mat out;
  for (auto _ : state) {
    tonemap->process(frame, out);
    benchmark::DoNotOptimize(out.data);
  }
}
BENCHMARK(BM_OpenCV_TonemapReinhard)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// The bloom stage written with OpenCV: bright pass (luminance threshold), GaussianBlur at the
// sigma the dual filter really has, weighted add.
void BM_OpenCV_GaussianBloom(benchmark::State& state) {
  const double sigma = DesignedSigma(kPipelineBloom, kBloomSigma);
  cv::Mat luminance, mask, bright, blurred, out;
  for (auto _ : state) {
    cv::cvtColor(Frame1080Bgr(), luminance, cv::COLOR_BGR2GRAY);
    cv::threshold(luminance, mask, 1.0, 1.0, cv::THRESH_BINARY);
    cv::cvtColor(mask, mask, cv::COLOR_GRAY2BGR);
    cv::multiply(Frame1080Bgr(), mask, bright);
    cv::GaussianBlur(bright, blurred, cv::Size(0, 0), sigma);
    cv::addWeighted(Frame1080Bgr(), 1.0, blurred, 0.1, 0.0, out);
    benchmark::DoNotOptimize(out.data);
  }
  state.counters["sigma_px"] = sigma;
}
BENCHMARK(BM_OpenCV_GaussianBloom)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// --- Blurs at equal sigma ----------------------------------------------------------------

// Relative L2 error of a blur's impulse response, asked for `sigma`, against the exact
// (continuous, sampled) Gaussian of standard deviation `reference_sigma`: the sigma the blur is
// designed for (the shape alone) or the one asked for (shape and the dual filter's rounding).
double ImpulseError(BlurKind kind, double sigma, double reference_sigma) {
  const double designed = DesignedSigma(kind, sigma);
  const int size = 2 * static_cast<int>(std::ceil(6 * std::max(designed, reference_sigma))) + 65;
  Image impulse(size, size, 0.0f);
  const int centre = size / 2;
  impulse.pixel(centre, centre)[0] = 1.0f;
  const Image response = Blur(impulse, kind, sigma);
  double error = 0.0, norm = 0.0;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double r2 = double(x - centre) * (x - centre) + double(y - centre) * (y - centre);
      const double exact = std::exp(-0.5 * r2 / (reference_sigma * reference_sigma)) /
                           (2 * kPi * reference_sigma * reference_sigma);
      error += (response.pixel(x, y)[0] - exact) * (response.pixel(x, y)[0] - exact);
      norm += exact * exact;
    }
  }
  return std::sqrt(error / norm);
}

void BM_Blur(benchmark::State& state) {
  const BlurKind kind = static_cast<BlurKind>(state.range(0));
  const double sigma = static_cast<double>(state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(Blur(Frame1080(), kind, sigma));
  state.SetLabel(BlurKindName(kind));
  state.counters["sigma_px"] = DesignedSigma(kind, sigma);
  state.counters["rel_l2_error"] = ImpulseError(kind, sigma, DesignedSigma(kind, sigma));
  state.counters["rel_l2_error_vs_requested"] = ImpulseError(kind, sigma, sigma);
  state.counters["is_default"] = kind == kPipelineBloom && sigma == kBloomSigma ? 1 : 0;
}
// Sigmas 2–16 px and the default bloom sigma.
BENCHMARK(BM_Blur)
    ->ArgsProduct({{static_cast<int>(BlurKind::kBox), static_cast<int>(BlurKind::kGaussian),
                    static_cast<int>(BlurKind::kKawase), static_cast<int>(BlurKind::kDual)},
                   {2, 4, 8, std::lround(ToneOptions{}.bloom_sigma), 16}})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// --- PNG ---------------------------------------------------------------------------------

// The 1080p frame tone mapped as `brdf tonemap` does it by default.
const Image8& Display1080() {
  static const Image8 display = RunTonePipeline(Frame1080(), ToneOptions()).display;
  return display;
}

// The whole PNG encoder (Sub filter, zlib's Huffman-only deflate, checksums) on one thread.
void BM_Png_OneThread(benchmark::State& state) {
  const Image8& display = Display1080();
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  size_t bytes = 0;
  for (auto _ : state) bytes = EncodePng(display, "bench.png").size();
  state.counters["bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_Png_OneThread)->Unit(benchmark::kMillisecond)->UseRealTime();

// --- OpenEXR ------------------------------------------------------------------------------

std::string TemporaryPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / name).string();
}

void BM_WriteExrHalf(benchmark::State& state) {
  const std::string path = TemporaryPath("brdfkit-bench-half.exr");
  const ExrCompression compression = static_cast<ExrCompression>(state.range(0));
  const char* names[] = {"zip", "piz", "rle", "none"};
  state.SetLabel(names[state.range(0)]);
  for (auto _ : state) WriteExr(path, Frame1080(), ExrPixelType::kHalf, compression);
  state.counters["bytes"] = static_cast<double>(std::filesystem::file_size(path));
  std::filesystem::remove(path);
}
BENCHMARK(BM_WriteExrHalf)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// OpenCV's writer with its default compression (zip) and with piz, for a like-for-like pair.
void BM_OpenCV_ImwriteExrHalf(benchmark::State& state) {
  const std::string path = TemporaryPath("brdfkit-bench-opencv.exr");
  const int compression = static_cast<int>(state.range(0));
  state.SetLabel(compression == cv::IMWRITE_EXR_COMPRESSION_ZIP ? "zip" : "piz");
  const std::vector<int> flags = {cv::IMWRITE_EXR_TYPE, cv::IMWRITE_EXR_TYPE_HALF,
                                  cv::IMWRITE_EXR_COMPRESSION, compression};
  for (auto _ : state) {
    if (!cv::imwrite(path, Frame1080Bgr(), flags)) state.SkipWithError("imwrite failed");
  }
  if (std::filesystem::exists(path)) {
    state.counters["bytes"] = static_cast<double>(std::filesystem::file_size(path));
    std::filesystem::remove(path);
  }
}
BENCHMARK(BM_OpenCV_ImwriteExrHalf)
    ->Arg(cv::IMWRITE_EXR_COMPRESSION_ZIP)
    ->Arg(cv::IMWRITE_EXR_COMPRESSION_PIZ)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// --- The env-lit preview ------------------------------------------------------------------

const Environment& Sunset() {
  static const Environment environment = Environment::Load(DataFile("hdr/venice_sunset_1k.hdr"));
  return environment;
}

const Material& Plastic() {
  static const std::unique_ptr<Material> material =
      LoadMaterial("blinn-phong:rho_d=0.5,0.1,0.1:rho_s=0.04:m=200");
  return *material;
}

void BM_RenderEnvironment(benchmark::State& state) {
  RenderOptions options;
  options.size = static_cast<int>(state.range(0));
  options.spp = static_cast<int>(state.range(1));
  for (auto _ : state) {
    benchmark::DoNotOptimize(RenderSphere(Plastic(), {}, &Sunset(), options));
  }
}
BENCHMARK(BM_RenderEnvironment)
    ->Args({512, 64})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Iterations(1);

// Noise against spp on a 128^2 preview: RMS relative error against a 4096-spp reference (a
// counter; the timing is incidental).
void BM_RenderNoise(benchmark::State& state) {
  RenderOptions options;
  options.size = 128;
  static const RenderResult reference = [] {
    RenderOptions many;
    many.size = 128;
    many.spp = 4096;
    many.seed = 12345;
    return RenderSphere(Plastic(), {}, &Sunset(), many);
  }();
  options.spp = static_cast<int>(state.range(0));
  RenderResult result;
  for (auto _ : state) result = RenderSphere(Plastic(), {}, &Sunset(), options);
  double squares = 0.0;
  int64_t pixels = 0;
  for (int64_t i = 0; i < result.radiance.pixel_count(); ++i) {
    const float* a = &result.radiance.rgba[i * 4];
    const float* b = &reference.radiance.rgba[i * 4];
    if (b[3] == 0.0f) continue;
    const double relative = (PixelLuminance(a) - PixelLuminance(b)) / PixelLuminance(b);
    squares += relative * relative;
    ++pixels;
  }
  state.counters["rms_rel_error"] = std::sqrt(squares / pixels);
}
BENCHMARK(BM_RenderNoise)
    ->Arg(1)
    ->Arg(4)
    ->Arg(16)
    ->Arg(64)
    ->Arg(256)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Iterations(1);

}  // namespace
}  // namespace brdf

int main(int argc, char** argv) {
  // As in the brdf executable (src/cli/main.cpp): large image buffers are reused, not remapped.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  // Debian's OpenCV reads and writes OpenEXR only when asked to.
  setenv("OPENCV_IO_ENABLE_OPENEXR", "1", 1);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
