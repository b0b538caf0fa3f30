#include "hdr/bloom.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "core/errors.h"

namespace brdf {

Image BrightPass(const Image& image, double threshold) {
  Image bright(image.width, image.height, 0.0f);
  const float t = static_cast<float>(threshold);
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, image.pixel_count()),
                    [&](const tbb::blocked_range<int64_t>& range) {
                      for (int64_t i = range.begin(); i < range.end(); ++i) {
                        const float* in = image.rgba.data() + i * Image::kChannels;
                        float* out = bright.rgba.data() + i * Image::kChannels;
                        const float luminance = PixelLuminance(in);
                        if (!(luminance > t) || !(luminance > 0.0f)) continue;
                        const float keep = (luminance - t) / luminance;
                        for (int c = 0; c < 3; ++c) out[c] = std::max(0.0f, in[c] * keep);
                      }
                    });
  return bright;
}

void AddBloom(Image* image, const Image& bloom, double strength) {
  if (bloom.width != image->width || bloom.height != image->height) {
    throw ComputeError("bloom: the blurred bright pass does not match the image size");
  }
  const float s = static_cast<float>(strength);
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, image->pixel_count()),
                    [&](const tbb::blocked_range<int64_t>& range) {
                      for (int64_t i = range.begin(); i < range.end(); ++i) {
                        float* out = image->rgba.data() + i * Image::kChannels;
                        const float* add = bloom.rgba.data() + i * Image::kChannels;
                        for (int c = 0; c < 3; ++c) out[c] += s * add[c];
                      }
                    });
}

}  // namespace brdf
