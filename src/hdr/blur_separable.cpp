#include "hdr/blur_separable.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace brdf {

void Kernel1D::AddBilinearTap(double position, double weight) {
  const int lower = static_cast<int>(std::floor(position));
  const double fraction = position - lower;
  if (weights.empty()) first_offset = lower;
  const int last = first_offset + static_cast<int>(weights.size()) - 1;
  const int new_first = std::min(first_offset, lower);
  const int new_last = std::max(last, lower + 1);
  std::vector<float> grown(new_last - new_first + 1, 0.0f);
  for (size_t k = 0; k < weights.size(); ++k) grown[first_offset - new_first + k] = weights[k];
  grown[lower - new_first] += static_cast<float>(weight * (1.0 - fraction));
  grown[lower + 1 - new_first] += static_cast<float>(weight * fraction);
  first_offset = new_first;
  weights = std::move(grown);
}

namespace {

constexpr int kC = Image::kChannels;

// One row: the clamped form near the ends, plain offsets (two partial sums, so consecutive taps
// do not wait for each other's addition) in between.
void ConvolveRow(const float* in, float* out, int width, const Kernel1D& kernel) {
  const int taps = static_cast<int>(kernel.weights.size());
  const int first = kernel.first_offset, last = first + taps - 1;
  for (int x = 0; x < width; ++x) {
    float even[kC] = {0, 0, 0, 0}, odd[kC] = {0, 0, 0, 0};
    if (x + first >= 0 && x + last < width) {
      const float* base = in + int64_t{x + first} * kC;
      int k = 0;
      for (; k + 1 < taps; k += 2) {
        const float wa = kernel.weights[k], wb = kernel.weights[k + 1];
        for (int c = 0; c < kC; ++c) {
          even[c] += wa * base[k * kC + c];
          odd[c] += wb * base[(k + 1) * kC + c];
        }
      }
      if (k < taps) {
        for (int c = 0; c < kC; ++c) even[c] += kernel.weights[k] * base[k * kC + c];
      }
    } else {
      for (int k = 0; k < taps; ++k) {
        const int source = std::clamp(x + first + k, 0, width - 1);
        for (int c = 0; c < kC; ++c) even[c] += kernel.weights[k] * in[source * kC + c];
      }
    }
    for (int c = 0; c < kC; ++c) out[x * kC + c] = even[c] + odd[c];
  }
}

}  // namespace

Image ConvolveSeparable(const Image& image, const Kernel1D& kernel) {
  const int width = image.width;
  const int height = image.height;
  const int taps = static_cast<int>(kernel.weights.size());
  Image rows_done(width, height);
  tbb::parallel_for(0, height, [&](int y) {
    ConvolveRow(image.pixel(0, y), rows_done.pixel(0, y), width, kernel);
  });
  // Columns, a block of 64 columns at a time: an output row is a weighted sum of input row
  // segments, and a block's window of segments stays in cache as the output row advances
  // (whole rows would stream the image through memory once per tap).
  constexpr int kBlock = 64;
  Image result(width, height);
  tbb::parallel_for(0, (width + kBlock - 1) / kBlock, [&](int block) {
    const int x0 = block * kBlock, x1 = std::min(width, x0 + kBlock);
    const int64_t span = int64_t{x1 - x0} * kC;
    for (int y = 0; y < height; ++y) {
      float* out = result.pixel(x0, y);
      std::fill(out, out + span, 0.0f);
      for (int k = 0; k < taps; ++k) {
        const float w = kernel.weights[k];
        if (w == 0.0f) continue;
        const int source = std::clamp(y + kernel.first_offset + k, 0, height - 1);
        const float* in = rows_done.pixel(x0, source);
        for (int64_t i = 0; i < span; ++i) out[i] += w * in[i];
      }
    }
  });
  return result;
}

}  // namespace brdf
