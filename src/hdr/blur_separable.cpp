#include "hdr/blur_separable.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/simd.h"

#if BRDF_HAS_AVX2_PATHS
#include <immintrin.h>
#endif

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

#if BRDF_HAS_AVX2_PATHS
// ConvolveRow's inside pixels from x on, two at a time (pixel x in the low half of a vector,
// x + 1 in the high half, each with the scalar sums' order); returns the first pixel not
// written.
BRDF_AVX2 int ConvolveInsideAvx2(const float* in, float* out, int x, int width,
                                 const Kernel1D& kernel) {
  const int taps = static_cast<int>(kernel.weights.size());
  const int first = kernel.first_offset, last = first + taps - 1;
  const float* weights = kernel.weights.data();
  for (; x + 1 < width && x + first >= 0 && x + 1 + last < width; x += 2) {
    const float* base = in + int64_t{x + first} * kC;
    __m256 even = _mm256_setzero_ps(), odd = _mm256_setzero_ps();
    int k = 0;
    for (; k + 1 < taps; k += 2) {
      even = _mm256_add_ps(
          even, _mm256_mul_ps(_mm256_set1_ps(weights[k]), _mm256_loadu_ps(base + k * kC)));
      odd = _mm256_add_ps(
          odd, _mm256_mul_ps(_mm256_set1_ps(weights[k + 1]), _mm256_loadu_ps(base + (k + 1) * kC)));
    }
    if (k < taps) {
      even = _mm256_add_ps(
          even, _mm256_mul_ps(_mm256_set1_ps(weights[k]), _mm256_loadu_ps(base + k * kC)));
    }
    _mm256_storeu_ps(out + int64_t{x} * kC, _mm256_add_ps(even, odd));
  }
  return x;
}

// out[i] += w * in[i], eight at a time.
BRDF_AVX2 int64_t AddScaledAvx2(float* out, const float* in, float w, int64_t count) {
  const __m256 w8 = _mm256_set1_ps(w);
  int64_t i = 0;
  for (; i + 8 <= count; i += 8) {
    _mm256_storeu_ps(out + i, _mm256_add_ps(_mm256_loadu_ps(out + i),
                                            _mm256_mul_ps(w8, _mm256_loadu_ps(in + i))));
  }
  return i;
}
#endif

// One row: the clamped form near the ends, plain offsets (two partial sums, so consecutive taps
// do not wait for each other's addition) in between.
void ConvolveRow(const float* in, float* out, int width, const Kernel1D& kernel) {
  const int taps = static_cast<int>(kernel.weights.size());
  const int first = kernel.first_offset, last = first + taps - 1;
  [[maybe_unused]] const bool avx2 = Avx2Enabled();
  for (int x = 0; x < width; ++x) {
#if BRDF_HAS_AVX2_PATHS
    if (avx2 && x + first >= 0 && x + last < width) {
      x = ConvolveInsideAvx2(in, out, x, width, kernel);
      if (x >= width) break;
    }
#endif
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
  Image rows_done(width, height, 0.0f);  // every float written
  tbb::parallel_for(0, height, [&](int y) {
    ConvolveRow(image.pixel(0, y), rows_done.pixel(0, y), width, kernel);
  });
  // Columns, a block of 64 columns at a time: an output row is a weighted sum of input row
  // segments, and a block's window of segments stays in cache as the output row advances
  // (whole rows would stream the image through memory once per tap).
  constexpr int kBlock = 64;
  Image result(width, height, 0.0f);  // zeroed a row at a time below
  [[maybe_unused]] const bool avx2 = Avx2Enabled();
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
        int64_t i = 0;
#if BRDF_HAS_AVX2_PATHS
        if (avx2) i = AddScaledAvx2(out, in, w, span);
#endif
        for (; i < span; ++i) out[i] += w * in[i];
      }
    }
  });
  return result;
}

}  // namespace brdf
