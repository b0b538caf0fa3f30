// The plane-of-incidence slice chart (src/cli/slice_plot.h): which samples it takes, where it
// puts them, and the PNG it writes.
#include "cli/slice_plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <set>

#include "cli/chart.h"
#include "core/angles.h"
#include "core/colour.h"
#include "core/errors.h"
#include "gonio/measure.h"
#include "gonio/schedule.h"
#include "gonio_test_util.h"
#include "models/model_string.h"
#include "test_util.h"

namespace brdf::cli {
namespace {

Measurement MeasureIdeal(const std::string& sample, const std::string& schedule) {
  gonio::MeasureOptions options;
  options.sample = sample;
  options.instrument = gonio::testing::IdealInstrument();
  return gonio::Measure(options, gonio::MakeSchedule(schedule));
}

// The 5 deg hemisphere schedule has phi_o = 0 and 180 among its azimuths: every incidence's
// in-plane samples are the detectors at those two azimuths, counted here from the schedule
// itself, less those the detector arm shadows. A Lambertian's points all read Y(rho)/pi.
TEST(SlicePlot, HemisphereSlicesHoldTheInPlaneDetectorsAtTheirValue) {
  const Measurement measurement = MeasureIdeal("model:lambert:rho_d=0.6,0.45,0.3", "hemisphere");
  const gonio::Schedule schedule = gonio::MakeSchedule("hemisphere");
  const std::vector<SlicePanel> panels = ExtractSlices(measurement, 100);
  std::set<long long> thetas;
  for (const gonio::Incidence& incidence : schedule.incidences) {
    thetas.insert(std::llround(RadToDeg(Theta(incidence.wi)) * 100));
  }
  ASSERT_EQ(panels.size(), thetas.size());
  const double expected = Luminance(Rgb(0.6, 0.45, 0.3)) * kInvPi;
  for (const SlicePanel& panel : panels) {
    size_t in_plane = 0;
    for (const gonio::Incidence& incidence : schedule.incidences) {
      if (std::abs(RadToDeg(Theta(incidence.wi)) - panel.theta_i_deg) > 1e-6) continue;
      for (const gonio::Detector& detector : incidence.detectors) {
        const bool blocked = incidence.wi.dot(detector.wo) > std::cos(DegToRad(2.0));
        if (!blocked && std::abs(detector.wo.y()) < 1e-9 && detector.wo.z() > 0) ++in_plane;
      }
    }
    EXPECT_EQ(panel.points.size(), in_plane) << "theta_i " << panel.theta_i_deg;
    EXPECT_EQ(panel.half_width_deg, 0.0);
    for (const SlicePoint& point : panel.points) {
      EXPECT_NEAR(point.luminance, expected, 1e-9 * expected);
      EXPECT_LE(std::abs(point.theta_o_deg), 90.0);
    }
  }
}

// The signed angle is positive on the mirror side: a glossy sample's brightest in-plane point
// sits at theta_o = +theta_i in every panel.
TEST(SlicePlot, TheLobePeaksAtPlusThetaI) {
  const Measurement measurement =
      MeasureIdeal("model:blinn-phong:rho_d=0.1:rho_s=0.5:m=200", "inplane:step=5");
  const std::vector<SlicePanel> panels = ExtractSlices(measurement, 6);
  ASSERT_EQ(panels.size(), 6u);  // spread over the incidences, not the first six
  EXPECT_GT(panels.back().theta_i_deg - panels.front().theta_i_deg, 60.0);
  for (const SlicePanel& panel : panels) {
    if (panel.theta_i_deg < 4) continue;  // at normal incidence the peak is the blocked one
    const SlicePoint* brightest = &panel.points.front();
    for (const SlicePoint& point : panel.points) {
      if (point.luminance > brightest->luminance) brightest = &point;
    }
    EXPECT_NEAR(brightest->theta_o_deg, panel.theta_i_deg, 2.6) << panel.theta_i_deg;
  }
}

// Image-based data have one incidence per pixel: they are binned, and the bins say so.
TEST(SlicePlot, ImageBasedIncidencesAreBinned) {
  const Measurement measurement =
      MeasureIdeal("sphere:blinn-phong:rho_d=0.2:rho_s=0.1:m=50", "inplane:step=30");
  const std::vector<SlicePanel> panels = ExtractSlices(measurement, 6);
  ASSERT_FALSE(panels.empty());
  for (const SlicePanel& panel : panels) {
    EXPECT_EQ(panel.half_width_deg, 0.5 * kIncidenceBinDeg);
    EXPECT_GE(panel.points.size(), 3u);
  }
}

TEST(SlicePlot, WritesAPngAndRefusesDataWithNothingInPlane) {
  const Measurement measurement =
      MeasureIdeal("model:blinn-phong:rho_d=0.1:rho_s=0.5:m=200", "inplane:step=10");
  const Model model = ParseModel("blinn-phong:rho_d=0.1:rho_s=0.5:m=200");
  const brdf::testing::ScratchDir scratch;
  const std::string path = scratch.File("slices.png");
  WriteSlicePlot(measurement,
                 {{"truth", [&](const Vec3& wi, const Vec3& wo) { return model.Eval(wi, wo); }}},
                 "test", path);
  const cv::Mat image = cv::imread(path);
  ASSERT_FALSE(image.empty());
  EXPECT_GT(image.cols, 1000);

  Measurement off_plane;
  off_plane.source = "off-plane.csv";
  for (int k = 0; k < 10; ++k) {
    off_plane.samples.push_back({SphericalDirection(DegToRad(30), 0),
                                 SphericalDirection(DegToRad(10 + 5 * k), DegToRad(90)),
                                 Rgb::Constant(0.1), false});
  }
  try {
    WriteSlicePlot(off_plane, {}, "test", scratch.File("none.png"));
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("off-plane.csv"), std::string::npos);
  }
}

// `brdf fit --plot` on a real file: the chart is written whole and the fit report is unchanged.
TEST(SlicePlot, FitPlotWritesTheChartOfARealFile) {
  const brdf::testing::ScratchDir scratch;
  const std::string png = scratch.File("cayman-slices.png");
  const brdf::testing::CommandResult result =
      brdf::testing::RunBrdf("fit '" + brdf::testing::DataPath("cornell-astm/cayman.astm") +
                             "' --model lambert --plot '" + png + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const cv::Mat image = cv::imread(png);
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(scratch.CountEntries(), 1);  // no temporary left beside it
}

}  // namespace
}  // namespace brdf::cli

namespace brdf::cli {
namespace {

int64_t PixelsOfColour(const cv::Mat& image, const cv::Scalar& colour) {
  int64_t count = 0;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b pixel = image.at<cv::Vec3b>(y, x);
      count += pixel[0] == colour[0] && pixel[1] == colour[1] && pixel[2] == colour[2];
    }
  }
  return count;
}

// Two models that coincide (blinn-phong and blinn-phong-exact on this lobe) must both show:
// the second curve is dashed, so the first one's colour stays visible through its gaps.
TEST(SlicePlot, ACurveUnderAnIdenticalOneStaysVisible) {
  const Measurement measurement =
      MeasureIdeal("model:blinn-phong:rho_d=0.1:rho_s=0.5:m=200", "inplane:step=10");
  const Model model = ParseModel("blinn-phong:rho_d=0.1:rho_s=0.5:m=200");
  const SliceCurve curve{"blinn-phong",
                         [&](const Vec3& wi, const Vec3& wo) { return model.Eval(wi, wo); }};
  const brdf::testing::ScratchDir scratch;
  WriteSlicePlot(measurement, {curve}, "alone", scratch.File("alone.png"));
  WriteSlicePlot(measurement, {curve, curve}, "both", scratch.File("both.png"));
  const cv::Mat alone = cv::imread(scratch.File("alone.png"));
  const cv::Mat both = cv::imread(scratch.File("both.png"));
  const int64_t first_alone = PixelsOfColour(alone, chart::kCurveColours[0]);
  const int64_t first_under = PixelsOfColour(both, chart::kCurveColours[0]);
  const int64_t second = PixelsOfColour(both, chart::kCurveColours[1]);
  ASSERT_GT(first_alone, 1000);
  // About half of the first curve shows through the gaps, and the second is drawn too.
  EXPECT_GT(first_under, first_alone / 4) << first_under << " of " << first_alone;
  EXPECT_LT(first_under, first_alone);
  EXPECT_GT(second, first_alone / 4);
}

}  // namespace
}  // namespace brdf::cli
