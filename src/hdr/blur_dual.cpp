// Dual filtering (Bjørge 2015); the taps and their variance are derived in blur.h.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/errors.h"
#include "hdr/blur.h"

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

// Weighted sum of source pixels around (base_x, base_y); `inside` says that no tap leaves the
// image, so the clamps (the edge rule) can be skipped.
// Weighted sum of source pixels around (base_x, base_y), edges repeating the border pixel.
void ApplyTapsClamped(const Image& source, const std::vector<Tap>& taps, int base_x, int base_y,
                      float* out) {
  float sum[kC] = {0, 0, 0, 0};
  for (const Tap& tap : taps) {
    const int y = std::clamp(base_y + tap.dy, 0, source.height - 1);
    const int x = std::clamp(base_x + tap.dx, 0, source.width - 1);
    const float* p = source.pixel(x, y);
    for (int c = 0; c < kC; ++c) sum[c] += tap.weight * p[c];
  }
  for (int c = 0; c < kC; ++c) out[c] = sum[c];
}

// The same taps away from the edges, as float offsets from the centre pixel in an image of
// `width` pixels: no clamps and no index arithmetic per tap.
struct OffsetTap {
  int64_t offset;
  float weight;
};
std::vector<OffsetTap> Offsets(const std::vector<Tap>& taps, int width) {
  std::vector<OffsetTap> offsets;
  for (const Tap& tap : taps) {
    offsets.push_back({(int64_t{tap.dy} * width + tap.dx) * kC, tap.weight});
  }
  return offsets;
}
void ApplyOffsets(const float* centre, const std::vector<OffsetTap>& taps, float* out) {
  // Two partial sums taken in turn, so that consecutive taps do not wait for each other's
  // addition.
  float even[kC] = {0, 0, 0, 0}, odd[kC] = {0, 0, 0, 0};
  const size_t count = taps.size();
  size_t k = 0;
  for (; k + 1 < count; k += 2) {
    const float* a = centre + taps[k].offset;
    const float* b = centre + taps[k + 1].offset;
    for (int c = 0; c < kC; ++c) {
      even[c] += taps[k].weight * a[c];
      odd[c] += taps[k + 1].weight * b[c];
    }
  }
  if (k < count) {
    const float* a = centre + taps[k].offset;
    for (int c = 0; c < kC; ++c) even[c] += taps[k].weight * a[c];
  }
  for (int c = 0; c < kC; ++c) out[c] = even[c] + odd[c];
}

Image Down(const Image& source) {
  static const std::vector<Tap> taps = Taps(DownStencil());
  const std::vector<OffsetTap> offsets = Offsets(taps, source.width);
  Image result((source.width + 1) / 2, (source.height + 1) / 2);
  tbb::parallel_for(0, result.height, [&](int y) {
    const bool row_inside = 2 * y - 1 >= 0 && 2 * y + 2 < source.height;
    for (int x = 0; x < result.width; ++x) {
      if (row_inside && 2 * x - 1 >= 0 && 2 * x + 2 < source.width) {
        ApplyOffsets(source.pixel(2 * x, 2 * y), offsets, result.pixel(x, y));
      } else {
        ApplyTapsClamped(source, taps, 2 * x, 2 * y, result.pixel(x, y));
      }
    }
  });
  return result;
}

Image Up(const Image& source, int width, int height) {
  static const std::array<std::vector<Tap>, 4> taps = {
      Taps(UpStencil(false, false)), Taps(UpStencil(true, false)), Taps(UpStencil(false, true)),
      Taps(UpStencil(true, true))};
  std::array<std::vector<OffsetTap>, 4> offsets;
  for (int phase = 0; phase < 4; ++phase) offsets[phase] = Offsets(taps[phase], source.width);
  Image result(width, height);
  tbb::parallel_for(0, height, [&](int y) {
    const bool row_inside = y / 2 - 2 >= 0 && y / 2 + 2 < source.height;
    for (int x = 0; x < width; ++x) {
      const int phase = (x & 1) + 2 * (y & 1);
      if (row_inside && x / 2 - 2 >= 0 && x / 2 + 2 < source.width) {
        ApplyOffsets(source.pixel(x / 2, y / 2), offsets[phase], result.pixel(x, y));
      } else {
        ApplyTapsClamped(source, taps[phase], x / 2, y / 2, result.pixel(x, y));
      }
    }
  });
  return result;
}

}  // namespace

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

Image DualFilterBlur(const Image& image, int levels) {
  if (levels < 1) throw UsageError("dual-filter blur: at least one level");
  std::vector<Image> chain;
  chain.push_back(image);
  for (int level = 0; level < levels; ++level) chain.push_back(Down(chain.back()));
  Image result = std::move(chain.back());
  for (int level = levels - 1; level >= 0; --level) {
    result = Up(result, chain[level].width, chain[level].height);
  }
  return result;
}

}  // namespace brdf
