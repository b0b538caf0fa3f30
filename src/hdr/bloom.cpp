#include "hdr/bloom.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "core/errors.h"
#include "core/simd.h"
#include "hdr/blur.h"
#include "hdr/exposure.h"

#if BRDF_HAS_AVX2_PATHS
#include <immintrin.h>
#endif

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

#if BRDF_HAS_AVX2_PATHS
// BrightPixel on the pixels [0, 8n) of a row, eight at a time with its operations in its
// order; returns 8n.
BRDF_AVX2 int64_t BrightRowAvx2(const float* in, int64_t count, float t, float scale, float* out) {
  const __m256 zero = _mm256_setzero_ps(), scale8 = _mm256_set1_ps(scale), t8 = _mm256_set1_ps(t);
  int64_t x = 0;
  for (; x + 8 <= count; x += 8) {
    const float* p = in + x * Image::kChannels;
    // Pixels k and k + 4 in the halves of quad[k], then as planes (r, g, b, alpha).
    __m256 quad[4];
    for (int k = 0; k < 4; ++k) {
      quad[k] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(p + 4 * k)),
                                     _mm_loadu_ps(p + 16 + 4 * k), 1);
    }
    const __m256 t0 = _mm256_unpacklo_ps(quad[0], quad[1]),
                 t1 = _mm256_unpackhi_ps(quad[0], quad[1]);
    const __m256 t2 = _mm256_unpacklo_ps(quad[2], quad[3]),
                 t3 = _mm256_unpackhi_ps(quad[2], quad[3]);
    const __m256 r = _mm256_mul_ps(_mm256_shuffle_ps(t0, t2, 0x44), scale8);
    const __m256 g = _mm256_mul_ps(_mm256_shuffle_ps(t0, t2, 0xee), scale8);
    const __m256 b = _mm256_mul_ps(_mm256_shuffle_ps(t1, t3, 0x44), scale8);
    const __m256 luminance = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(0.2126f), r),
                                                         _mm256_mul_ps(_mm256_set1_ps(0.7152f), g)),
                                           _mm256_mul_ps(_mm256_set1_ps(0.0722f), b));
    const __m256 bright = _mm256_and_ps(_mm256_cmp_ps(luminance, t8, _CMP_GT_OQ),
                                        _mm256_cmp_ps(luminance, zero, _CMP_GT_OQ));
    const __m256 keep = _mm256_div_ps(_mm256_sub_ps(luminance, t8), luminance);
    // std::max(0, x) is x > 0 ? x : 0, as maxps(x, 0) (NaN gives 0).
    const __m256 out_r = _mm256_and_ps(_mm256_max_ps(_mm256_mul_ps(r, keep), zero), bright);
    const __m256 out_g = _mm256_and_ps(_mm256_max_ps(_mm256_mul_ps(g, keep), zero), bright);
    const __m256 out_b = _mm256_and_ps(_mm256_max_ps(_mm256_mul_ps(b, keep), zero), bright);
    // Back to pixels, alpha 0.
    const __m256 u0 = _mm256_unpacklo_ps(out_r, out_g), u1 = _mm256_unpackhi_ps(out_r, out_g);
    const __m256 u2 = _mm256_unpacklo_ps(out_b, zero), u3 = _mm256_unpackhi_ps(out_b, zero);
    const __m256 p04 = _mm256_shuffle_ps(u0, u2, 0x44), p15 = _mm256_shuffle_ps(u0, u2, 0xee);
    const __m256 p26 = _mm256_shuffle_ps(u1, u3, 0x44), p37 = _mm256_shuffle_ps(u1, u3, 0xee);
    float* o = out + x * Image::kChannels;
    _mm256_storeu_ps(o, _mm256_permute2f128_ps(p04, p15, 0x20));
    _mm256_storeu_ps(o + 8, _mm256_permute2f128_ps(p26, p37, 0x20));
    _mm256_storeu_ps(o + 16, _mm256_permute2f128_ps(p04, p15, 0x31));
    _mm256_storeu_ps(o + 24, _mm256_permute2f128_ps(p26, p37, 0x31));
  }
  return x;
}
#endif

// `count` pixels of the bright pass.
void BrightRow(const float* in, int64_t count, float t, float scale, float* out) {
  int64_t x = 0;
#if BRDF_HAS_AVX2_PATHS
  if (Avx2Enabled()) x = BrightRowAvx2(in, count, t, scale, out);
#endif
  for (; x < count; ++x) {
    BrightPixel(in + x * Image::kChannels, t, scale, out + x * Image::kChannels);
  }
}

// Whether BrightPixel gives black for every pixel whose red, green and blue are at most
// peak[0], peak[1], peak[2]: with scale > 0, scaling, the weighted sum and their rounding
// are monotone, so each pixel's exposed luminance is at most the peaks' (or NaN, also black).
// A NaN bound proves nothing.
bool ProvenDark(const float* peak, float t, float scale) {
  if (!(scale > 0.0f)) return false;
  const float exposed[3] = {peak[0] * scale, peak[1] * scale, peak[2] * scale};
  return PixelLuminance(exposed) <= t;
}

// Destination rows per task of the fused bright pass and step down; each task bright-passes
// the 2 * kRowsPerTask + 2 source rows it needs (the two shared with a neighbour twice).
constexpr int kRowsPerTask = 16;
// Destination row y reads source rows 2y - 1 .. 2y + 2 (clamped), and row y + 1 two of them
// again: a task keeps its last four bright rows, source row sy in slot sy mod 4, so they stay
// in cache.
constexpr int kBrightSlots = 4;

}  // namespace

Image BrightPass(const Image& image, double threshold, double exposure) {
  Image bright(image.width, image.height, 0.0f);
  const float t = static_cast<float>(threshold);
  const float scale = static_cast<float>(exposure);
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, image.pixel_count()),
                    [&](const tbb::blocked_range<int64_t>& range) {
                      BrightRow(image.rgba.data() + range.begin() * Image::kChannels, range.size(),
                                t, scale, bright.rgba.data() + range.begin() * Image::kChannels);
                    });
  return bright;
}

Image BrightPassDown(const Image& image, double threshold, double exposure, const float* peaks) {
  const float t = static_cast<float>(threshold);
  const float scale = static_cast<float>(exposure);
  const int width = image.width, height = image.height;
  Image result((width + 1) / 2, (height + 1) / 2, 0.0f);  // every float written
  const int tasks = (result.height + kRowsPerTask - 1) / kRowsPerTask;
  const int64_t row_floats = int64_t{width} * Image::kChannels;
  // Source segment s holds the pixels [64 s, 64 s + 64) of a row (exposure.h), destination
  // segment s the pixels [32 s, 32 s + 32), which read the source columns 64 s - 1 .. 64 s + 64:
  // segments s - 1, s and s + 1 of four rows.
  const int segments = PeakSegments(width);
  constexpr int kHalfSegment = kPeakSegment / 2;
  tbb::parallel_for(0, tasks, [&](int task) {
    const int y0 = task * kRowsPerTask, y1 = std::min(result.height, y0 + kRowsPerTask);
    // Every float is written before it is read: no zero-filling.
    const std::unique_ptr<float[]> bright(new float[kBrightSlots * row_floats]);
    const auto slot = [&](int sy) { return bright.get() + (sy % kBrightSlots) * row_floats; };
    // Whether segment s of the row in slot k is proven dark: dark[k * segments + s]; and
    // whether that segment of the slot holds zeros already (from an earlier dark row).
    std::vector<char> dark(int64_t{kBrightSlots} * segments);
    std::vector<char> zeroed(int64_t{kBrightSlots} * segments);
    int next = std::max(0, 2 * y0 - 1);  // the first source row not yet bright-passed
    for (int y = y0; y < y1; ++y) {
      for (const int last = std::min(height - 1, 2 * y + 2); next <= last; ++next) {
        char* row_dark = dark.data() + (next % kBrightSlots) * segments;
        char* row_zeroed = zeroed.data() + (next % kBrightSlots) * segments;
        for (int s = 0; s < segments; ++s) {
          const int x0 = s * kPeakSegment, x1 = std::min(width, x0 + kPeakSegment);
          float* out = slot(next) + int64_t{x0} * Image::kChannels;
          row_dark[s] = peaks != nullptr && ProvenDark(PeakAt(peaks, width, next, s), t, scale);
          if (!row_dark[s]) {
            BrightRow(image.pixel(x0, next), x1 - x0, t, scale, out);
            row_zeroed[s] = false;
          } else if (!row_zeroed[s]) {  // what the bright pass gives there: zeros
            std::fill(out, out + int64_t{x1 - x0} * Image::kChannels, 0.0f);
            row_zeroed[s] = true;
          }
        }
      }
      const float* rows[4];
      const char* rows_dark[4];
      for (int k = 0; k < 4; ++k) {
        const int sy = std::clamp(2 * y - 1 + k, 0, height - 1);
        rows[k] = slot(sy);
        rows_dark[k] = dark.data() + (sy % kBrightSlots) * segments;
      }
      const auto zero = [&](int s) {  // destination segment s: the taps' sums of zeros
        for (int k = 0; k < 4; ++k) {
          for (int n = std::max(0, s - 1); n <= std::min(segments - 1, s + 1); ++n) {
            if (!rows_dark[k][n]) return false;
          }
        }
        return true;
      };
      float* out = result.pixel(0, y);
      for (int s = 0; s < segments;) {
        const bool zeros = zero(s);
        int end = s + 1;  // a run of segments alike, made in one call
        while (end < segments && zero(end) == zeros) ++end;
        const int x0 = s * kHalfSegment, x1 = std::min(result.width, end * kHalfSegment);
        if (zeros) {
          std::fill(out + int64_t{x0} * Image::kChannels, out + int64_t{x1} * Image::kChannels,
                    0.0f);
        } else {
          DualFilterDownRow(rows, width, height, y, x0, x1, out);
        }
        s = end;
      }
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
