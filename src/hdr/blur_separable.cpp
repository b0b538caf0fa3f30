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

Image ConvolveSeparable(const Image& image, const Kernel1D& kernel) {
  constexpr int kC = Image::kChannels;
  const int width = image.width;
  const int height = image.height;
  const int taps = static_cast<int>(kernel.weights.size());
  Image rows_done(width, height);
  tbb::parallel_for(0, height, [&](int y) {
    const float* in = image.pixel(0, y);
    float* out = rows_done.pixel(0, y);
    for (int x = 0; x < width; ++x) {
      float sum[kC] = {0, 0, 0, 0};
      for (int k = 0; k < taps; ++k) {
        const float w = kernel.weights[k];
        if (w == 0.0f) continue;
        const int source = std::clamp(x + kernel.first_offset + k, 0, width - 1);
        for (int c = 0; c < kC; ++c) sum[c] += w * in[source * kC + c];
      }
      for (int c = 0; c < kC; ++c) out[x * kC + c] = sum[c];
    }
  });
  // Columns: each output row is a weighted sum of whole input rows (cache friendly).
  Image result(width, height);
  tbb::parallel_for(0, height, [&](int y) {
    float* out = result.pixel(0, y);
    std::fill(out, out + int64_t{width} * kC, 0.0f);
    for (int k = 0; k < taps; ++k) {
      const float w = kernel.weights[k];
      if (w == 0.0f) continue;
      const int source = std::clamp(y + kernel.first_offset + k, 0, height - 1);
      const float* in = rows_done.pixel(0, source);
      for (int64_t i = 0; i < int64_t{width} * kC; ++i) out[i] += w * in[i];
    }
  });
  return result;
}

}  // namespace brdf
