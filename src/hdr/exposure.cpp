#include "hdr/exposure.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/deterministic_reduce.h"
#include "core/errors.h"

namespace brdf {
namespace {

// Pixels per chunk of the log-average sum.
constexpr int64_t kPixelGrain = 16384;

struct LogSum {
  double log_sum = 0.0;
  double lit_log_sum = 0.0;
  double max = 0.0;
  int64_t pixels = 0;
  int64_t black = 0;
};

}  // namespace

SceneLuminance MeasureSceneLuminance(const Image& image, double delta) {
  // A fixed summation order: the exposure, and so every output byte, must not depend on the
  // thread count.
  const LogSum total = DeterministicReduce(
      image.pixel_count(), kPixelGrain, LogSum{},
      [&](int64_t begin, int64_t end, LogSum sum) {
        for (int64_t i = begin; i < end; ++i) {
          const float* rgba = image.rgba.data() + i * Image::kChannels;
          if (!(rgba[3] > 0.0f)) continue;
          const float luminance = std::max(0.0f, PixelLuminance(rgba));
          const double log_luminance = std::log(static_cast<float>(delta) + luminance);
          sum.log_sum += log_luminance;
          if (luminance > 0.0f) {
            sum.lit_log_sum += log_luminance;
          } else {
            ++sum.black;
          }
          sum.max = std::max(sum.max, static_cast<double>(luminance));
          ++sum.pixels;
        }
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
