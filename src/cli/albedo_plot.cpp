#include "cli/albedo_plot.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "cli/chart.h"

namespace brdf::cli {
namespace {

constexpr int kWidth = 960, kHeight = 600;
constexpr int kLeft = 80, kRight = 30, kTop = 50, kBottom = 60;
constexpr double kThetaAxisDeg = 90.0;
const char* const kChannelLabels[3] = {"red", "green", "blue"};

using chart::kBlack;
using chart::kChannelColours;
using chart::kGrey;
using chart::kLightGrey;
using chart::Label;
using chart::TickLabel;
using chart::TickStep;

class PlotArea {
 public:
  explicit PlotArea(double albedo_top) : albedo_top_(albedo_top) {}
  cv::Point At(double theta_deg, double albedo) const {
    const double x = kLeft + theta_deg / kThetaAxisDeg * (kWidth - kLeft - kRight);
    const double y = kHeight - kBottom - albedo / albedo_top_ * (kHeight - kTop - kBottom);
    return cv::Point(static_cast<int>(std::lround(x)), static_cast<int>(std::lround(y)));
  }
  double albedo_top() const { return albedo_top_; }

 private:
  double albedo_top_;
};

}  // namespace

void WriteAlbedoPlot(const AlbedoCurve& curve, const std::string& path) {
  double highest = 1.0;
  for (const AlbedoPoint& point : curve.points) {
    const double top = (point.estimate.albedo + point.estimate.error).maxCoeff();
    if (std::isfinite(top)) highest = std::max(highest, top);
  }
  const double step = TickStep(1.15 * highest, 8);
  const PlotArea area(std::ceil(1.15 * highest / step) * step);
  cv::Mat image(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));

  // Grid and tick labels.
  for (double theta = 0; theta <= kThetaAxisDeg + 1e-9; theta += 10) {
    cv::line(image, area.At(theta, 0), area.At(theta, area.albedo_top()), kLightGrey);
    Label(&image, TickLabel(theta), area.At(theta, 0) + cv::Point(-8, 22), 0.45);
  }
  for (double albedo = 0; albedo <= area.albedo_top() + 1e-9 * step; albedo += step) {
    cv::line(image, area.At(0, albedo), area.At(kThetaAxisDeg, albedo), kLightGrey);
    Label(&image, TickLabel(albedo), area.At(0, albedo) + cv::Point(-60, 5), 0.45);
  }
  cv::rectangle(image, area.At(0, area.albedo_top()), area.At(kThetaAxisDeg, 0), kBlack);

  // a = 1, dashed: above it a material creates energy.
  for (double theta = 0; theta < kThetaAxisDeg; theta += 2) {
    cv::line(image, area.At(theta, 1.0), area.At(std::min(theta + 1, kThetaAxisDeg), 1.0), kGrey, 2,
             cv::LINE_AA);
  }
  Label(&image, "a = 1", area.At(kThetaAxisDeg, 1.0) + cv::Point(-55, -8), 0.45);

  for (int c = 0; c < 3; ++c) {
    std::vector<cv::Point> line;
    for (const AlbedoPoint& point : curve.points) {
      if (std::isfinite(point.estimate.albedo[c])) {
        line.push_back(area.At(point.theta_deg, point.estimate.albedo[c]));
      }
    }
    if (line.size() == 1) cv::circle(image, line[0], 3, kChannelColours[c], cv::FILLED);
    cv::polylines(image, line, false, kChannelColours[c], 2, cv::LINE_AA);
    const cv::Point legend(kWidth - kRight - 130, kTop + 20 + 20 * c);
    cv::line(image, legend, legend + cv::Point(25, 0), kChannelColours[c], 2, cv::LINE_AA);
    Label(&image, kChannelLabels[c], legend + cv::Point(32, 5), 0.45);
  }

  Label(&image, chart::Shorten("directional albedo: " + curve.source, 90), cv::Point(kLeft, 30),
        0.55);
  Label(&image, "theta (deg)", cv::Point(kWidth / 2 - 40, kHeight - 15));
  Label(&image, "albedo", cv::Point(8, kTop - 12));
  Label(&image, curve.verdict().name(), cv::Point(kLeft + 10, kTop + 25), 0.55);

  chart::WritePng(image, path);
}

}  // namespace brdf::cli
