#include "hdr/pipeline.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>

#include "core/errors.h"
#include "hdr/bloom.h"
#include "hdr/exposure.h"

namespace brdf {

void ToneOptions::Validate() const {
  auto positive = [](double value) { return value > 0.0 && std::isfinite(value); };
  if (exposure && !positive(*exposure)) throw UsageError("--exposure must be > 0");
  if (!positive(key) || key >= 1.0) throw UsageError("--key must lie in (0, 1)");
  if (!positive(delta)) throw UsageError("delta must be > 0");
  if (!std::isfinite(white) || white < 0.0) throw UsageError("--white must be 'auto' or > 0");
  if (!(bloom_threshold >= 0.0) || !std::isfinite(bloom_threshold)) {
    throw UsageError("--bloom-threshold must be >= 0");
  }
  if (!(bloom_strength >= 0.0) || !std::isfinite(bloom_strength)) {
    throw UsageError("--bloom-strength must be >= 0");
  }
  if (!positive(bloom_sigma) || bloom_sigma > 1000.0) {
    throw UsageError("--bloom-sigma must lie in (0, 1000] px");
  }
}

std::string ToneResult::Summary() const {
  char buffer[256];
  std::string text;
  std::snprintf(buffer, sizeof(buffer),
                "%dx%d, log-average luminance %.4g, max %.4g, exposure %.4g", display.width,
                display.height, scene.log_average, scene.max, exposure);
  text = buffer;
  text += std::string(", ") + ToneOperatorName(mapping.tone_operator);
  if (mapping.tone_operator == ToneOperator::kReinhardExtended) {
    std::snprintf(buffer, sizeof(buffer), " L_white %.4g", mapping.white);
    text += buffer;
  }
  if (bloom_sigma > 0.0) {
    std::snprintf(buffer, sizeof(buffer), ", bloom sigma %.3g px", bloom_sigma);
    text += buffer;
  }
  return text;
}

namespace {

// Black pixels enter the log-average as log(delta) (Reinhard 2002, eq. 1): a share b of them
// multiplies the automatic exposure by (L_lit / delta)^b, L_lit the log-average of the rest —
// 100x for half an image of black background at L_lit = 1. One photographic stop (a factor 2)
// is the smallest exposure change a viewer plainly sees, so the pipeline says so from there.
constexpr double kVisibleExposureFactor = 2.0;

std::string BlackPixelWarning(const SceneLuminance& scene) {
  if (scene.black_pixels == 0 || scene.pixels == 0) return "";
  char buffer[320];
  if (scene.black_pixels == scene.pixels) {
    std::snprintf(buffer, sizeof(buffer),
                  "all %lld pixels are black (luminance <= 0): nothing to expose",
                  static_cast<long long>(scene.pixels));
    return buffer;
  }
  const double factor = scene.log_average_lit / scene.log_average;
  if (!(factor >= kVisibleExposureFactor)) return "";
  std::snprintf(buffer, sizeof(buffer),
                "%lld of %lld pixels (%.3g%%) are black (luminance <= 0) and raise the automatic "
                "exposure %.3gx (%.2g stops) over the rest's; set --exposure to choose it",
                static_cast<long long>(scene.black_pixels), static_cast<long long>(scene.pixels),
                100.0 * scene.black_pixels / scene.pixels, factor, std::log2(factor));
  return buffer;
}

}  // namespace

Image8 EncodeDisplay(const Image& image, const TransferCurve& transfer) {
  const Quantizer8 quantize(transfer);
  Image8 display;
  display.width = image.width;
  display.height = image.height;
  display.rgb.resize(image.pixel_count() * 3);
  tbb::parallel_for(0, image.height, [&](int y) {
    const float* in = image.pixel(0, y);
    uint8_t* out = display.rgb.data() + int64_t{y} * image.width * 3;
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < 3; ++c) out[3 * x + c] = quantize(in[Image::kChannels * x + c]);
    }
  });
  return display;
}

ToneResult RunTonePipeline(Image image, const ToneOptions& options) {
  options.Validate();
  ToneResult result;
  result.scene = MeasureSceneLuminance(image, options.delta);
  result.exposure = options.exposure ? *options.exposure : AutoExposure(result.scene, options.key);
  if (!options.exposure) {
    const std::string warning = BlackPixelWarning(result.scene);
    if (!warning.empty()) result.warnings.push_back(warning);
  }
  ApplyExposure(&image, result.exposure);

  if (options.bloom != BlurKind::kNone && options.bloom_strength > 0.0) {
    const Image bloom =
        Blur(BrightPass(image, options.bloom_threshold), options.bloom, options.bloom_sigma);
    AddBloom(&image, bloom, options.bloom_strength);
    result.bloom_sigma = DesignedSigma(options.bloom, options.bloom_sigma);
  }

  // Reinhard's key scaling needs the statistics of what is being mapped (after exposure and
  // bloom); the other operators need none.
  const bool reinhard = options.tone_operator == ToneOperator::kReinhard ||
                        options.tone_operator == ToneOperator::kReinhardExtended;
  const SceneLuminance mapped =
      reinhard ? MeasureSceneLuminance(image, options.delta) : SceneLuminance{};
  result.mapping = PlanToneMapping(options.tone_operator, mapped, options.key, options.white);
  ApplyToneMapping(&image, result.mapping);
  result.display = EncodeDisplay(image, options.transfer);
  return result;
}

}  // namespace brdf
