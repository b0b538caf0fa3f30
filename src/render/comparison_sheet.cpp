#include "render/comparison_sheet.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "core/errors.h"
#include "core/format.h"
#include "core/text.h"

namespace brdf {
namespace {

// The reference level of a sheet: this percentile of B's luminance over its sphere. A highlight
// covering less than a tenth of the sphere cannot set it (B's maximum, the former reference,
// made a chrome table's sheet read 0.002 everywhere beside its peak).
constexpr double kReferencePercentile = 0.9;
// Share of the reference level below which a channel's error is taken relative to that floor
// (a channel near black, e.g. the red of a blue paint, would otherwise turn noise into
// thousands of per cent).
constexpr double kRelativeErrorFloor = 0.05;
// Share of the reference level above which a pixel of A or B counts as lit: the statistics run
// over the lit sphere, not over the black back of a sphere under a directional light.
constexpr double kLitShare = 0.01;

// The value at `fraction` (0..1) of the sorted values (nearest rank); 0 for none.
double Percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  const size_t rank = static_cast<size_t>(fraction * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(rank),
                   values.end());
  return values[rank];
}

// Two previews side by side in one image, so that one pipeline run maps both identically.
Image SideBySide(const Image& a, const Image& b) {
  Image both(a.width + b.width, a.height, 0.0f);
  for (int y = 0; y < a.height; ++y) {
    std::copy(a.pixel(0, y), a.pixel(0, y) + int64_t{a.width} * Image::kChannels, both.pixel(0, y));
    std::copy(b.pixel(0, y), b.pixel(0, y) + int64_t{b.width} * Image::kChannels,
              both.pixel(a.width, y));
  }
  return both;
}

// Columns [first, first + width) of an 8-bit image.
Image8 Columns(const Image8& image, int first, int width) {
  Image8 part;
  part.width = width;
  part.height = image.height;
  part.rgb.resize(int64_t{width} * image.height * 3);
  for (int y = 0; y < image.height; ++y) {
    const uint8_t* row = image.rgb.data() + (int64_t{y} * image.width + first) * 3;
    std::copy(row, row + int64_t{width} * 3, part.rgb.data() + int64_t{y} * width * 3);
  }
  return part;
}

constexpr int kLabelHeight = 28;
constexpr int kBarWidth = 70;

// The smallest 1, 2 or 5 times a power of ten at or above `value`.
double RoundUp125(double value) {
  if (!(value > 0.0)) return 1.0;
  const double decade = std::pow(10.0, std::floor(std::log10(value)));
  for (double step : {1.0, 2.0, 5.0, 10.0}) {
    if (step * decade >= value * (1 - 1e-12)) return step * decade;
  }
  return 10.0 * decade;
}

cv::Mat ToBgr(const Image8& image) {
  const cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<uint8_t*>(image.rgb.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return bgr;
}

void Label(cv::Mat& sheet, const std::string& text, int x, int width) {
  // Long labels are cut to what fits (about 8 px per character at this scale), a file's path
  // to its name first.
  const std::string shown = ShortLabel(text, static_cast<size_t>(std::max(4, width / 8)));
  cv::putText(sheet, shown, cv::Point(x + 4, 19), cv::FONT_HERSHEY_SIMPLEX, 0.45,
              cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
}

}  // namespace

std::string ComparisonSheet::Summary() const {
  return Format(
      "colour error max over R,G,B of |A-B|/max(B, 5%% of B's 90th-percentile luminance), over "
      "the lit sphere (%lld px, one exposure for A and B): median %.3g, 90th percentile %.3g, "
      "99th percentile %.3g, max %.3g (colour bar 0..%g)",
      static_cast<long long>(lit_pixels), median_relative_error, p90_relative_error,
      p99_relative_error, max_relative_error, colour_bar_top);
}

double ColourRelativeError(const Rgb& a, const Rgb& b, double floor) {
  double error = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double denominator = std::max(b[c], floor);
    const double difference = std::abs(a[c] - b[c]);
    error = std::max(error,
                     denominator > 0.0 ? difference / denominator : (difference > 0.0 ? 1.0 : 0.0));
  }
  return error;
}

ComparisonSheet CompareRadiance(const Image& radiance_a, const Image& radiance_b,
                                cv::Mat* error_map) {
  const int size_x = radiance_a.width, size_y = radiance_a.height;
  ComparisonSheet result;
  std::vector<double> luminance_b;
  for (int y = 0; y < size_y; ++y) {
    for (int x = 0; x < size_x; ++x) {
      const float* b = radiance_b.pixel(x, y);
      if (b[3] != 0.0f) luminance_b.push_back(PixelLuminance(b));
    }
  }
  result.reference_luminance = Percentile(std::move(luminance_b), kReferencePercentile);
  const double floor = kRelativeErrorFloor * result.reference_luminance;
  const double lit = kLitShare * result.reference_luminance;
  std::vector<double> errors;
  errors.reserve(static_cast<size_t>(size_x) * size_y);
  double sum = 0.0;
  for (int y = 0; y < size_y; ++y) {
    for (int x = 0; x < size_x; ++x) {
      const float* a = radiance_a.pixel(x, y);
      const float* b = radiance_b.pixel(x, y);
      if (a[3] == 0.0f || b[3] == 0.0f) continue;
      if (!(std::max(PixelLuminance(a), PixelLuminance(b)) > lit)) continue;
      const double relative =
          ColourRelativeError(Rgb(a[0], a[1], a[2]), Rgb(b[0], b[1], b[2]), floor);
      if (error_map != nullptr) error_map->at<float>(y, x) = static_cast<float>(relative);
      result.max_relative_error = std::max(result.max_relative_error, relative);
      sum += relative;
      errors.push_back(relative);
    }
  }
  result.lit_pixels = static_cast<int64_t>(errors.size());
  result.mean_relative_error = errors.empty() ? 0.0 : sum / static_cast<double>(errors.size());
  result.median_relative_error = Percentile(errors, 0.5);
  result.p90_relative_error = Percentile(errors, 0.9);
  // The colour bar spans the 99th percentile: a few Monte Carlo outliers (a sharp lobe found
  // by one sample in thousands) would otherwise push every other pixel to the bottom colour.
  result.p99_relative_error = Percentile(std::move(errors), 0.99);
  result.colour_bar_top = RoundUp125(result.p99_relative_error);
  return result;
}

ComparisonSheet MakeComparisonSheet(const Image8& display_a, const Image8& display_b,
                                    const Image& radiance_a, const Image& radiance_b,
                                    const std::string& label_a, const std::string& label_b) {
  const int size_x = display_a.width, size_y = display_a.height;
  if (display_b.width != size_x || display_b.height != size_y || radiance_a.width != size_x ||
      radiance_b.width != size_x || radiance_a.height != size_y || radiance_b.height != size_y) {
    throw ComputeError("comparison sheet: the two previews differ in size");
  }
  // The map: the error on the lit sphere, black (the bottom colour's background) elsewhere.
  cv::Mat error(size_y, size_x, CV_32F, cv::Scalar(-1));
  ComparisonSheet result = CompareRadiance(radiance_a, radiance_b, &error);
  const cv::Mat on_sphere = error >= 0.0f;

  cv::Mat error8, error_colour;
  error.convertTo(error8, CV_8U, 255.0 / result.colour_bar_top);
  cv::applyColorMap(error8, error_colour, cv::COLORMAP_VIRIDIS);
  error_colour.setTo(cv::Scalar(0, 0, 0), on_sphere == 0);

  cv::Mat sheet(size_y + kLabelHeight, 3 * size_x + kBarWidth, CV_8UC3, cv::Scalar(40, 40, 40));
  ToBgr(display_a).copyTo(sheet(cv::Rect(0, kLabelHeight, size_x, size_y)));
  ToBgr(display_b).copyTo(sheet(cv::Rect(size_x, kLabelHeight, size_x, size_y)));
  error_colour.copyTo(sheet(cv::Rect(2 * size_x, kLabelHeight, size_x, size_y)));
  Label(sheet, "A: " + label_a, 0, size_x);
  Label(sheet, "B: " + label_b, size_x, size_x);
  Label(sheet, "max RGB |A-B|/B", 2 * size_x, size_x);

  // Colour bar: top = colour_bar_top, bottom = 0, labelled at both ends and the middle.
  const int bar_x = 3 * size_x + 8, bar_top = kLabelHeight + 10, bar_height = size_y - 20;
  cv::Mat ramp(bar_height, 1, CV_8U);
  for (int row = 0; row < bar_height; ++row) {
    ramp.at<uint8_t>(row, 0) = static_cast<uint8_t>(
        std::lround(255.0 * (bar_height - 1 - row) / std::max(1, bar_height - 1)));
  }
  cv::Mat ramp_colour;
  cv::applyColorMap(ramp, ramp_colour, cv::COLORMAP_VIRIDIS);
  cv::resize(ramp_colour, ramp_colour, cv::Size(14, bar_height), 0, 0, cv::INTER_NEAREST);
  ramp_colour.copyTo(sheet(cv::Rect(bar_x, bar_top, 14, bar_height)));
  for (double fraction : {1.0, 0.5, 0.0}) {
    const std::string text = Format("%g", fraction * result.colour_bar_top);
    const int y = bar_top + static_cast<int>((1.0 - fraction) * (bar_height - 1));
    cv::putText(sheet, text, cv::Point(bar_x + 18, y + 4), cv::FONT_HERSHEY_SIMPLEX, 0.38,
                cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  }

  result.sheet.width = sheet.cols;
  result.sheet.height = sheet.rows;
  result.sheet.rgb.resize(int64_t{sheet.cols} * sheet.rows * 3);
  cv::Mat rgb(sheet.rows, sheet.cols, CV_8UC3, result.sheet.rgb.data());
  cv::cvtColor(sheet, rgb, cv::COLOR_BGR2RGB);  // writes into result.sheet.rgb
  return result;
}

ComparisonSheet ToneMapAndCompare(const Image& radiance_a, const Image& radiance_b,
                                  const ToneOptions& tone, const std::string& label_a,
                                  const std::string& label_b, ToneResult* toned) {
  ToneResult result = RunTonePipeline(SideBySide(radiance_a, radiance_b), tone);
  const int width = radiance_a.width;
  ComparisonSheet sheet =
      MakeComparisonSheet(Columns(result.display, 0, width), Columns(result.display, width, width),
                          radiance_a, radiance_b, label_a, label_b);
  if (toned != nullptr) *toned = std::move(result);
  return sheet;
}

}  // namespace brdf
