#include "hdr/exposure.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "core/deterministic_reduce.h"
#include "core/errors.h"

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

using Float4 = float __attribute__((vector_size(16)));
using Int4 = int32_t __attribute__((vector_size(16)));

// Natural logarithm of four positive, finite, normal floats, within about 2 float ulps; the
// library's scalar log per pixel was most of the statistics pass. x = 2^e m with m in
// [sqrt(1/2), sqrt(2)), and log m = 2 atanh(s) = 2 (s + s^3/3 + s^5/5 + ...) with
// s = (m - 1) / (m + 1), |s| <= 0.172: the series to s^9 leaves a relative error below 1e-8.
Float4 Log4(Float4 x) {
  Int4 bits;
  std::memcpy(&bits, &x, sizeof(bits));
  Int4 exponent = ((bits >> 23) & 0xff) - 127;
  const Int4 mantissa_bits = (bits & 0x007fffff) | 0x3f800000;
  Float4 m;
  std::memcpy(&m, &mantissa_bits, sizeof(m));
  const Int4 above = m > 1.41421356f;  // all ones where true
  m = above ? m * 0.5f : m;
  exponent -= above;
  const Float4 s = (m - 1.0f) / (m + 1.0f);
  const Float4 s2 = s * s;
  const Float4 series =
      1.0f + s2 * (1.0f / 3 + s2 * (1.0f / 5 + s2 * (1.0f / 7 + s2 * (1.0f / 9))));
  const Float4 e = __builtin_convertvector(exponent, Float4);
  return e * 0.693147181f + 2.0f * s * series;
}

using Double4 = double __attribute__((vector_size(32)));

// Sums of one chunk in four lanes (pixel x goes to lane x mod 4), joined in a fixed order.
struct LaneSums {
  Double4 log_sum{0, 0, 0, 0};
  Double4 lit_log_sum{0, 0, 0, 0};
  Float4 max{0, 0, 0, 0};
  Int4 pixels{0, 0, 0, 0};
  Int4 black{0, 0, 0, 0};
};

// Folds four pixels (alpha and luminance clamped at 0; padding lanes have alpha 0) into `sums`.
inline void AddFour(const Float4& luminance, const Float4& alpha, float delta, LaneSums* sums) {
  constexpr float kLargest = std::numeric_limits<float>::max();
  constexpr float kSmallest = std::numeric_limits<float>::min();  // the least normal float
  const Float4 argument = delta + luminance;
  Float4 logs;
  const Int4 normal = (argument <= kLargest) & (argument >= kSmallest);
  if (normal[0] & normal[1] & normal[2] & normal[3]) {
    logs = Log4(argument);
  } else {  // an infinite pixel or a subnormal delta: the library's log
    for (int k = 0; k < 4; ++k) logs[k] = std::log(argument[k]);
  }
  const Int4 counted = alpha > 0.0f;  // all ones where true
  const Int4 lit = counted & (luminance > 0.0f);
  const Float4 zero{0, 0, 0, 0};
  sums->log_sum += __builtin_convertvector(counted ? logs : zero, Double4);
  sums->lit_log_sum += __builtin_convertvector(lit ? logs : zero, Double4);
  sums->max = (counted & (luminance > sums->max)) ? luminance : sums->max;
  sums->pixels -= counted;
  sums->black -= counted & ~lit;
}

// Folds one row into `sums`, four pixels at a time, the sums in double. The sums are kept in
// a local while the row is read: a vector of floats may alias the row, so through the pointer
// they would be stored and reloaded for every four pixels.
void AddRow(const float* row, int width, float delta, LaneSums* sums) {
  LaneSums local = *sums;
  const Float4 zero{0, 0, 0, 0};
  int x0 = 0;
  for (; x0 + 4 <= width; x0 += 4) {
    const float* p = row + int64_t{x0} * Image::kChannels;
    const Float4 r{p[0], p[4], p[8], p[12]}, g{p[1], p[5], p[9], p[13]},
        b{p[2], p[6], p[10], p[14]}, alpha{p[3], p[7], p[11], p[15]};
    // PixelLuminance's operations in its order, then std::max(0, L) (NaN gives 0).
    const Float4 luminance = 0.2126f * r + 0.7152f * g + 0.0722f * b;
    AddFour(luminance > 0.0f ? luminance : zero, alpha, delta, &local);
  }
  if (x0 < width) {
    Float4 luminance = zero, alpha = zero;
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

}  // namespace

SceneLuminance MeasureSceneLuminanceByRow(
    int width, int height, double delta,
    const std::function<const float*(int y, float* scratch)>& row) {
  // A fixed summation order: the exposure, and so every output byte, must not depend on the
  // thread count.
  const int64_t rows_per_chunk = std::max<int64_t>(1, kPixelGrain / std::max(1, width));
  const float delta_f = static_cast<float>(delta);
  const LogSum total = DeterministicReduce(
      int64_t{height}, rows_per_chunk, LogSum{},
      [&](int64_t begin, int64_t end, LogSum sum) {
        std::vector<float> scratch(2 * int64_t{width} * Image::kChannels);
        LaneSums lanes;
        for (int64_t y = begin; y < end; ++y) {
          AddRow(row(static_cast<int>(y), scratch.data()), width, delta_f, &lanes);
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

SceneLuminance MeasureSceneLuminance(const Image& image, double delta) {
  return MeasureSceneLuminanceByRow(image.width, image.height, delta,
                                    [&](int y, float*) { return image.pixel(0, y); });
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
