// The float image every stage of the HDR pipeline reads and writes (DESIGN §8): linear RGB
// (Rec.709 primaries, radiometric units where the producer knows them) plus alpha, four floats
// per pixel, rows top to bottom.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace brdf {

struct Image {
  static constexpr int kChannels = 4;  // R, G, B, A

  int width = 0;
  int height = 0;
  std::vector<float> rgba;  // width * height * 4, row-major, top row first

  Image() = default;
  // An image of the given size, every pixel (0, 0, 0, alpha).
  Image(int width, int height, float alpha = 1.0f);

  int64_t pixel_count() const { return int64_t{width} * height; }
  float* pixel(int x, int y) { return rgba.data() + (int64_t{y} * width + x) * kChannels; }
  const float* pixel(int x, int y) const {
    return rgba.data() + (int64_t{y} * width + x) * kChannels;
  }
};

// Rec.709 luminance of a pixel (DESIGN §1); the float twin of core's Luminance().
inline float PixelLuminance(const float* rgb) {
  return 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2];
}

// Counts the pixels with a NaN or infinite channel and makes them black (RGB 0; a broken
// alpha becomes 1), so that a broken input never reaches the tone mapper, whose log-average a
// single NaN would poison.
int64_t ReplaceNonFinite(Image* image);

// Throws UsageError unless 0 < width, height <= 65536 and width * height <= 2^28 (`what`
// names the option or file).
void CheckImageSize(int width, int height, const std::string& what);

}  // namespace brdf
