#include "hdr/bloom.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

#include "core/errors.h"
#include "hdr/blur.h"

namespace brdf {

namespace {

// One pixel of the bright pass of the exposed image; alpha 0.
inline void BrightPixel(const float* in, float t, float scale, float* out) {
  const float exposed[3] = {in[0] * scale, in[1] * scale, in[2] * scale};
  const float luminance = PixelLuminance(exposed);
  out[0] = out[1] = out[2] = out[3] = 0.0f;
  if (!(luminance > t) || !(luminance > 0.0f)) return;
  const float keep = (luminance - t) / luminance;
  for (int c = 0; c < 3; ++c) out[c] = std::max(0.0f, exposed[c] * keep);
}

// Destination rows per task of the fused bright pass and step down; each task bright-passes
// the 2 * kRowsPerTask + 2 source rows it needs (the two shared with a neighbour twice).
constexpr int kRowsPerTask = 16;

}  // namespace

Image BrightPass(const Image& image, double threshold, double exposure) {
  Image bright(image.width, image.height, 0.0f);
  const float t = static_cast<float>(threshold);
  const float scale = static_cast<float>(exposure);
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, image.pixel_count()),
                    [&](const tbb::blocked_range<int64_t>& range) {
                      for (int64_t i = range.begin(); i < range.end(); ++i) {
                        BrightPixel(image.rgba.data() + i * Image::kChannels, t, scale,
                                    bright.rgba.data() + i * Image::kChannels);
                      }
                    });
  return bright;
}

Image BrightPassDown(const Image& image, double threshold, double exposure) {
  const float t = static_cast<float>(threshold);
  const float scale = static_cast<float>(exposure);
  const int width = image.width, height = image.height;
  Image result((width + 1) / 2, (height + 1) / 2);
  const int tasks = (result.height + kRowsPerTask - 1) / kRowsPerTask;
  tbb::parallel_for(0, tasks, [&](int task) {
    const int y0 = task * kRowsPerTask, y1 = std::min(result.height, y0 + kRowsPerTask);
    // Source rows 2 y0 - 1 .. 2 y1, clamped to the image.
    const int first = std::max(0, 2 * y0 - 1), last = std::min(height - 1, 2 * y1);
    std::vector<float> bright(int64_t{last - first + 1} * width * Image::kChannels);
    for (int sy = first; sy <= last; ++sy) {
      const float* in = image.pixel(0, sy);
      float* out = bright.data() + int64_t{sy - first} * width * Image::kChannels;
      for (int x = 0; x < width; ++x) {
        BrightPixel(in + int64_t{x} * Image::kChannels, t, scale,
                    out + int64_t{x} * Image::kChannels);
      }
    }
    for (int y = y0; y < y1; ++y) {
      const float* rows[4];
      for (int k = 0; k < 4; ++k) {
        const int sy = std::clamp(2 * y - 1 + k, 0, height - 1);
        rows[k] = bright.data() + int64_t{sy - first} * width * Image::kChannels;
      }
      DualFilterDownRow(rows, width, height, y, result.pixel(0, y));
    }
  });
  return result;
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
