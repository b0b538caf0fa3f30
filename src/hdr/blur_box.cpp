#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "hdr/blur.h"

namespace brdf {
namespace {

// Gwosdek et al. 2011, eqs. (7)-(8) rewritten for the variance s^2 of one pass: the largest
// radius r with r(r+1)/3 <= s^2 (a plain box of 2r+1 taps has variance r(r+1)/3), then the end
// weight alpha in [0, 1) that makes the variance exactly s^2:
//   alpha = (2r+1)(s^2 - r(r+1)/3) / (2((r+1)^2 - s^2)).
struct ExtendedBox {
  int radius = 0;
  float alpha = 0.0f;
  float normaliser = 1.0f;  // 1 / (2r + 1 + 2 alpha)
};

ExtendedBox DesignExtendedBox(double variance) {
  ExtendedBox box;
  box.radius = static_cast<int>(std::floor(0.5 * (std::sqrt(12.0 * variance + 1.0) - 1.0)));
  const double r = box.radius;
  const double alpha =
      (2 * r + 1) * (variance - r * (r + 1) / 3.0) / (2 * ((r + 1) * (r + 1) - variance));
  box.alpha = static_cast<float>(alpha);
  box.normaliser = static_cast<float>(1.0 / (2 * r + 1 + 2 * alpha));
  return box;
}

// One pass along a line of `count` pixels `stride` floats apart (4 channels each), by a
// running sum: O(1) per pixel whatever the radius.
void BoxLine(const float* in, float* out, int count, int64_t stride, const ExtendedBox& box,
             std::vector<float>* scratch) {
  constexpr int kC = Image::kChannels;
  const int r = box.radius;
  auto at = [&](int i) { return in + std::clamp(i, 0, count - 1) * stride; };
  float sum[kC] = {0, 0, 0, 0};
  for (int i = -r; i <= r; ++i) {
    for (int c = 0; c < kC; ++c) sum[c] += at(i)[c];
  }
  scratch->resize(int64_t{count} * kC);
  for (int x = 0; x < count; ++x) {
    const float* before = at(x - r - 1);
    const float* after = at(x + r + 1);
    for (int c = 0; c < kC; ++c) {
      (*scratch)[x * kC + c] = (sum[c] + box.alpha * (before[c] + after[c])) * box.normaliser;
    }
    const float* leaving = at(x - r);
    for (int c = 0; c < kC; ++c) sum[c] += after[c] - leaving[c];
  }
  for (int x = 0; x < count; ++x) {
    for (int c = 0; c < kC; ++c) out[x * stride + c] = (*scratch)[x * kC + c];
  }
}

// One vertical pass over columns [first, last): running sums of whole row segments, so memory
// is read row by row (a column walk would miss the cache on every pixel).
void BoxColumns(const Image& in, Image* out, int first, int last, const ExtendedBox& box) {
  constexpr int kC = Image::kChannels;
  const int r = box.radius, height = in.height;
  const int64_t span = int64_t{last - first} * kC;
  auto row = [&](int y) { return in.pixel(first, std::clamp(y, 0, height - 1)); };
  std::vector<float> sum(span, 0.0f);
  for (int y = -r; y <= r; ++y) {
    const float* line = row(y);
    for (int64_t i = 0; i < span; ++i) sum[i] += line[i];
  }
  for (int y = 0; y < height; ++y) {
    const float* before = row(y - r - 1);
    const float* after = row(y + r + 1);
    const float* leaving = row(y - r);
    float* target = out->pixel(first, y);
    for (int64_t i = 0; i < span; ++i) {
      target[i] = (sum[i] + box.alpha * (before[i] + after[i])) * box.normaliser;
      sum[i] += after[i] - leaving[i];
    }
  }
}

}  // namespace

Image BoxBlur(const Image& image, double sigma, int passes) {
  if (!(sigma > 0)) throw UsageError("box blur: sigma must be > 0");
  if (passes < 1) throw UsageError("box blur: at least one pass");
  // Variances add under convolution: each pass carries sigma^2 / passes.
  const ExtendedBox box = DesignExtendedBox(sigma * sigma / passes);
  constexpr int kC = Image::kChannels;
  constexpr int kColumnBlock = 64;
  Image result = image;
  Image scratch(image.width, image.height);
  for (int pass = 0; pass < passes; ++pass) {
    tbb::parallel_for(0, result.height, [&](int y) {
      std::vector<float> line;
      BoxLine(result.pixel(0, y), result.pixel(0, y), result.width, kC, box, &line);
    });
    tbb::parallel_for(0, (result.width + kColumnBlock - 1) / kColumnBlock, [&](int block) {
      BoxColumns(result, &scratch, block * kColumnBlock,
                 std::min(result.width, (block + 1) * kColumnBlock), box);
    });
    std::swap(result, scratch);
  }
  return result;
}

}  // namespace brdf
