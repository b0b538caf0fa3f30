#include "cli/chart.h"

#include <cmath>
#include <iomanip>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "core/text.h"
#include "hdr/image_files.h"

namespace brdf::cli::chart {

double TickStep(double range, int ticks) {
  const double raw = range / ticks;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 5.0, 10.0}) {
    if (factor * power >= raw) return factor * power;
  }
  return 10.0 * power;
}

std::string TickLabel(double value) {
  std::ostringstream text;
  text << std::setprecision(6) << value;
  return text.str();
}

void Label(cv::Mat* image, const std::string& text, cv::Point origin, double scale) {
  cv::putText(*image, text, origin, cv::FONT_HERSHEY_SIMPLEX, scale, kBlack, 1, cv::LINE_AA);
}

std::string Shorten(const std::string& text, size_t max_chars) {
  return ShortLabel(text, max_chars);
}

void WritePng(const cv::Mat& image, const std::string& path) {
  // Through the HDR library's PNG encoder, not OpenCV's: one encoder for every PNG brdf writes,
  // and no image-codec libraries to load at start-up.
  Image8 rgb;
  rgb.width = image.cols;
  rgb.height = image.rows;
  rgb.rgb.resize(size_t(image.cols) * image.rows * 3);
  for (int y = 0; y < image.rows; ++y) {
    const cv::Vec3b* row = image.ptr<cv::Vec3b>(y);
    for (int x = 0; x < image.cols; ++x) {
      uint8_t* pixel = &rgb.rgb[(size_t(y) * image.cols + x) * 3];
      pixel[0] = row[x][2];  // OpenCV stores BGR
      pixel[1] = row[x][1];
      pixel[2] = row[x][0];
    }
  }
  brdf::WritePng(path, rgb);
}

}  // namespace brdf::cli::chart
