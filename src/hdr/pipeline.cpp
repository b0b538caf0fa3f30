#include "hdr/pipeline.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <type_traits>
#include <vector>

#include "core/colour.h"
#include "core/errors.h"
#include "core/format.h"
#include "core/simd.h"
#include "hdr/bloom.h"
#include "hdr/exposure.h"

#if BRDF_HAS_AVX2_PATHS
#include <immintrin.h>
#endif

namespace brdf {

void ToneOptions::Validate() const {
  auto positive = [](double value) { return value > 0.0 && std::isfinite(value); };
  if (exposure && !positive(*exposure)) throw UsageError("exposure must be > 0");
  if (!positive(key) || key >= 1.0) throw UsageError("the key must lie in (0, 1)");
  if (!positive(delta)) throw UsageError("delta must be > 0");
  if (!std::isfinite(white) || white < 0.0) throw UsageError("white must be 'auto' or > 0");
  if (!(bloom_threshold >= 0.0) || !std::isfinite(bloom_threshold)) {
    throw UsageError("the bloom threshold must be >= 0");
  }
  if (!(bloom_strength >= 0.0) || !std::isfinite(bloom_strength)) {
    throw UsageError("the bloom strength must be >= 0");
  }
  if (!positive(bloom_sigma) || bloom_sigma > 1000.0) {
    throw UsageError("the bloom sigma must lie in (0, 1000] px");
  }
}

std::string ToneResult::Summary(bool radiometric) const {
  std::string text =
      radiometric
          ? Format(
                "%dx%d, log-average luminance %.4g W/(m^2 sr) = %.4g cd/m^2, max %.4g "
                "W/(m^2 sr) = %.4g cd/m^2, exposure %.4g",
                display.width, display.height, scene.log_average, RadianceToNits(scene.log_average),
                scene.max, RadianceToNits(scene.max), exposure)
          : Format(
                "%dx%d, log-average luminance %.4g, max %.4g (the file's own units), "
                "exposure %.4g",
                display.width, display.height, scene.log_average, scene.max, exposure);
  // "tone map" names the operator apart from the exposure factor printed before it.
  text += std::string(", tone map ") + ToneOperatorName(mapping.tone_operator);
  if (mapping.tone_operator == ToneOperator::kExposure) text += " (1 - exp(-x))";
  if (mapping.tone_operator == ToneOperator::kReinhardExtended) {
    text += Format(" L_white %.4g", mapping.white);
  }
  if (bloom_sigma > 0.0) text += Format(", bloom sigma %.3g px", bloom_sigma);
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
  if (scene.black_pixels == scene.pixels) {
    return Format("all %lld pixels are black (luminance <= 0): nothing to expose",
                  static_cast<long long>(scene.pixels));
  }
  const double factor = scene.log_average_lit / scene.log_average;
  if (!(factor >= kVisibleExposureFactor)) return "";
  return Format(
      "%lld of %lld pixels (%.3g%%) are black (luminance <= 0) and raise the automatic "
      "exposure %.3gx (%.2g stops) over the rest's; give an explicit exposure to choose it",
      static_cast<long long>(scene.black_pixels), static_cast<long long>(scene.pixels),
      100.0 * scene.black_pixels / scene.pixels, factor, std::log2(factor));
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

namespace {

// Rows per task of the last pass.
constexpr int kRowsPerTask = 8;

// Pixel x of a row kept as red, green and blue planes of `width` floats, as RGB.
inline void KeptPixel(const float* planes, int width, int x, float rgb[3]) {
  for (int c = 0; c < 3; ++c) rgb[c] = planes[int64_t{c} * width + x];
}

#if BRDF_HAS_AVX2_PATHS
// PixelToneMap<kOperator> on eight pixels given as planes channel[c], with its operations in
// its order, into red[0..8), green[0..8), blue[0..8). Not for the exponential operator
// (std::exp has no exact vector twin).
template <ToneOperator kOperator>
BRDF_AVX2 inline void ToneMapEightAvx2(const __m256 channel[3], __m256 key8, __m256 white_squared,
                                       float* red, float* green, float* blue) {
  static_assert(kOperator != ToneOperator::kExposure, "std::exp has no exact vector twin");
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
  const __m256 world =
      _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(0.2126f), channel[0]),
                                  _mm256_mul_ps(_mm256_set1_ps(0.7152f), channel[1])),
                    _mm256_mul_ps(_mm256_set1_ps(0.0722f), channel[2]));
  __m256 display = world;
  if constexpr (kOperator == ToneOperator::kReinhard) {
    const __m256 scaled = _mm256_mul_ps(key8, world);
    display = _mm256_div_ps(scaled, _mm256_add_ps(one, scaled));
  } else if constexpr (kOperator == ToneOperator::kReinhardExtended) {
    const __m256 scaled = _mm256_mul_ps(key8, world);
    display = _mm256_div_ps(
        _mm256_mul_ps(scaled, _mm256_add_ps(one, _mm256_div_ps(scaled, white_squared))),
        _mm256_add_ps(one, scaled));
  }
  // L_d / L_w where L_w > 0, else 0.
  const __m256 ratio =
      _mm256_and_ps(_mm256_div_ps(display, world), _mm256_cmp_ps(world, zero, _CMP_GT_OQ));
  float* const planes[3] = {red, green, blue};
  for (int c = 0; c < 3; ++c) {
    // std::clamp(v, 0, 1): v < 0 ? 0 : (1 < v ? 1 : v).
    __m256 v = _mm256_mul_ps(channel[c], ratio);
    v = _mm256_blendv_ps(v, zero, _mm256_cmp_ps(v, zero, _CMP_LT_OQ));
    v = _mm256_blendv_ps(v, one, _mm256_cmp_ps(one, v, _CMP_LT_OQ));
    _mm256_storeu_ps(planes[c], v);
  }
}

// PixelToneMap<kOperator> on the pixels [0, 8n) of a row kept as three planes (in[x],
// in[width + x], in[2 width + x]); returns 8n.
template <ToneOperator kOperator>
BRDF_AVX2 int ToneMapPlanesAvx2(const float* in, int width, float key_scale, float white,
                                float* red, float* green, float* blue) {
  const __m256 key8 = _mm256_set1_ps(key_scale), white_squared = _mm256_set1_ps(white * white);
  int x = 0;
  for (; x + 8 <= width; x += 8) {
    const __m256 channel[3] = {_mm256_loadu_ps(in + x), _mm256_loadu_ps(in + width + x),
                               _mm256_loadu_ps(in + 2 * int64_t{width} + x)};
    ToneMapEightAvx2<kOperator>(channel, key8, white_squared, red + x, green + x, blue + x);
  }
  return x;
}

// PixelToneMap<kOperator> on the pixels [0, 8n) of the RGBA row ExposeRow(row, add, scale,
// strength) would make, made here on the way; writes the planes red[x], green[x], blue[x];
// returns 8n.
template <ToneOperator kOperator>
BRDF_AVX2 int ToneMapRowAvx2(const float* row, const float* add, float scale, float strength,
                             int width, float key_scale, float white, float* red, float* green,
                             float* blue) {
  const __m256 key8 = _mm256_set1_ps(key_scale), white_squared = _mm256_set1_ps(white * white);
  const __m256 scale8 = _mm256_set1_ps(scale), strength8 = _mm256_set1_ps(strength);
  int x = 0;
  for (; x + 8 <= width; x += 8) {
    const int64_t at = int64_t{x} * Image::kChannels;
    __m256 quad[4];  // pixels k and k + 4 in the halves of quad[k]
    for (int k = 0; k < 4; ++k) {
      quad[k] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(row + at + 4 * k)),
                                     _mm_loadu_ps(row + at + 16 + 4 * k), 1);
      // ExposeRow's arithmetic (alpha is not needed here).
      quad[k] = _mm256_mul_ps(quad[k], scale8);
      if (add != nullptr) {
        const __m256 bloom =
            _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(add + at + 4 * k)),
                                 _mm_loadu_ps(add + at + 16 + 4 * k), 1);
        quad[k] = _mm256_add_ps(quad[k], _mm256_mul_ps(strength8, bloom));
      }
    }
    const __m256 t0 = _mm256_unpacklo_ps(quad[0], quad[1]),
                 t1 = _mm256_unpackhi_ps(quad[0], quad[1]);
    const __m256 t2 = _mm256_unpacklo_ps(quad[2], quad[3]),
                 t3 = _mm256_unpackhi_ps(quad[2], quad[3]);
    const __m256 channel[3] = {_mm256_shuffle_ps(t0, t2, 0x44), _mm256_shuffle_ps(t0, t2, 0xee),
                               _mm256_shuffle_ps(t1, t3, 0x44)};
    ToneMapEightAvx2<kOperator>(channel, key8, white_squared, red + x, green + x, blue + x);
  }
  return x;
}
#endif

// The exposed and bloomed image, row by row, never stored whole: row y is
// exposure * input (+ strength * bloom), the arithmetic of ApplyExposure and AddBloom. The
// bloom is either full size or (dual filtering) at half size, its last doubling step taken
// here, per row.
class ExposedRows {
 public:
  ExposedRows(const Image& image, double exposure, const Image* bloom, bool bloom_is_half,
              double strength)
      : image_(image),
        scale_(static_cast<float>(exposure)),
        bloom_(bloom),
        bloom_is_half_(bloom_is_half),
        strength_(static_cast<float>(strength)) {}

  float scale() const { return scale_; }
  float strength() const { return strength_; }
  // Row y of the input and of the full-size bloom (null without bloom), the bloom's row made
  // in `bloom_scratch` (width * 4 floats) when it is kept at half size.
  ExposedRowSource Sources(int y, float* bloom_scratch) const {
    ExposedRowSource source;
    source.in = image_.pixel(0, y);
    if (bloom_ != nullptr && bloom_is_half_) {
      DualFilterUpRow(*bloom_, image_.width, y, bloom_scratch);
      source.add = bloom_scratch;
    } else if (bloom_ != nullptr) {
      source.add = bloom_->pixel(0, y);
    }
    return source;
  }
  // Row y into `scratch` (width * 4 floats); `bloom_scratch` has as much room again.
  const float* Row(int y, float* scratch, float* bloom_scratch) const {
    const ExposedRowSource source = Sources(y, bloom_scratch);
    ExposeRow(source.in, source.add, image_.width, scale_, strength_, scratch);
    return scratch;
  }

 private:
  const Image& image_;
  float scale_;
  const Image* bloom_;
  bool bloom_is_half_;
  float strength_;
};

}  // namespace

// The stages of pipeline.h fused into as few passes over the full-size image as the data
// allow, with the stages' own per-pixel arithmetic, so the bytes are those of running the
// stages one after another (tests/hdr_tone_test.cpp checks it):
//   1. scene statistics of the input (the automatic exposure needs them first);
//   2. with bloom: exposure, bright pass and the first step down read the input once
//      (dual filtering; the other blurs run on a full-size bright image); the rest of the
//      blur runs at half size;
//   3. Reinhard only: statistics of the exposed and bloomed image, made a row at a time
//      (the last doubling step of the bloom included) and not stored;
//   4. the same rows again, tone mapped, encoded and rounded to 8 bits.
ToneResult RunTonePipeline(const Image& image, const ToneOptions& options) {
  options.Validate();
  ToneResult result;
  const bool blooming = options.bloom != BlurKind::kNone && options.bloom_strength > 0.0;
  // The row segments' channel peaks let the fused bright pass skip what they prove dark.
  std::vector<float> peaks;
  if (blooming && options.bloom == BlurKind::kDual) {
    peaks.resize(PeakFloats(image.width, image.height));
  }
  result.scene =
      MeasureSceneLuminance(image, options.delta, peaks.empty() ? nullptr : peaks.data());
  result.exposure = options.exposure ? *options.exposure : AutoExposure(result.scene, options.key);
  if (!options.exposure) {
    const std::string warning = BlackPixelWarning(result.scene);
    if (!warning.empty()) result.warnings.push_back(warning);
  }

  Image bloom;
  bool bloom_is_half = false;
  if (blooming) {
    if (options.bloom == BlurKind::kDual) {
      bloom = DualFilterFromHalf(
          BrightPassDown(image, options.bloom_threshold, result.exposure, peaks.data()),
          DualFilterLevelsForSigma(options.bloom_sigma));
      bloom_is_half = true;
    } else {
      bloom = Blur(BrightPass(image, options.bloom_threshold, result.exposure), options.bloom,
                   options.bloom_sigma);
    }
    result.bloom_sigma = DesignedSigma(options.bloom, options.bloom_sigma);
  }
  const ExposedRows rows(image, result.exposure, blooming ? &bloom : nullptr, bloom_is_half,
                         options.bloom_strength);
  const int width = image.width;
  const int64_t row_floats = int64_t{width} * Image::kChannels;

  // Reinhard's key scaling needs the statistics of what is being mapped (after exposure and
  // bloom); the other operators need none.
  const bool reinhard = options.tone_operator == ToneOperator::kReinhard ||
                        options.tone_operator == ToneOperator::kReinhardExtended;
  SceneLuminance mapped;
  // With dual-filter bloom a row costs its doubling step (13 taps a pixel): the statistics
  // pass keeps the rows it makes for the last pass, which then reads them instead (one write
  // and one read of the frame cost less than the taps again).
  // The rows are kept as red, green and blue planes (tone mapping reads no alpha): three
  // quarters of the memory traffic of RGBA rows, and no interleaving on either side.
  std::unique_ptr<float[]> kept;
  const int64_t kept_floats = 3 * int64_t{width};
  if (reinhard) {
    if (bloom_is_half) kept.reset(new float[kept_floats * image.height]);
    mapped = MeasureExposedLuminanceByRow(width, image.height, options.delta, rows.scale(),
                                          rows.strength(), [&](int y, float* scratch) {
                                            ExposedRowSource source = rows.Sources(y, scratch);
                                            if (kept) source.keep = kept.get() + y * kept_floats;
                                            return source;
                                          });
  }
  result.mapping = PlanToneMapping(options.tone_operator, mapped, options.key, options.white);

  const Quantizer8 quantize(options.transfer);
  Image8& display = result.display;
  display.width = width;
  display.height = image.height;
  display.rgb.resize(image.pixel_count() * 3);
  const int tasks = (image.height + kRowsPerTask - 1) / kRowsPerTask;
  [[maybe_unused]] const bool avx2 = Avx2Enabled();
  ForToneOperator(result.mapping, [&](const auto& map) {
    [[maybe_unused]] constexpr ToneOperator kOperator = std::decay_t<decltype(map)>::kToneOperator;
    tbb::parallel_for(0, tasks, [&](int task) {
      // Every float of these rows is written before it is read: not zero-filled (a vector's
      // zero-filling, per task, cost as much as a pass over the frame).
      const std::unique_ptr<float[]> scratch_rows(new float[2 * row_floats]);
      float* const scratch = scratch_rows.get();
      // One row tone mapped: RGB, or (AVX2) three planes.
      const std::unique_ptr<float[]> mapped_row(new float[int64_t{width} * 3]);
      float* const mapped = mapped_row.get();
      const int y1 = std::min(image.height, (task + 1) * kRowsPerTask);
      for (int y = task * kRowsPerTask; y < y1; ++y) {
        uint8_t* out = display.rgb.data() + int64_t{y} * width * 3;
#if BRDF_HAS_AVX2_PATHS
        if constexpr (kOperator != ToneOperator::kExposure) {
          if (avx2) {
            float* const red = mapped;
            float* const green = red + width;
            float* const blue = green + width;
            // The kept planes, or the exposure (and bloom) made on the way from the input.
            const float* const planes = kept ? kept.get() + y * kept_floats : nullptr;
            int x = 0;
            if (planes != nullptr) {
              x = ToneMapPlanesAvx2<kOperator>(planes, width, map.key_scale(), map.white(), red,
                                               green, blue);
            } else {
              const ExposedRowSource source = rows.Sources(y, scratch + row_floats);
              x = ToneMapRowAvx2<kOperator>(source.in, source.add, rows.scale(), rows.strength(),
                                            width, map.key_scale(), map.white(), red, green, blue);
              if (x < width) {  // the last pixels through the scalar path
                const int64_t at = int64_t{x} * Image::kChannels;
                ExposeRow(source.in + at, source.add == nullptr ? nullptr : source.add + at,
                          width - x, rows.scale(), rows.strength(), scratch + at);
              }
            }
            for (; x < width; ++x) {
              float in[3], rgb[3];
              if (planes != nullptr) KeptPixel(planes, width, x, in);
              map(planes != nullptr ? in : scratch + int64_t{x} * Image::kChannels, rgb);
              red[x] = rgb[0], green[x] = rgb[1], blue[x] = rgb[2];
            }
            quantize.EncodePlanes(red, green, blue, width, out);
            continue;
          }
        }
#endif
        if (kept) {
          const float* const planes = kept.get() + y * kept_floats;
          for (int x = 0; x < width; ++x) {
            float in[3];
            KeptPixel(planes, width, x, in);
            map(in, mapped + 3 * x);
          }
        } else {
          const float* row = rows.Row(y, scratch, scratch + row_floats);
          for (int x = 0; x < width; ++x) {
            map(row + int64_t{x} * Image::kChannels, mapped + 3 * x);
          }
        }
        quantize.EncodeMany(mapped, int64_t{width} * 3, out);
      }
    });
  });
  return result;
}

}  // namespace brdf
