#include "hdr/image.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/errors.h"

namespace brdf {

Image::Image(int width, int height, float alpha) : width(width), height(height) {
  rgba.assign(static_cast<size_t>(pixel_count()) * kChannels, 0.0f);
  // The vector is zero already: a (positive) zero alpha needs no second pass.
  if (alpha != 0.0f || std::signbit(alpha)) {
    for (int64_t i = 0; i < pixel_count(); ++i) rgba[i * kChannels + 3] = alpha;
  }
}

int64_t ReplaceNonFinite(Image* image) {
  // Broken pixels are rare: a branch-free scan of each block (which the compiler vectorises)
  // finds the blocks that hold one, and only those are repaired pixel by pixel.
  constexpr int64_t kBlockPixels = 4096;
  int64_t count = 0;
  const int64_t pixels = image->pixel_count();
  for (int64_t begin = 0; begin < pixels; begin += kBlockPixels) {
    const int64_t end = std::min(pixels, begin + kBlockPixels);
    const float* block = image->rgba.data() + begin * Image::kChannels;
    uint32_t broken = 0;
    for (int64_t i = 0; i < (end - begin) * Image::kChannels; ++i) {
      uint32_t bits;
      std::memcpy(&bits, block + i, sizeof(bits));
      broken |= (bits & 0x7f800000u) == 0x7f800000u;  // exponent all ones: NaN or infinite
    }
    if (broken == 0) continue;
    for (int64_t i = begin; i < end; ++i) {
      float* rgba = image->rgba.data() + i * Image::kChannels;
      const bool broken_colour =
          !std::isfinite(rgba[0]) || !std::isfinite(rgba[1]) || !std::isfinite(rgba[2]);
      const bool broken_alpha = !std::isfinite(rgba[3]);
      // The other channels of a broken pixel are not trusted either: the whole colour goes.
      if (broken_colour) rgba[0] = rgba[1] = rgba[2] = 0.0f;
      if (broken_alpha) rgba[3] = 1.0f;
      count += broken_colour || broken_alpha;
    }
  }
  return count;
}

void CheckImageSize(int width, int height, const std::string& what) {
  constexpr int kMaxSide = 65536;
  if (width <= 0 || height <= 0 || width > kMaxSide || height > kMaxSide) {
    throw UsageError(what + ": image size " + std::to_string(width) + "x" + std::to_string(height) +
                     " is outside 1.." + std::to_string(kMaxSide));
  }
}

}  // namespace brdf
