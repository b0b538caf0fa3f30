#include "hdr/image.h"

#include <cmath>

#include "core/errors.h"

namespace brdf {

Image::Image(int width, int height, float alpha)
    : width(width), height(height), rgba(int64_t{width} * height * kChannels, 0.0f) {
  for (int64_t i = 0; i < pixel_count(); ++i) rgba[i * kChannels + 3] = alpha;
}

int64_t ReplaceNonFinite(Image* image) {
  int64_t count = 0;
  for (int64_t i = 0; i < image->pixel_count(); ++i) {
    float* channel = image->rgba.data() + i * Image::kChannels;
    bool broken = false;
    for (int c = 0; c < Image::kChannels; ++c) {
      if (!std::isfinite(channel[c])) {
        channel[c] = c == 3 ? 1.0f : 0.0f;
        broken = true;
      }
    }
    count += broken;
  }
  return count;
}

void CheckImageSize(int width, int height, const std::string& what) {
  constexpr int kMaxSide = 65536;
  if (width <= 0 || height <= 0 || width > kMaxSide || height > kMaxSide) {
    throw UsageError(what + ": image size " + std::to_string(width) + "x" +
                     std::to_string(height) + " is outside 1.." + std::to_string(kMaxSide));
  }
}

}  // namespace brdf
