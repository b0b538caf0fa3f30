// Dual filtering (Bjørge 2015); the taps and their variance are derived in blur.h.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/errors.h"
#include "core/simd.h"
#include "hdr/blur.h"

#if BRDF_HAS_AVX2_PATHS
#include <immintrin.h>
#endif

namespace brdf {
namespace {

constexpr int kC = Image::kChannels;

// Weights on a 4x4 (down) or 5x5 (up) neighbourhood of source pixels; stencil[row][column]
// with row and column offsets starting at `first`.
template <int N>
struct Stencil {
  int first = 0;
  std::array<std::array<float, N>, N> weight{};

  // A bilinear fetch at the continuous source offset (x, y), pixel centres at integers.
  void AddBilinearTap(double x, double y, double w) {
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    weight[y0 - first][x0 - first] += static_cast<float>(w * (1 - fx) * (1 - fy));
    weight[y0 - first][x0 + 1 - first] += static_cast<float>(w * fx * (1 - fy));
    weight[y0 + 1 - first][x0 - first] += static_cast<float>(w * (1 - fx) * fy);
    weight[y0 + 1 - first][x0 + 1 - first] += static_cast<float>(w * fx * fy);
  }
};

// Destination pixel j samples around source coordinate 2j + 1/2 (the corner shared by its
// four source pixels); offsets relative to 2j.
Stencil<4> DownStencil() {
  Stencil<4> s;
  s.first = -1;
  s.AddBilinearTap(0.5, 0.5, 4.0 / 8.0);
  for (double dy : {-1.0, 1.0}) {
    for (double dx : {-1.0, 1.0}) s.AddBilinearTap(0.5 + dx, 0.5 + dy, 1.0 / 8.0);
  }
  return s;
}

// Destination pixel i sits at source coordinate i/2 - 1/4: m - 1/4 for i = 2m, m + 1/4 for
// i = 2m + 1. Offsets relative to m; `odd_x`, `odd_y` select the phase.
Stencil<5> UpStencil(bool odd_x, bool odd_y) {
  Stencil<5> s;
  s.first = -2;
  const double cx = odd_x ? 0.25 : -0.25, cy = odd_y ? 0.25 : -0.25;
  for (double d : {-1.0, 1.0}) {
    s.AddBilinearTap(cx + d, cy, 1.0 / 12.0);
    s.AddBilinearTap(cx, cy + d, 1.0 / 12.0);
  }
  for (double dy : {-0.5, 0.5}) {
    for (double dx : {-0.5, 0.5}) s.AddBilinearTap(cx + dx, cy + dy, 2.0 / 12.0);
  }
  return s;
}

// One RGBA pixel's sum: each channel does the scalar arithmetic in a four-lane loop the
// compiler vectorizes, so the sums are the same bits as channel-by-channel code.
struct Pixel {
  float channel[kC] = {};
  void AddScaled(float weight, const float* p) {
    for (int c = 0; c < kC; ++c) channel[c] += weight * p[c];
  }
  Pixel operator+(const Pixel& other) const {
    Pixel sum;
    for (int c = 0; c < kC; ++c) sum.channel[c] = channel[c] + other.channel[c];
    return sum;
  }
  void Store(float* p) const { std::memcpy(p, channel, sizeof(channel)); }
};

// The non-zero taps of a stencil as (row offset, column offset, weight).
struct Tap {
  int dy, dx;
  float weight;
};
template <int N>
std::vector<Tap> Taps(const Stencil<N>& s) {
  std::vector<Tap> taps;
  for (int row = 0; row < N; ++row) {
    for (int column = 0; column < N; ++column) {
      if (s.weight[row][column] != 0.0f) {
        taps.push_back({s.first + row, s.first + column, s.weight[row][column]});
      }
    }
  }
  return taps;
}

// One destination pixel: the taps' weighted sum of the source pixels at column base_x + dx of
// rows[dy - first] (rows already clamped to the image). Inside the image two partial sums are
// taken in turn, so that consecutive taps do not wait for each other's addition; near an edge
// the columns repeat the border pixel and one sum is taken in tap order.
inline void ApplyTaps(const float* const* rows, const std::vector<Tap>& taps, int first, int base_x,
                      int width, bool inside, float* out) {
  if (inside) {
    Pixel even, odd;
    const size_t count = taps.size();
    size_t k = 0;
    for (; k + 1 < count; k += 2) {
      const Tap& a = taps[k];
      const Tap& b = taps[k + 1];
      even.AddScaled(a.weight, rows[a.dy - first] + int64_t{base_x + a.dx} * kC);
      odd.AddScaled(b.weight, rows[b.dy - first] + int64_t{base_x + b.dx} * kC);
    }
    if (k < count) {
      const Tap& a = taps[k];
      even.AddScaled(a.weight, rows[a.dy - first] + int64_t{base_x + a.dx} * kC);
    }
    (even + odd).Store(out);
    return;
  }
  Pixel sum;
  for (const Tap& tap : taps) {
    const int x = std::clamp(base_x + tap.dx, 0, width - 1);
    sum.AddScaled(tap.weight, rows[tap.dy - first] + int64_t{x} * kC);
  }
  sum.Store(out);
}

// The taps of a stencil resolved against the rows of one destination row, for the pixels whose
// taps all lie inside the image: tap k reads row_[k] at float offset offset_[k] + base. Sum()
// adds them in ApplyTaps' order and association (two partial sums in turn), so the bits are
// the same; N, the number of taps, is fixed so that the loop unrolls.
template <int N>
class ResolvedTaps {
 public:
  ResolvedTaps(const float* const* rows, const std::vector<Tap>& taps, int first) {
    if (taps.size() != N) throw ComputeError("dual filter: unexpected number of stencil taps");
    for (int k = 0; k < N; ++k) {
      row_[k] = rows[taps[k].dy - first];
      offset_[k] = int64_t{taps[k].dx} * kC;
      weight_[k] = taps[k].weight;
    }
  }
  Pixel Sum(int64_t base) const {
    Pixel even, odd;
    int k = 0;
    for (; k + 1 < N; k += 2) {
      even.AddScaled(weight_[k], row_[k] + (offset_[k] + base));
      odd.AddScaled(weight_[k + 1], row_[k + 1] + (offset_[k + 1] + base));
    }
    if (k < N) even.AddScaled(weight_[k], row_[k] + (offset_[k] + base));
    return even + odd;
  }

#if BRDF_HAS_AVX2_PATHS
  // Sum(base) and Sum(base + one pixel) in the two halves of one vector: each half does
  // Sum's arithmetic, so the bits are the same.
  BRDF_AVX2 __m256 SumTwo(int64_t base) const {
    __m256 even = _mm256_setzero_ps(), odd = _mm256_setzero_ps();
    int k = 0;
    for (; k + 1 < N; k += 2) {
      even = _mm256_add_ps(even, _mm256_mul_ps(_mm256_set1_ps(weight_[k]),
                                               _mm256_loadu_ps(row_[k] + (offset_[k] + base))));
      odd =
          _mm256_add_ps(odd, _mm256_mul_ps(_mm256_set1_ps(weight_[k + 1]),
                                           _mm256_loadu_ps(row_[k + 1] + (offset_[k + 1] + base))));
    }
    if (k < N) {
      even = _mm256_add_ps(even, _mm256_mul_ps(_mm256_set1_ps(weight_[k]),
                                               _mm256_loadu_ps(row_[k] + (offset_[k] + base))));
    }
    return _mm256_add_ps(even, odd);
  }
  // SumTwo at the M bases base + 2 j pixels, j < M, each with SumTwo's arithmetic (the same
  // bits): one broadcast of each weight and one look-up of each tap's row serve M vectors,
  // which a loop of SumTwo calls spent as many loads on as on the pixels.
  template <int M>
  BRDF_AVX2 void SumTwoMany(int64_t base, __m256 sums[M]) const {
    __m256 even[M], odd[M];
    for (int j = 0; j < M; ++j) even[j] = odd[j] = _mm256_setzero_ps();
    int k = 0;
    for (; k + 1 < N; k += 2) {
      const __m256 weight_even = _mm256_set1_ps(weight_[k]);
      const __m256 weight_odd = _mm256_set1_ps(weight_[k + 1]);
      const float* const even_row = row_[k] + (offset_[k] + base);
      const float* const odd_row = row_[k + 1] + (offset_[k + 1] + base);
      for (int j = 0; j < M; ++j) {
        even[j] = _mm256_add_ps(even[j],
                                _mm256_mul_ps(weight_even, _mm256_loadu_ps(even_row + 2 * j * kC)));
        odd[j] =
            _mm256_add_ps(odd[j], _mm256_mul_ps(weight_odd, _mm256_loadu_ps(odd_row + 2 * j * kC)));
      }
    }
    if (k < N) {
      const __m256 weight = _mm256_set1_ps(weight_[k]);
      const float* const row = row_[k] + (offset_[k] + base);
      for (int j = 0; j < M; ++j) {
        even[j] = _mm256_add_ps(even[j], _mm256_mul_ps(weight, _mm256_loadu_ps(row + 2 * j * kC)));
      }
    }
    for (int j = 0; j < M; ++j) sums[j] = _mm256_add_ps(even[j], odd[j]);
  }
  // Whether each pair of taps (2i, 2i + 1) reads neighbouring pixels of one row, the second
  // to the right: then SumPaired() is Sum() with one load per pair.
  bool Paired() const {
    if (N % 2 != 0) return false;
    for (int k = 0; k < N; k += 2) {
      if (row_[k] != row_[k + 1] || offset_[k + 1] != offset_[k] + kC) return false;
    }
    return true;
  }
  // Sum(base) when Paired(): the low half of a vector gathers the even taps' sum, the high
  // half the odd taps', in Sum's order.
  BRDF_AVX2 __m128 SumPaired(int64_t base) const {
    __m256 sum = _mm256_setzero_ps();
    for (int k = 0; k < N; k += 2) {
      const __m256 weights = _mm256_setr_m128(_mm_set1_ps(weight_[k]), _mm_set1_ps(weight_[k + 1]));
      sum = _mm256_add_ps(sum,
                          _mm256_mul_ps(weights, _mm256_loadu_ps(row_[k] + (offset_[k] + base))));
    }
    return _mm_add_ps(_mm256_castps256_ps128(sum), _mm256_extractf128_ps(sum, 1));
  }
#endif

 private:
  std::array<const float*, N> row_;
  std::array<int64_t, N> offset_;
  std::array<float, N> weight_;
};

// Non-zero taps of the stencils (blur.h): the step down's 4x4 are all non-zero, each phase of
// the step up has 13 of its 5x5.
constexpr int kDownTaps = 16;
constexpr int kUpTaps = 13;

#if BRDF_HAS_AVX2_PATHS
// The inside pixels [x, end) of a step down with paired taps; returns `end`.
BRDF_AVX2 int DownInsideAvx2(const ResolvedTaps<kDownTaps>& taps, int x, int end, float* out) {
  for (; x < end; ++x) {
    _mm_storeu_ps(out + int64_t{x} * kC, taps.SumPaired(int64_t{2 * x} * kC));
  }
  return x;
}

// The inside pixels of a doubling step from the even pixel x, four at a time (pixels x and
// x + 2 of the even phase in one vector, x + 1 and x + 3 of the odd one); returns the first
// pixel not written.
BRDF_AVX2 int UpInsideAvx2(const ResolvedTaps<kUpTaps>& even, const ResolvedTaps<kUpTaps>& odd,
                           int x, int end, float* out) {
  constexpr int kVectors = 4;  // sixteen pixels a step, then four
  for (; x + 4 * kVectors - 1 < end; x += 4 * kVectors) {
    const int64_t base = int64_t{x / 2} * kC;
    __m256 even_pairs[kVectors], odd_pairs[kVectors];
    even.SumTwoMany<kVectors>(base, even_pairs);
    odd.SumTwoMany<kVectors>(base, odd_pairs);
    for (int j = 0; j < kVectors; ++j) {
      float* target = out + int64_t{x + 4 * j} * kC;
      _mm256_storeu_ps(target, _mm256_permute2f128_ps(even_pairs[j], odd_pairs[j], 0x20));
      _mm256_storeu_ps(target + 2 * kC, _mm256_permute2f128_ps(even_pairs[j], odd_pairs[j], 0x31));
    }
  }
  for (; x + 3 < end; x += 4) {
    const int64_t base = int64_t{x / 2} * kC;
    const __m256 even_pair = even.SumTwo(base), odd_pair = odd.SumTwo(base);
    float* target = out + int64_t{x} * kC;
    _mm256_storeu_ps(target, _mm256_permute2f128_ps(even_pair, odd_pair, 0x20));
    _mm256_storeu_ps(target + 2 * kC, _mm256_permute2f128_ps(even_pair, odd_pair, 0x31));
  }
  return x;
}
#endif

const std::vector<Tap>& DownTaps() {
  static const std::vector<Tap> taps = Taps(DownStencil());
  return taps;
}

const std::array<std::vector<Tap>, 4>& UpTaps() {
  static const std::array<std::vector<Tap>, 4> taps = {
      Taps(UpStencil(false, false)), Taps(UpStencil(true, false)), Taps(UpStencil(false, true)),
      Taps(UpStencil(true, true))};
  return taps;
}

Image Down(const Image& source) {
  Image result((source.width + 1) / 2, (source.height + 1) / 2, 0.0f);  // every float written
  tbb::parallel_for(0, result.height, [&](int y) {
    const float* rows[4];
    for (int k = 0; k < 4; ++k) {
      rows[k] = source.pixel(0, std::clamp(2 * y - 1 + k, 0, source.height - 1));
    }
    DualFilterDownRow(rows, source.width, source.height, y, result.pixel(0, y));
  });
  return result;
}

// The doubling step from `source` into `target`, whose size it keeps and every float of which
// it writes (its old content is not read).
void UpInto(const Image& source, Image* target) {
  tbb::parallel_for(0, target->height,
                    [&](int y) { DualFilterUpRow(source, target->width, y, target->pixel(0, y)); });
}

Image Up(const Image& source, int width, int height) {
  Image result(width, height, 0.0f);
  UpInto(source, &result);
  return result;
}

}  // namespace

void DualFilterDownRow(const float* const rows[4], int source_width, int source_height, int y,
                       float* out) {
  DualFilterDownRow(rows, source_width, source_height, y, 0, (source_width + 1) / 2, out);
}

void DualFilterDownRow(const float* const rows[4], int source_width, int source_height, int y,
                       int begin, int end, float* out) {
  const std::vector<Tap>& taps = DownTaps();
  const int width = (source_width + 1) / 2;
  // Destination pixels whose taps all lie inside: 2x - 1 >= 0 and 2x + 2 < source_width.
  const bool row_inside = 2 * y - 1 >= 0 && 2 * y + 2 < source_height;
  const int inside_begin = row_inside ? std::min(width, 1) : width;
  const int inside_end = row_inside ? std::max(inside_begin, (source_width - 1) / 2) : width;
  for (int x = begin; x < std::min(end, inside_begin); ++x) {
    ApplyTaps(rows, taps, -1, 2 * x, source_width, false, out + int64_t{x} * kC);
  }
  const ResolvedTaps<kDownTaps> resolved(rows, taps, -1);
  int x = std::max(begin, inside_begin);
  const int stop = std::max(x, std::min(end, inside_end));
#if BRDF_HAS_AVX2_PATHS
  if (Avx2Enabled() && resolved.Paired()) x = DownInsideAvx2(resolved, x, stop, out);
#endif
  for (; x < stop; ++x) {
    resolved.Sum(int64_t{2 * x} * kC).Store(out + int64_t{x} * kC);
  }
  for (x = std::max(begin, inside_end); x < end; ++x) {
    ApplyTaps(rows, taps, -1, 2 * x, source_width, false, out + int64_t{x} * kC);
  }
}

void DualFilterUpRow(const Image& source, int width, int y, float* out) {
  const std::array<std::vector<Tap>, 4>& taps = UpTaps();
  const int base_y = y / 2;
  const float* rows[5];
  for (int k = 0; k < 5; ++k) {
    rows[k] = source.pixel(0, std::clamp(base_y - 2 + k, 0, source.height - 1));
  }
  const std::vector<Tap>& even = taps[2 * (y & 1)];
  const std::vector<Tap>& odd = taps[1 + 2 * (y & 1)];
  // Destination pixels whose taps all lie inside: x / 2 - 2 >= 0 and x / 2 + 2 < source.width.
  const bool row_inside = base_y - 2 >= 0 && base_y + 2 < source.height;
  const int inside_begin = row_inside ? std::min(width, 4) : width;
  const int inside_end =
      row_inside ? std::clamp(2 * (source.width - 2), inside_begin, width) : width;
  for (int x = 0; x < inside_begin; ++x) {
    ApplyTaps(rows, (x & 1) ? odd : even, -2, x / 2, source.width, false, out + int64_t{x} * kC);
  }
  const ResolvedTaps<kUpTaps> resolved_even(rows, even, -2), resolved_odd(rows, odd, -2);
  int x = inside_begin;  // even: inside_begin is 4 or width
#if BRDF_HAS_AVX2_PATHS
  if (Avx2Enabled()) x = UpInsideAvx2(resolved_even, resolved_odd, x, inside_end, out);
#endif
  for (; x + 1 < inside_end; x += 2) {
    const int64_t base = int64_t{x / 2} * kC;
    resolved_even.Sum(base).Store(out + int64_t{x} * kC);
    resolved_odd.Sum(base).Store(out + int64_t{x + 1} * kC);
  }
  if (x < inside_end) {
    resolved_even.Sum(int64_t{x / 2} * kC).Store(out + int64_t{x} * kC);
    ++x;
  }
  for (; x < width; ++x) {
    ApplyTaps(rows, (x & 1) ? odd : even, -2, x / 2, source.width, false, out + int64_t{x} * kC);
  }
}

Image DualFilterDown(const Image& source) { return Down(source); }

double DualFilterSigma(int levels) { return std::sqrt(17.0 / 18.0 * (std::pow(4.0, levels) - 1)); }

int DualFilterLevelsForSigma(double sigma) {
  if (!(sigma > 0)) throw UsageError("dual-filter blur: sigma must be > 0");
  int best = 1;
  for (int levels = 2; levels <= 12; ++levels) {
    if (std::abs(std::log(DualFilterSigma(levels) / sigma)) <
        std::abs(std::log(DualFilterSigma(best) / sigma))) {
      best = levels;
    }
  }
  return best;
}

Image DualFilterFromHalf(Image half, int levels) {
  if (levels < 1) throw UsageError("dual-filter blur: at least one level");
  std::vector<Image> chain;
  chain.push_back(std::move(half));
  for (int level = 1; level < levels; ++level) chain.push_back(Down(chain.back()));
  Image result = std::move(chain.back());
  for (int level = levels - 2; level >= 0; --level) {
    // Level `level` has been stepped down from: its storage takes the step back up (no
    // zero-filled allocation).
    Image target = std::move(chain[level]);
    UpInto(result, &target);
    result = std::move(target);
  }
  return result;
}

Image DualFilterBlur(const Image& image, int levels) {
  if (levels < 1) throw UsageError("dual-filter blur: at least one level");
  return Up(DualFilterFromHalf(Down(image), levels), image.width, image.height);
}

}  // namespace brdf
