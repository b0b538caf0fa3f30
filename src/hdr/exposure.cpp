#include "hdr/exposure.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "core/deterministic_reduce.h"
#include "core/errors.h"
#include "core/simd.h"

#if BRDF_HAS_AVX2_PATHS
#include <immintrin.h>
#endif

namespace brdf {
namespace {

// Pixels per chunk of the log-average sum (rounded to whole rows).
constexpr int64_t kPixelGrain = 16384;

struct LogSum {
  double log_sum = 0.0;
  double lit_log_sum = 0.0;
  double max = 0.0;
  int64_t pixels = 0;
  int64_t black = 0;
};

// Natural logarithm of a positive, finite, normal float, within about 2 float ulps; the
// library's scalar log per pixel was most of the statistics pass. x = 2^e m with m in
// [sqrt(1/2), sqrt(2)), and log m = 2 atanh(s) = 2 (s + s^3/3 + s^5/5 + ...) with
// s = (m - 1) / (m + 1), |s| <= 0.172: the series to s^9 leaves a relative error below 1e-8.
inline float LogOfNormal(float x) {
  int32_t bits;
  std::memcpy(&bits, &x, sizeof(bits));
  int32_t exponent = ((bits >> 23) & 0xff) - 127;
  const int32_t mantissa_bits = (bits & 0x007fffff) | 0x3f800000;
  float m;
  std::memcpy(&m, &mantissa_bits, sizeof(m));
  const bool above = m > 1.41421356f;
  m = above ? m * 0.5f : m;
  exponent += above ? 1 : 0;
  const float s = (m - 1.0f) / (m + 1.0f);
  const float s2 = s * s;
  const float series = 1.0f + s2 * (1.0f / 3 + s2 * (1.0f / 5 + s2 * (1.0f / 7 + s2 * (1.0f / 9))));
  return static_cast<float>(exponent) * 0.693147181f + 2.0f * s * series;
}

// Sums of one chunk in four lanes (pixel x goes to lane x mod 4), joined in a fixed order.
struct LaneSums {
  double log_sum[4] = {};
  double lit_log_sum[4] = {};
  float max[4] = {};
  int32_t pixels[4] = {};
  int32_t black[4] = {};
};

// Folds four pixels (alpha and luminance clamped at 0; padding lanes have alpha 0) into `sums`:
// LogOfNormal when all four arguments are normal floats, else the library's log for the four.
inline void AddFour(const float luminance[4], const float alpha[4], float delta, LaneSums* sums) {
  constexpr float kLargest = std::numeric_limits<float>::max();
  constexpr float kSmallest = std::numeric_limits<float>::min();  // the least normal float
  float argument[4];
  bool normal = true;
  for (int k = 0; k < 4; ++k) {
    argument[k] = delta + luminance[k];
    normal &= (argument[k] <= kLargest) & (argument[k] >= kSmallest);
  }
  float logs[4];
  if (normal) {
    for (int k = 0; k < 4; ++k) logs[k] = LogOfNormal(argument[k]);
  } else {  // an infinite pixel or a subnormal delta
    for (int k = 0; k < 4; ++k) logs[k] = std::log(argument[k]);
  }
  for (int k = 0; k < 4; ++k) {
    const bool counted = alpha[k] > 0.0f;
    const bool lit = counted & (luminance[k] > 0.0f);
    sums->log_sum[k] += static_cast<double>(counted ? logs[k] : 0.0f);
    sums->lit_log_sum[k] += static_cast<double>(lit ? logs[k] : 0.0f);
    sums->max[k] = (counted & (luminance[k] > sums->max[k])) ? luminance[k] : sums->max[k];
    sums->pixels[k] += counted;
    sums->black[k] += counted & !lit;
  }
}

#if BRDF_HAS_AVX2_PATHS
// Four RGBA pixels in each 128-bit half of `quad` (p[k] pixel k of the half) as planes:
// channel[c] holds channel c of pixels 0..3 (low half) and 4..7 (high half).
BRDF_AVX2 inline void TransposeQuads(const __m256 quad[4], __m256 channel[4]) {
  const __m256 t0 = _mm256_unpacklo_ps(quad[0], quad[1]);  // r0 r1 g0 g1
  const __m256 t1 = _mm256_unpackhi_ps(quad[0], quad[1]);  // b0 b1 a0 a1
  const __m256 t2 = _mm256_unpacklo_ps(quad[2], quad[3]);  // r2 r3 g2 g3
  const __m256 t3 = _mm256_unpackhi_ps(quad[2], quad[3]);  // b2 b3 a2 a3
  channel[0] = _mm256_shuffle_ps(t0, t2, 0x44);
  channel[1] = _mm256_shuffle_ps(t0, t2, 0xee);
  channel[2] = _mm256_shuffle_ps(t1, t3, 0x44);
  channel[3] = _mm256_shuffle_ps(t1, t3, 0xee);
}

// LogOfNormal on eight lanes: the same operations, so the same bits.
BRDF_AVX2 inline __m256 Log8(__m256 x) {
  const __m256i bits = _mm256_castps_si256(x);
  __m256i exponent =
      _mm256_sub_epi32(_mm256_and_si256(_mm256_srli_epi32(bits, 23), _mm256_set1_epi32(0xff)),
                       _mm256_set1_epi32(127));
  __m256 m = _mm256_castsi256_ps(_mm256_or_si256(
      _mm256_and_si256(bits, _mm256_set1_epi32(0x007fffff)), _mm256_set1_epi32(0x3f800000)));
  const __m256 above = _mm256_cmp_ps(m, _mm256_set1_ps(1.41421356f), _CMP_GT_OQ);
  m = _mm256_blendv_ps(m, _mm256_mul_ps(m, _mm256_set1_ps(0.5f)), above);
  exponent = _mm256_sub_epi32(exponent, _mm256_castps_si256(above));
  const __m256 one = _mm256_set1_ps(1.0f);
  const __m256 s = _mm256_div_ps(_mm256_sub_ps(m, one), _mm256_add_ps(m, one));
  const __m256 s2 = _mm256_mul_ps(s, s);
  __m256 series =
      _mm256_add_ps(_mm256_set1_ps(1.0f / 7), _mm256_mul_ps(s2, _mm256_set1_ps(1.0f / 9)));
  series = _mm256_add_ps(_mm256_set1_ps(1.0f / 5), _mm256_mul_ps(s2, series));
  series = _mm256_add_ps(_mm256_set1_ps(1.0f / 3), _mm256_mul_ps(s2, series));
  series = _mm256_add_ps(one, _mm256_mul_ps(s2, series));
  const __m256 e = _mm256_cvtepi32_ps(exponent);
  return _mm256_add_ps(_mm256_mul_ps(e, _mm256_set1_ps(0.693147181f)),
                       _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(2.0f), s), series));
}

// Raises target[c] to the largest lane of peak[c] (RaisePeaks' comparison) and resets the
// lanes to -infinity.
BRDF_AVX2 inline void FlushPeaks(__m256 peak[3], float* target) {
  for (int c = 0; c < 3; ++c) {
    alignas(32) float lanes[8];
    _mm256_store_ps(lanes, peak[c]);
    for (float lane : lanes) target[c] = lane > target[c] ? lane : target[c];
    peak[c] = _mm256_set1_ps(-std::numeric_limits<float>::infinity());
  }
}

// AddRow's loop eight pixels at a time: pixels x0..x0+3 are folded into the lanes, then
// x0+4..x0+7, each group as AddFour does it (the library's log for a whole group of four with
// an argument that is not a normal float). Returns the first pixel not folded.
//
// With kExpose, the row is made on the way from `in` (and `add`) as ExposeRow does it, and its
// red, green and blue stored to the planes keep[x], keep[width + x], keep[2 width + x] when
// `keep` is not null; otherwise `in` is the row and the rest unused.
// `peaks` (not null): the row's segment peaks (exposure.h) raised to the largest red, green and
// blue of the pixels folded, as RaisePeaks does it.
template <bool kExpose>
BRDF_AVX2 int AddRowAvx2(const float* in, const float* add, float scale, float strength,
                         float* keep, int width, float delta, LaneSums* sums, float* peaks) {
  __m256d log_sum, lit_log_sum;
  std::memcpy(&log_sum, &sums->log_sum, sizeof(log_sum));
  std::memcpy(&lit_log_sum, &sums->lit_log_sum, sizeof(lit_log_sum));
  // Maxima and counts in eight lanes, lane k + 4 folded into lane k at the end (neither the
  // maximum nor an integer count depends on the order).
  __m128 max4;
  __m128i pixels4, black4;
  std::memcpy(&max4, &sums->max, sizeof(max4));
  std::memcpy(&pixels4, &sums->pixels, sizeof(pixels4));
  std::memcpy(&black4, &sums->black, sizeof(black4));
  __m256 max = _mm256_castps128_ps256(max4);
  max = _mm256_insertf128_ps(max, _mm_setzero_ps(), 1);
  __m256i pixels = _mm256_setzero_si256(), black = _mm256_setzero_si256();
  const __m256 zero = _mm256_setzero_ps();
  const __m256 delta8 = _mm256_set1_ps(delta);
  const __m256 largest = _mm256_set1_ps(std::numeric_limits<float>::max());
  const __m256 smallest = _mm256_set1_ps(std::numeric_limits<float>::min());
  int x0 = 0;
  const __m256 scale8 = _mm256_set1_ps(scale), strength8 = _mm256_set1_ps(strength);
  // The peaks of segment `pending` so far, eight lanes each.
  const __m256 lowest = _mm256_set1_ps(-std::numeric_limits<float>::infinity());
  __m256 peak[3] = {lowest, lowest, lowest};
  static_assert(kPeakSegment % 8 == 0, "eight pixels lie in one segment");
  int pending = -1;

  for (; x0 + 8 <= width; x0 += 8) {
    const int64_t at = int64_t{x0} * Image::kChannels;
    __m256 quad[4], channel[4];
    for (int k = 0; k < 4; ++k) {
      quad[k] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(in + at + 4 * k)),
                                     _mm_loadu_ps(in + at + 16 + 4 * k), 1);
    }
    if constexpr (kExpose) {
      for (int k = 0; k < 4; ++k) {
        __m256 exposed = _mm256_mul_ps(quad[k], scale8);
        if (add != nullptr) {
          const __m256 bloom =
              _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(add + at + 4 * k)),
                                   _mm_loadu_ps(add + at + 16 + 4 * k), 1);
          exposed = _mm256_add_ps(exposed, _mm256_mul_ps(strength8, bloom));
        }
        quad[k] = _mm256_blend_ps(exposed, quad[k], 0x88);  // alpha kept
      }
    }
    TransposeQuads(quad, channel);
    if (kExpose && keep != nullptr) {  // the exposed red, green and blue as planes
      for (int c = 0; c < 3; ++c) _mm256_storeu_ps(keep + int64_t{c} * width + x0, channel[c]);
    }
    if (peaks != nullptr) {
      const int segment = x0 / kPeakSegment;  // eight pixels never straddle two segments
      if (segment != pending) {
        if (pending >= 0) FlushPeaks(peak, peaks + 3 * pending);
        pending = segment;
      }
      // maxps(v, peak) is v > peak ? v : peak, RaisePeaks' comparison (NaN skipped).
      for (int c = 0; c < 3; ++c) peak[c] = _mm256_max_ps(channel[c], peak[c]);
    }
    // PixelLuminance's operations in its order, then std::max(0, L) (NaN gives 0).
    __m256 luminance =
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(0.2126f), channel[0]),
                                    _mm256_mul_ps(_mm256_set1_ps(0.7152f), channel[1])),
                      _mm256_mul_ps(_mm256_set1_ps(0.0722f), channel[2]));
    luminance = _mm256_and_ps(luminance, _mm256_cmp_ps(luminance, zero, _CMP_GT_OQ));
    const __m256 argument = _mm256_add_ps(delta8, luminance);
    __m256 logs = Log8(argument);
    const int normal =
        _mm256_movemask_ps(_mm256_and_ps(_mm256_cmp_ps(argument, largest, _CMP_LE_OQ),
                                         _mm256_cmp_ps(argument, smallest, _CMP_GE_OQ)));
    if (normal != 0xff) {  // a group of four with an infinite or subnormal argument
      alignas(32) float lanes[8], arguments[8];
      _mm256_store_ps(lanes, logs);
      _mm256_store_ps(arguments, argument);
      for (int group = 0; group < 2; ++group) {
        if (((normal >> (4 * group)) & 0xf) == 0xf) continue;
        for (int k = 4 * group; k < 4 * group + 4; ++k) lanes[k] = std::log(arguments[k]);
      }
      logs = _mm256_load_ps(lanes);
    }
    const __m256 counted = _mm256_cmp_ps(channel[3], zero, _CMP_GT_OQ);
    const __m256 lit = _mm256_and_ps(counted, _mm256_cmp_ps(luminance, zero, _CMP_GT_OQ));
    const __m256 counted_logs = _mm256_and_ps(logs, counted);
    const __m256 lit_logs = _mm256_and_ps(logs, lit);
    log_sum = _mm256_add_pd(log_sum, _mm256_cvtps_pd(_mm256_castps256_ps128(counted_logs)));
    lit_log_sum = _mm256_add_pd(lit_log_sum, _mm256_cvtps_pd(_mm256_castps256_ps128(lit_logs)));
    log_sum = _mm256_add_pd(log_sum, _mm256_cvtps_pd(_mm256_extractf128_ps(counted_logs, 1)));
    lit_log_sum = _mm256_add_pd(lit_log_sum, _mm256_cvtps_pd(_mm256_extractf128_ps(lit_logs, 1)));
    max = _mm256_blendv_ps(max, luminance,
                           _mm256_and_ps(counted, _mm256_cmp_ps(luminance, max, _CMP_GT_OQ)));
    pixels = _mm256_sub_epi32(pixels, _mm256_castps_si256(counted));
    black = _mm256_sub_epi32(black, _mm256_castps_si256(_mm256_andnot_ps(lit, counted)));
  }
  std::memcpy(&sums->log_sum, &log_sum, sizeof(log_sum));
  std::memcpy(&sums->lit_log_sum, &lit_log_sum, sizeof(lit_log_sum));
  max4 = _mm256_castps256_ps128(max);
  const __m128 high = _mm256_extractf128_ps(max, 1);
  max4 = _mm_blendv_ps(max4, high, _mm_cmpgt_ps(high, max4));
  pixels4 = _mm_add_epi32(_mm_add_epi32(pixels4, _mm256_castsi256_si128(pixels)),
                          _mm256_extracti128_si256(pixels, 1));
  black4 = _mm_add_epi32(_mm_add_epi32(black4, _mm256_castsi256_si128(black)),
                         _mm256_extracti128_si256(black, 1));
  std::memcpy(&sums->max, &max4, sizeof(max4));
  std::memcpy(&sums->pixels, &pixels4, sizeof(pixels4));
  std::memcpy(&sums->black, &black4, sizeof(black4));
  if (peaks != nullptr && pending >= 0) FlushPeaks(peak, peaks + 3 * pending);
  return x0;
}

// ExposeRow's arithmetic on the floats [0, 8n) of a row; returns 8n.
BRDF_AVX2 int64_t ExposeRowAvx2(const float* in, const float* add, int64_t floats, float scale,
                                float strength, float* out) {
  const __m256 scale8 = _mm256_set1_ps(scale), strength8 = _mm256_set1_ps(strength);
  int64_t i = 0;
  for (; i + 8 <= floats; i += 8) {
    const __m256 pixels = _mm256_loadu_ps(in + i);
    __m256 exposed = _mm256_mul_ps(pixels, scale8);
    if (add != nullptr) {
      exposed = _mm256_add_ps(exposed, _mm256_mul_ps(strength8, _mm256_loadu_ps(add + i)));
    }
    _mm256_storeu_ps(out + i, _mm256_blend_ps(exposed, pixels, 0x88));  // alpha kept
  }
  return i;
}
#endif

// ExposeRow on the pixels [x0, width).
void ExposeRowFrom(const float* in, const float* add, int x0, int width, float scale,
                   float strength, float* out) {
  int64_t i = int64_t{x0} * Image::kChannels;
  const int64_t floats = int64_t{width} * Image::kChannels;
#if BRDF_HAS_AVX2_PATHS
  if (Avx2Enabled()) {
    i += ExposeRowAvx2(in + i, add == nullptr ? nullptr : add + i, floats - i, scale, strength,
                       out + i);
  }
#endif
  if (add == nullptr) {
    for (; i < floats; i += Image::kChannels) {
      out[i] = in[i] * scale;
      out[i + 1] = in[i + 1] * scale;
      out[i + 2] = in[i + 2] * scale;
      out[i + 3] = in[i + 3];
    }
    return;
  }
  for (; i < floats; i += Image::kChannels) {
    out[i] = in[i] * scale + strength * add[i];
    out[i + 1] = in[i + 1] * scale + strength * add[i + 1];
    out[i + 2] = in[i + 2] * scale + strength * add[i + 2];
    out[i + 3] = in[i + 3];
  }
}

// Raises each segment's peaks[3 s + c] to the largest channel c (red, green, blue) of its
// pixels among [x0, width) of an RGBA row; a NaN never wins a comparison, so it is skipped.
void RaisePeaks(const float* row, int x0, int width, float* peaks) {
  for (int x = x0; x < width; ++x) {
    float* peak = peaks + 3 * (x / kPeakSegment);
    for (int c = 0; c < 3; ++c) {
      const float v = row[int64_t{x} * Image::kChannels + c];
      peak[c] = v > peak[c] ? v : peak[c];
    }
  }
}

// Folds one row into `sums`, four pixels at a time, the sums in double. The sums are kept in
// a local while the row is read: the float lanes may alias the row, so through the pointer
// they would be stored and reloaded for every four pixels.
// Starts at pixel `x0`, a multiple of 4 (the lane of pixel x is x mod 4).
void AddRow(const float* row, int x0, int width, float delta, LaneSums* sums) {
  LaneSums local = *sums;
  for (; x0 + 4 <= width; x0 += 4) {
    const float* p = row + int64_t{x0} * Image::kChannels;
    float luminance[4], alpha[4];
    for (int k = 0; k < 4; ++k) {
      const float* rgba = p + 4 * k;
      // PixelLuminance's operations in its order, then std::max(0, L) (NaN gives 0).
      const float l = 0.2126f * rgba[0] + 0.7152f * rgba[1] + 0.0722f * rgba[2];
      luminance[k] = l > 0.0f ? l : 0.0f;
      alpha[k] = rgba[3];
    }
    AddFour(luminance, alpha, delta, &local);
  }
  if (x0 < width) {
    float luminance[4] = {}, alpha[4] = {};
    for (int k = 0; x0 + k < width; ++k) {
      const float* rgba = row + int64_t{x0 + k} * Image::kChannels;
      alpha[k] = rgba[3];
      luminance[k] = std::max(0.0f, PixelLuminance(rgba));
    }
    AddFour(luminance, alpha, delta, &local);
  }
  *sums = local;
}

LogSum Join(const LaneSums& lanes) {
  LogSum sum;
  for (int k = 0; k < 4; ++k) {
    sum.log_sum += lanes.log_sum[k];
    sum.lit_log_sum += lanes.lit_log_sum[k];
    sum.max = std::max(sum.max, static_cast<double>(lanes.max[k]));
    sum.pixels += lanes.pixels[k];
    sum.black += lanes.black[k];
  }
  return sum;
}

// The statistics of `height` rows, `fold(y, scratch, delta, lanes)` folding row y into the
// lanes (`scratch` has room for two RGBA rows). A fixed summation order: the exposure, and so
// every output byte, must not depend on the thread count.
template <typename Fold>
SceneLuminance MeasureRows(int width, int height, double delta, const Fold& fold) {
  const int64_t rows_per_chunk = std::max<int64_t>(1, kPixelGrain / std::max(1, width));
  const float delta_f = static_cast<float>(delta);
  const LogSum total = DeterministicReduce(
      int64_t{height}, rows_per_chunk, LogSum{},
      [&](int64_t begin, int64_t end, LogSum sum) {
        // Written before it is read (the row callbacks' contract): not zero-filled.
        const std::unique_ptr<float[]> scratch(new float[2 * int64_t{width} * Image::kChannels]);
        LaneSums lanes;
        for (int64_t y = begin; y < end; ++y) {
          fold(static_cast<int>(y), scratch.get(), delta_f, &lanes);
        }
        const LogSum chunk = Join(lanes);
        sum.log_sum += chunk.log_sum;
        sum.lit_log_sum += chunk.lit_log_sum;
        sum.max = std::max(sum.max, chunk.max);
        sum.pixels += chunk.pixels;
        sum.black += chunk.black;
        return sum;
      },
      [](LogSum a, const LogSum& b) {
        a.log_sum += b.log_sum;
        a.lit_log_sum += b.lit_log_sum;
        a.black += b.black;
        a.max = std::max(a.max, b.max);
        a.pixels += b.pixels;
        return a;
      });
  SceneLuminance scene;
  scene.pixels = total.pixels;
  scene.max = total.max;
  scene.log_average = total.pixels > 0 ? std::exp(total.log_sum / total.pixels) : 0.0;
  scene.black_pixels = total.black;
  const int64_t lit = total.pixels - total.black;
  scene.log_average_lit = lit > 0 ? std::exp(total.lit_log_sum / lit) : 0.0;
  return scene;
}

}  // namespace

SceneLuminance MeasureSceneLuminanceByRow(
    int width, int height, double delta,
    const std::function<const float*(int y, float* scratch)>& row, float* peaks) {
  return MeasureRows(
      width, height, delta, [&](int y, float* scratch, float delta_f, LaneSums* lanes) {
        const float* pixels = row(y, scratch);
        float* const row_peaks =
            peaks == nullptr ? nullptr : peaks + 3 * int64_t{y} * PeakSegments(width);
        if (row_peaks != nullptr) {
          std::fill(row_peaks, row_peaks + 3 * PeakSegments(width),
                    -std::numeric_limits<float>::infinity());
        }
        int x0 = 0;
#if BRDF_HAS_AVX2_PATHS
        if (Avx2Enabled()) {
          x0 = AddRowAvx2<false>(pixels, nullptr, 1.0f, 0.0f, nullptr, width, delta_f, lanes,
                                 row_peaks);
        }
#endif
        if (row_peaks != nullptr) RaisePeaks(pixels, x0, width, row_peaks);
        AddRow(pixels, x0, width, delta_f, lanes);
      });
}

SceneLuminance MeasureExposedLuminanceByRow(
    int width, int height, double delta, float scale, float strength,
    const std::function<ExposedRowSource(int y, float* scratch)>& row) {
  return MeasureRows(
      width, height, delta, [&](int y, float* scratch, float delta_f, LaneSums* lanes) {
        const ExposedRowSource source = row(y, scratch);
        // The exposed pixels the vector path leaves (all of them without it) are made in the
        // scratch row's second half, and copied to the kept planes from there.
        float* exposed = scratch + int64_t{width} * Image::kChannels;
        int x0 = 0;
#if BRDF_HAS_AVX2_PATHS
        if (Avx2Enabled()) {
          x0 = AddRowAvx2<true>(source.in, source.add, scale, strength, source.keep, width, delta_f,
                                lanes, nullptr);
        }
#endif
        ExposeRowFrom(source.in, source.add, x0, width, scale, strength, exposed);
        AddRow(exposed, x0, width, delta_f, lanes);
        if (source.keep != nullptr) {
          for (int x = x0; x < width; ++x) {
            for (int c = 0; c < 3; ++c) {
              source.keep[int64_t{c} * width + x] = exposed[int64_t{x} * Image::kChannels + c];
            }
          }
        }
      });
}

void ExposeRow(const float* in, const float* add, int width, float scale, float strength,
               float* out) {
  ExposeRowFrom(in, add, 0, width, scale, strength, out);
}

SceneLuminance MeasureSceneLuminance(const Image& image, double delta, float* peaks) {
  return MeasureSceneLuminanceByRow(
      image.width, image.height, delta, [&](int y, float*) { return image.pixel(0, y); }, peaks);
}

void ApplyExposure(Image* image, double exposure) {
  const float scale = static_cast<float>(exposure);
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, image->pixel_count()),
                    [&](const tbb::blocked_range<int64_t>& range) {
                      for (int64_t i = range.begin(); i < range.end(); ++i) {
                        float* rgba = image->rgba.data() + i * Image::kChannels;
                        rgba[0] *= scale;
                        rgba[1] *= scale;
                        rgba[2] *= scale;
                      }
                    });
}

double AutoExposure(const SceneLuminance& scene, double key) {
  // A black scene has nothing to expose; leave it as it is.
  return scene.log_average > 0.0 && scene.max > 0.0 ? key / scene.log_average : 1.0;
}

}  // namespace brdf
