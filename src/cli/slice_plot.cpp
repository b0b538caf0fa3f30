#include "cli/slice_plot.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>

#include "cli/chart.h"
#include "core/angles.h"
#include "core/colour.h"
#include "core/errors.h"
#include "core/text.h"

namespace brdf::cli {
namespace {

constexpr int kColumns = 3, kPanelWidth = 440, kPanelHeight = 330;
constexpr int kMarginTop = 60, kMarginBottom = 70;
constexpr int kPanelLeft = 62, kPanelRight = 14, kPanelTop = 28, kPanelBottom = 40;
constexpr double kThetaAxisDeg = 90.0;
// Lower end of the log axis at most this many decades below the largest value: a dark
// sample's noise floor would otherwise squash the lobe into the top of the panel.
constexpr double kMaxDecades = 6.0;
// Model curves are sampled every half degree of theta_o.
constexpr double kCurveStepDeg = 0.5;

// Every second curve is dashed, so that two models that coincide (blinn-phong and
// blinn-phong-exact away from grazing) both stay visible: the later, dashed one lets the
// earlier one's colour show through its gaps. Dashes of kDashOn points, gaps of kDashOff.
constexpr size_t kDashOn = 5, kDashOff = 7;
bool Dashed(size_t curve) { return curve % 2 == 1; }

void DrawCurve(cv::Mat* image, const std::vector<cv::Point>& line, const cv::Scalar& colour,
               bool dashed) {
  if (!dashed) {
    cv::polylines(*image, line, false, colour, 2, cv::LINE_AA);
    return;
  }
  for (size_t start = 0; start < line.size(); start += kDashOn + kDashOff) {
    const size_t end = std::min(line.size(), start + kDashOn + 1);
    const std::vector<cv::Point> dash(line.begin() + start, line.begin() + end);
    cv::polylines(*image, dash, false, colour, 2, cv::LINE_AA);
  }
}

double LuminanceSigma(const Rgb& sigma) {
  return std::sqrt(std::pow(kLuminanceWeights[0] * sigma[0], 2) +
                   std::pow(kLuminanceWeights[1] * sigma[1], 2) +
                   std::pow(kLuminanceWeights[2] * sigma[2], 2));
}

// The in-plane test and the signed detector angle of wo for incidence wi: the plane holds the
// normal and wi (the x-z plane at normal incidence).
bool InPlane(const Vec3& wi, const Vec3& wo, double* signed_theta_o_deg) {
  Vec3 horizontal(wi.x(), wi.y(), 0.0);
  if (horizontal.squaredNorm() < 1e-20) horizontal = Vec3(1, 0, 0);
  horizontal.normalize();
  const Vec3 plane_normal = Vec3(0, 0, 1).cross(horizontal);
  // Azimuth within the tolerance of the plane: |sin(phi_o - phi_i)| sin(theta_o) = |wo.n|.
  const double sin_theta_o = std::hypot(wo.x(), wo.y());
  if (std::abs(wo.dot(plane_normal)) > std::sin(DegToRad(kInPlaneToleranceDeg)) * sin_theta_o) {
    return false;
  }
  const double theta_o = RadToDeg(Theta(wo));
  *signed_theta_o_deg = wo.dot(horizontal) > 0 ? -theta_o : theta_o;
  return true;
}

// The incidence direction at theta (azimuth 0) and the in-plane detector at signed angle t.
Vec3 PanelIncidence(double theta_i_deg) { return SphericalDirection(DegToRad(theta_i_deg), 0); }
Vec3 PanelDetector(double signed_theta_o_deg) {
  return SphericalDirection(DegToRad(std::abs(signed_theta_o_deg)),
                            signed_theta_o_deg >= 0 ? kPi : 0.0);
}

struct LogAxis {
  double low = -1, high = 1;  // log10 bounds
};

class PanelArea {
 public:
  PanelArea(int column, int row, LogAxis axis) : axis_(axis) {
    x0_ = column * kPanelWidth + kPanelLeft;
    x1_ = (column + 1) * kPanelWidth - kPanelRight;
    y0_ = kMarginTop + row * kPanelHeight + kPanelTop;
    y1_ = kMarginTop + (row + 1) * kPanelHeight - kPanelBottom;
  }
  cv::Point At(double theta_deg, double value) const {
    const double u = (theta_deg + kThetaAxisDeg) / (2 * kThetaAxisDeg);
    const double v = (std::log10(std::max(value, 1e-300)) - axis_.low) / (axis_.high - axis_.low);
    const double y = y1_ - std::clamp(v, -0.02, 1.02) * (y1_ - y0_);
    return cv::Point(static_cast<int>(std::lround(x0_ + u * (x1_ - x0_))),
                     static_cast<int>(std::lround(y)));
  }
  int left() const { return x0_; }
  int right() const { return x1_; }
  int top() const { return y0_; }
  int bottom() const { return y1_; }

 private:
  LogAxis axis_;
  int x0_, x1_, y0_, y1_;
};

void DrawPanelFrame(cv::Mat* image, const PanelArea& area, const LogAxis& axis,
                    const SlicePanel& panel) {
  using chart::kLightGrey;
  for (double theta = -90; theta <= 90; theta += 30) {
    cv::line(*image, cv::Point(area.At(theta, 1).x, area.top()),
             cv::Point(area.At(theta, 1).x, area.bottom()), kLightGrey);
    chart::Label(image, chart::TickLabel(theta),
                 cv::Point(area.At(theta, 1).x - 10, area.bottom() + 16), 0.4);
  }
  for (double decade = std::ceil(axis.low); decade <= axis.high + 1e-9; decade += 1) {
    const int y = area.At(0, std::pow(10.0, decade)).y;
    cv::line(*image, cv::Point(area.left(), y), cv::Point(area.right(), y), kLightGrey);
    chart::Label(image, "1e" + chart::TickLabel(decade), cv::Point(area.left() - 50, y + 5), 0.4);
  }
  cv::rectangle(*image, cv::Point(area.left(), area.top()), cv::Point(area.right(), area.bottom()),
                chart::kBlack);
  std::string heading = "theta_i = " + FormatNumber(panel.theta_i_deg, 3) + " deg";
  if (panel.half_width_deg > 0) heading += " (+-" + FormatNumber(panel.half_width_deg, 2) + ")";
  heading += ", " + std::to_string(panel.points.size()) + " in-plane samples";
  chart::Label(image, heading, cv::Point(area.left(), area.top() - 8), 0.45);
}

}  // namespace

std::vector<SlicePanel> ExtractSlices(const Measurement& measurement, int max_panels) {
  struct Candidate {
    double theta_i_deg;
    SlicePoint point;
  };
  std::vector<Candidate> candidates;
  std::map<long long, int> distinct;  // theta_i in 1e-2 deg -> count
  for (size_t k = 0; k < measurement.samples.size(); ++k) {
    const Sample& sample = measurement.samples[k];
    if (sample.missing || !(sample.wi.z() > 0) || !(sample.wo.z() > 0)) continue;
    const double luminance = Luminance(sample.value);
    if (!std::isfinite(luminance)) continue;
    SlicePoint point;
    if (!InPlane(sample.wi, sample.wo, &point.theta_o_deg)) continue;
    point.luminance = luminance;
    point.sigma = measurement.has_sigma() ? LuminanceSigma(measurement.sigma[k]) : 0.0;
    const double theta_i_deg = RadToDeg(Theta(sample.wi));
    candidates.push_back({theta_i_deg, point});
    ++distinct[std::llround(theta_i_deg * 100)];
  }
  // Exact incidences (a schedule's), or bins of kIncidenceBinDeg (one incidence per sample).
  const bool binned = static_cast<int>(distinct.size()) > kMaxExactIncidences;
  std::map<long long, SlicePanel> groups;
  for (const Candidate& candidate : candidates) {
    const long long key = binned ? std::llround(candidate.theta_i_deg / kIncidenceBinDeg)
                                 : std::llround(candidate.theta_i_deg * 100);
    SlicePanel& panel = groups[key];
    panel.theta_i_deg += candidate.theta_i_deg;  // summed here, averaged below
    panel.points.push_back(candidate.point);
  }
  std::vector<SlicePanel> usable;
  for (auto& [key, panel] : groups) {
    if (panel.points.size() < 3) continue;
    panel.theta_i_deg /= static_cast<double>(panel.points.size());
    panel.half_width_deg = binned ? 0.5 * kIncidenceBinDeg : 0.0;
    std::sort(
        panel.points.begin(), panel.points.end(),
        [](const SlicePoint& a, const SlicePoint& b) { return a.theta_o_deg < b.theta_o_deg; });
    usable.push_back(std::move(panel));
  }
  if (static_cast<int>(usable.size()) <= max_panels) return usable;
  std::vector<SlicePanel> chosen;
  for (int p = 0; p < max_panels; ++p) {
    const size_t index = static_cast<size_t>(
        std::lround(p * (usable.size() - 1) / static_cast<double>(max_panels - 1)));
    chosen.push_back(usable[index]);
  }
  return chosen;
}

void WriteSlicePlot(const Measurement& measurement, const std::vector<SliceCurve>& curves,
                    const std::string& title, const std::string& path) {
  const std::vector<SlicePanel> panels = ExtractSlices(measurement, 2 * kColumns);
  if (panels.empty()) {
    throw InputError(measurement.source,
                     "no incidence has three samples within " + FormatNumber(kInPlaneToleranceDeg) +
                         " deg of azimuth of its plane of incidence: nothing to draw a slice of");
  }
  // Curves first: their values set the axis together with the data.
  std::vector<std::vector<std::vector<std::pair<double, double>>>> curve_points(panels.size());
  double high = 0;
  std::vector<double> positives;
  for (size_t p = 0; p < panels.size(); ++p) {
    const Vec3 wi = PanelIncidence(panels[p].theta_i_deg);
    for (const SliceCurve& curve : curves) {
      std::vector<std::pair<double, double>> line;
      for (double t = -89; t <= 89 + 1e-9; t += kCurveStepDeg) {
        const double value = Luminance(curve.brdf(wi, PanelDetector(t)));
        if (std::isfinite(value) && value > 0) {
          line.emplace_back(t, value);
          high = std::max(high, value);
          positives.push_back(value);
        }
      }
      curve_points[p].push_back(std::move(line));
    }
    for (const SlicePoint& point : panels[p].points) {
      if (point.luminance > 0) {
        high = std::max(high, point.luminance + point.sigma);
        positives.push_back(point.luminance);
      }
    }
  }
  LogAxis axis;
  if (high > 0) {
    const double low = *std::min_element(positives.begin(), positives.end());
    axis.high = std::ceil(std::log10(high) + 1e-9);
    axis.low = std::max(std::floor(std::log10(low)), axis.high - kMaxDecades);
    if (axis.low >= axis.high) axis.low = axis.high - 1;
  }

  const int rows = static_cast<int>((panels.size() + kColumns - 1) / kColumns);
  cv::Mat image(kMarginTop + rows * kPanelHeight + kMarginBottom, kColumns * kPanelWidth, CV_8UC3,
                chart::kWhite);
  for (size_t p = 0; p < panels.size(); ++p) {
    const PanelArea area(static_cast<int>(p % kColumns), static_cast<int>(p / kColumns), axis);
    DrawPanelFrame(&image, area, axis, panels[p]);
    for (size_t c = 0; c < curves.size(); ++c) {
      std::vector<cv::Point> line;
      for (const auto& [t, value] : curve_points[p][c]) line.push_back(area.At(t, value));
      DrawCurve(&image, line, chart::kCurveColours[c % 6], Dashed(c));
    }
    for (const SlicePoint& point : panels[p].points) {
      if (!(point.luminance > 0)) continue;
      const cv::Point centre = area.At(point.theta_o_deg, point.luminance);
      if (point.sigma > 0) {
        cv::line(image, area.At(point.theta_o_deg, point.luminance + point.sigma),
                 area.At(point.theta_o_deg,
                         std::max(point.luminance - point.sigma, std::pow(10.0, axis.low - 1))),
                 chart::kGrey, 1);
      }
      cv::circle(image, centre, 2, chart::kBlack, cv::FILLED, cv::LINE_AA);
    }
  }
  chart::Label(&image, chart::Shorten(title, 120), cv::Point(kPanelLeft, 30), 0.6);
  const int legend_y = image.rows - kMarginBottom + 30;
  cv::circle(image, cv::Point(kPanelLeft, legend_y - 4), 3, chart::kBlack, cv::FILLED);
  chart::Label(&image, "measured (+- sigma)", cv::Point(kPanelLeft + 10, legend_y), 0.45);
  int x = kPanelLeft + 190;
  for (size_t c = 0; c < curves.size(); ++c) {
    std::vector<cv::Point> sample;
    for (int dx = 0; dx <= 25; dx += 2) sample.emplace_back(x + dx, legend_y - 4);
    DrawCurve(&image, sample, chart::kCurveColours[c % 6], Dashed(c));
    const std::string label = chart::Shorten(curves[c].label, 60);
    chart::Label(&image, label, cv::Point(x + 32, legend_y), 0.45);
    x += 45 + 9 * static_cast<int>(label.size());
  }
  chart::Label(&image,
               "luminance Y of f (sr^-1, log) against signed theta_o (deg, > 0 on the mirror "
               "side); samples within " +
                   FormatNumber(kInPlaneToleranceDeg) + " deg of azimuth of the plane of incidence",
               cv::Point(kPanelLeft, legend_y + 25), 0.42);
  chart::WritePng(image, path);
}

}  // namespace brdf::cli
