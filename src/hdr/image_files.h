// Image files of the HDR pipeline (DESIGN §8): OpenEXR (read, write half or float), Radiance
// RGBE `.hdr` (read, by brdfkit's own decoder) and 8-bit PNG (write, strips deflated by zlib in
// parallel). Readers throw InputError naming the file
// (and the byte where a signature is wrong); writers are atomic (temporary file, then rename) and
// throw OutputError naming the target.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hdr/image.h"

namespace brdf {

enum class ExrPixelType { kHalf, kFloat };
// "half" or "float"; anything else is a UsageError naming the accepted names.
ExrPixelType ParseExrPixelType(const std::string& name);
// Lossless OpenEXR compressions: zip (zlib level 1 here, 16-line blocks), piz (wavelet +
// Huffman; the default: on noisy HDR renders about as small as zip and twice as fast to write,
// docs/hdr.md), rle, none.
enum class ExrCompression { kZip, kPiz, kRle, kNone };
// "zip", "piz", "rle", "none"; throws UsageError otherwise.
ExrCompression ParseExrCompression(const std::string& name);

// Reads the R, G, B (or luminance-only Y) and A channels of a scan-line or tiled OpenEXR file
// as float; a missing channel reads as 0 (A as 1).
Image ReadExr(const std::string& path);
// Writes R, G, B, A in half or float. Half values beyond +-65504 (the largest half) are
// clamped to it rather than becoming infinite; returns how many channel values were clamped.
int64_t WriteExr(const std::string& path, const Image& image, ExrPixelType type,
                 ExrCompression compression = ExrCompression::kPiz);

// Reads a Radiance RGBE file (`#?RADIANCE`, run-length encoded or flat) as linear float RGB,
// alpha 1.
Image ReadRadiance(const std::string& path);

// OpenEXR or Radiance, chosen by the file's signature (never by the extension alone).
Image ReadHdrImage(const std::string& path);

// 8-bit sRGB-encoded RGB, `width * height * 3` bytes, top row first.
struct Image8 {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;
};
// The PNG file's bytes (8-bit RGB; `path` only names the target in errors), and the atomic
// write of them. Strips of rows are compressed in parallel (image_files.cpp).
std::string EncodePng(const Image8& image, const std::string& path);
void WritePng(const std::string& path, const Image8& image);

}  // namespace brdf
