#include "cli/chart.h"

#include <cmath>
#include <iomanip>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

#include "core/atomic_file.h"
#include "core/errors.h"

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
  if (text.size() <= max_chars || max_chars < 4) return text;
  return text.substr(0, max_chars - 3) + "...";
}

void WritePng(const cv::Mat& image, const std::string& path) {
  std::vector<uchar> png;
  try {
    if (!cv::imencode(".png", image, png)) throw OutputError(path, "PNG encoding failed");
  } catch (const cv::Exception& error) {
    throw OutputError(path, std::string("PNG encoding failed: ") + error.what());
  }
  WriteFileAtomically(
      path,
      [&](std::ostream& out) {
        out.write(reinterpret_cast<const char*>(png.data()),
                  static_cast<std::streamsize>(png.size()));
      },
      /*binary=*/true);
}

}  // namespace brdf::cli::chart
