// Radiance RGBE (Ward, "Real Pixels", Graphics Gems II, 1991) through OpenCV's reader.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "core/errors.h"
#include "core/text.h"
#include "hdr/image_files.h"

namespace brdf {
namespace {

// The header's resolution line ("-Y 512 +X 768"), checked against the file size before OpenCV
// allocates width x height float pixels: a 100-byte file claiming 30000 x 30000 pixels would
// otherwise cost 10 GB. Each scan line takes at least 4 bytes per pixel when flat; run-length
// encoded lines (width 8..32767) at least a 4-byte marker plus, per channel, 2 bytes per run of
// up to 127 pixels (Ward, Graphics Gems II, and the RGBE reader's limits).
void CheckRadianceSize(const std::string& path) {
  const int64_t file_size = RegularFileSize(path);
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path, "cannot open the file");
  std::string line;
  int64_t offset = 0;
  bool header_done = false;
  // Header lines up to an empty one, then the resolution line; headers are short.
  for (int lines = 0; lines < 1024 && std::getline(file, line); ++lines) {
    const int64_t line_offset = offset;
    offset += static_cast<int64_t>(line.size()) + 1;
    if (!header_done) {
      header_done = line.empty();
      continue;
    }
    char y_sign = 0, x_sign = 0, y_axis = 0, x_axis = 0;
    long long first = 0, second = 0;
    if (std::sscanf(line.c_str(), "%c%c %lld %c%c %lld", &y_sign, &y_axis, &first, &x_sign, &x_axis,
                    &second) != 6) {
      throw ByteError(path, line_offset, "expected a resolution line such as '-Y 512 +X 768'");
    }
    // "-Y H +X W" is the usual order; "+X W -Y H" (columns first) swaps the roles.
    const long long height = y_axis == 'Y' ? first : second;
    const long long width = y_axis == 'Y' ? second : first;
    if (width <= 0 || height <= 0 || width > 65536 || height > 65536) {
      throw ByteError(path, line_offset,
                      "image size " + std::to_string(width) + "x" + std::to_string(height) +
                          " is outside 1..65536");
    }
    const bool run_length = width >= 8 && width <= 32767;
    const long long min_line_bytes = run_length ? 4 + 4 * 2 * ((width + 126) / 127) : 4 * width;
    const long long pixel_bytes = file_size - offset;
    if (pixel_bytes < height * min_line_bytes) {
      throw ByteError(path, offset,
                      "the header claims " + std::to_string(width) + "x" + std::to_string(height) +
                          " pixels, more than the " + std::to_string(pixel_bytes) +
                          " bytes after it can hold");
    }
    return;
  }
  throw ByteError(path, offset, "no resolution line after the Radiance header");
}

}  // namespace

Image ReadRadiance(const std::string& path) {
  CheckRadianceSize(path);
  // OpenCV reports a broken file by returning an empty matrix after logging a warning and
  // printing its own message on std::cerr; either would be a second error line (DESIGN §3:
  // one line), so both are held back and the error is raised here.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  cv::Mat bgr;
  {
    std::ostringstream held_back;
    std::streambuf* const cerr_buffer = std::cerr.rdbuf(held_back.rdbuf());
    try {
      bgr = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_COLOR);
    } catch (const cv::Exception&) {
      bgr.release();
    }
    std::cerr.rdbuf(cerr_buffer);
  }
  if (bgr.empty() || bgr.depth() != CV_32F || bgr.channels() != 3) {
    throw InputError(path, "not a readable Radiance RGBE file (bad header or truncated pixels)");
  }
  CheckImageSize(bgr.cols, bgr.rows, path);
  Image image(bgr.cols, bgr.rows);
  for (int y = 0; y < bgr.rows; ++y) {
    const cv::Vec3f* row = bgr.ptr<cv::Vec3f>(y);
    for (int x = 0; x < bgr.cols; ++x) {
      float* rgba = image.pixel(x, y);
      rgba[0] = row[x][2];
      rgba[1] = row[x][1];
      rgba[2] = row[x][0];
    }
  }
  return image;
}

}  // namespace brdf
