// Radiance RGBE (Ward, "Real Pixels", Graphics Gems II, 1991) through OpenCV's reader.
#include <iostream>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "core/errors.h"
#include "hdr/image_files.h"

namespace brdf {

Image ReadRadiance(const std::string& path) {
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
