// Radiance RGBE (Ward, "Real Pixels", Graphics Gems II, 1991; the file format of Ward's Radiance
// documentation): a text header ending in a blank line, a resolution line "-Y H +X W", then H
// scan lines of W pixels, each (R, G, B, E) byte quadruple worth (R, G, B) x 2^(E - 136).
// Scan lines 8..32767 pixels wide are usually run-length encoded per channel.
//
// Read here rather than through cv::imread: imread picks its decoder by sniffing the bytes, so a
// file that began like a Radiance file but carried another format's signature inside reached
// OpenCV's DICOM decoder, which allocated gigabytes (found by fuzz_radiance). The conversion is
// the reference one (mantissa x 2^(E - 136), 0 when E = 0), so images read as before.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "core/errors.h"
#include "core/text.h"
#include "hdr/image_files.h"

namespace brdf {
namespace {

// Radiance files are pictures; a larger one is not one brdfkit reads.
constexpr int64_t kMaxRadianceBytes = int64_t{1} << 31;

// Run-length encoding applies to scan lines of this width (the format's limits).
constexpr int kMinRunLengthWidth = 8;
constexpr int kMaxRunLengthWidth = 32767;

struct RadianceHeader {
  int width = 0;
  int height = 0;
  size_t pixels_offset = 0;  // first byte after the resolution line
};

// Reads the next line of `bytes` from `*offset` (without its '\n'); false at the end.
bool NextLine(const std::string& bytes, size_t* offset, std::string_view* line) {
  if (*offset >= bytes.size()) return false;
  size_t end = bytes.find('\n', *offset);
  if (end == std::string::npos) end = bytes.size();
  *line = std::string_view(bytes).substr(*offset, end - *offset);
  *offset = end + 1;
  return true;
}

RadianceHeader ReadHeader(const std::string& bytes, const std::string& path) {
  if (bytes.size() < 2 || bytes[0] != '#' || bytes[1] != '?') {
    throw ByteError(path, 0, "not a Radiance file (expected '#?')");
  }
  size_t offset = 0;
  std::string_view line;
  NextLine(bytes, &offset, &line);  // "#?RADIANCE"
  // Variables up to the blank line; only FORMAT matters for reading.
  for (;;) {
    const size_t line_offset = offset;
    if (!NextLine(bytes, &offset, &line)) {
      throw ByteError(path, static_cast<int64_t>(line_offset),
                      "the header does not end (no blank line before the resolution)");
    }
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty()) break;
    if (StartsWith(line, "FORMAT=") && line != "FORMAT=32-bit_rle_rgbe") {
      throw ByteError(
          path, static_cast<int64_t>(line_offset),
          "unsupported " + std::string(line.substr(0, 40)) + " (brdfkit reads 32-bit_rle_rgbe)");
    }
  }
  const size_t resolution_offset = offset;
  RadianceHeader header;
  long long height = 0, width = 0;
  char extra = 0;
  const std::string resolution(NextLine(bytes, &offset, &line) ? line : std::string_view());
  if (std::sscanf(resolution.c_str(), "-Y %lld +X %lld %c", &height, &width, &extra) != 2) {
    throw ByteError(path, static_cast<int64_t>(resolution_offset),
                    "expected the resolution line '-Y HEIGHT +X WIDTH' (the standard "
                    "orientation), found '" +
                        resolution.substr(0, 40) + "'");
  }
  if (width <= 0 || height <= 0 || width > 65536 || height > 65536) {
    throw ByteError(path, static_cast<int64_t>(resolution_offset),
                    "image size " + std::to_string(width) + "x" + std::to_string(height) +
                        " is outside 1..65536");
  }
  header.width = static_cast<int>(width);
  header.height = static_cast<int>(height);
  header.pixels_offset = offset;
  // Before allocating width x height float pixels: a run-length scan line takes at least a
  // 4-byte marker and, per channel, 2 bytes per run of up to 127 pixels; a flat one 4 bytes a
  // pixel. A 60-byte file claiming 30000 x 30000 pixels must not cost 10 GB.
  const bool run_length = width >= kMinRunLengthWidth && width <= kMaxRunLengthWidth;
  const long long min_line_bytes = run_length ? 4 + 4 * 2 * ((width + 126) / 127) : 4 * width;
  const long long pixel_bytes = static_cast<long long>(bytes.size() - offset);
  if (pixel_bytes < height * min_line_bytes) {
    throw ByteError(path, static_cast<int64_t>(offset),
                    "the header claims " + std::to_string(width) + "x" + std::to_string(height) +
                        " pixels, more than the " + std::to_string(pixel_bytes) +
                        " bytes after it can hold");
  }
  return header;
}

// (R, G, B, E) -> linear RGB: mantissas x 2^(E - 136), black when E = 0 (Ward 1991).
void RgbeToFloat(const uint8_t* rgbe, float* rgb) {
  if (rgbe[3] == 0) {
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    return;
  }
  const float scale = static_cast<float>(std::ldexp(1.0, rgbe[3] - (128 + 8)));
  for (int c = 0; c < 3; ++c) rgb[c] = rgbe[c] * scale;
}

}  // namespace

Image ReadRadiance(const std::string& path) {
  const std::string bytes = ReadFileBytes(path, kMaxRadianceBytes);
  const RadianceHeader header = ReadHeader(bytes, path);
  const int width = header.width;
  CheckImageSize(width, header.height, path);
  Image image(width, header.height);
  const uint8_t* const data = reinterpret_cast<const uint8_t*>(bytes.data());
  size_t at = header.pixels_offset;
  auto need = [&](size_t count, const char* what) {
    if (bytes.size() - at < count) {
      throw ByteError(path, static_cast<int64_t>(at),
                      std::string("the file ends inside ") + what + " (truncated pixels)");
    }
  };
  std::vector<uint8_t> line(static_cast<size_t>(width) * 4);  // channel-planar: RRR..GGG..
  for (int y = 0; y < header.height; ++y) {
    const bool run_length = width >= kMinRunLengthWidth && width <= kMaxRunLengthWidth;
    need(4, "a scan line");
    const bool encoded =
        run_length && data[at] == 2 && data[at + 1] == 2 && (data[at + 2] & 0x80) == 0;
    if (!encoded) {  // flat: W quadruples
      need(static_cast<size_t>(width) * 4, "a flat scan line");
      for (int x = 0; x < width; ++x) RgbeToFloat(data + at + 4 * x, image.pixel(x, y));
      at += static_cast<size_t>(width) * 4;
      continue;
    }
    const int line_width = (data[at + 2] << 8) | data[at + 3];
    if (line_width != width) {
      throw ByteError(path, static_cast<int64_t>(at),
                      "scan line of " + std::to_string(line_width) + " pixels in an image " +
                          std::to_string(width) + " wide");
    }
    at += 4;
    // Each channel in turn: a count byte above 128 repeats the next byte (count - 128) times,
    // otherwise `count` literal bytes follow.
    for (int channel = 0; channel < 4; ++channel) {
      uint8_t* const plane = line.data() + static_cast<size_t>(channel) * width;
      int x = 0;
      while (x < width) {
        need(1, "a run-length scan line");
        const size_t count_offset = at;
        int count = data[at++];
        const bool run = count > 128;
        if (run) count -= 128;
        if (count == 0 || count > width - x) {
          throw ByteError(path, static_cast<int64_t>(count_offset),
                          "run of " + std::to_string(count) + " pixels where " +
                              std::to_string(width - x) + " remain in the scan line");
        }
        if (run) {
          need(1, "a run-length scan line");
          std::fill(plane + x, plane + x + count, data[at++]);
        } else {
          need(static_cast<size_t>(count), "a run-length scan line");
          std::copy(data + at, data + at + count, plane + x);
          at += static_cast<size_t>(count);
        }
        x += count;
      }
    }
    for (int x = 0; x < width; ++x) {
      const uint8_t rgbe[4] = {line[x], line[static_cast<size_t>(width) + x],
                               line[2 * static_cast<size_t>(width) + x],
                               line[3 * static_cast<size_t>(width) + x]};
      RgbeToFloat(rgbe, image.pixel(x, y));
    }
  }
  return image;
}

}  // namespace brdf
