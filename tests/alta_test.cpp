// ALTA data text (io/alta.cpp) against the real CEA retro-reflection files in data/alta-retro/:
// one row converted by hand, the header, and the parameterizations it refuses.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/angles.h"
#include "core/errors.h"
#include "io/formats.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::DataPath;
using testing::RunBrdf;
using testing::ScratchDir;

const char* const kYellow = "alta-retro/retro-3M-jaune.dat";

// Line 2000 of retro-3M-jaune.dat (the 1993rd data row, after 7 header lines):
//   0.26179938779914940782944654529274  0.23706318621610644736819040190312
//   -0.02491292719488907153602141875126  6.31752021563342314180999892414548
// By hand: theta_l = 0.2617994 rad = 15 deg, so wi = (sin 15, 0, cos 15) = (0.2588190, 0,
// 0.9659258). theta_v = sqrt(0.2370632^2 + 0.0249129^2) = sqrt(0.0561989 + 0.0006207) =
// 0.2383686 rad (13.658 deg); dphi = atan2(-0.0249129, 0.2370632) = -0.1047055 rad (-5.999
// deg); wo = (sin 13.658 cos 5.999, -sin 13.658 sin 5.999, cos 13.658) = (0.2348246,
// -0.0246777, 0.9717245). The output is f cos(theta_v): f = 6.3175202 / 0.9717245 = 6.501349.
TEST(Alta, ARowConvertedByHand) {
  const Measurement measurement = ReadMeasurement(DataPath(kYellow));
  EXPECT_EQ(measurement.format, "alta");
  ASSERT_EQ(measurement.samples.size(), 7397u);
  const Sample& sample = measurement.samples[1992];
  EXPECT_NEAR(sample.wi.x(), 0.2588190, 1e-7);
  EXPECT_NEAR(sample.wi.y(), 0.0, 1e-12);
  EXPECT_NEAR(sample.wi.z(), 0.9659258, 1e-7);
  EXPECT_NEAR(sample.wo.x(), 0.2348246, 1e-7);
  EXPECT_NEAR(sample.wo.y(), -0.0246777, 1e-7);
  EXPECT_NEAR(sample.wo.z(), 0.9717245, 1e-7);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sample.value[c], 6.501349, 1e-6);
  EXPECT_FALSE(sample.missing);
  EXPECT_EQ(measurement.metadata.at("sample"), "3M Yellow");
  EXPECT_EQ(measurement.tabulated, nullptr);  // sparse rows: scattered interpolation
}

// The 86 rows at theta_v = 90 deg give f cos(theta_v) with cos = 0: f is undefined there.
TEST(Alta, RowsAtTheHorizonAreMissing) {
  const Measurement measurement = ReadMeasurement(DataPath(kYellow));
  const MeasurementSummary summary = Summarize(measurement);
  EXPECT_EQ(summary.missing, 86u);
  EXPECT_EQ(summary.incidence_directions, 3u);  // 15, 30 and 60 deg
  EXPECT_NEAR(summary.theta_i_deg[0], 15.0, 1e-3);
  EXPECT_NEAR(summary.theta_i_deg[1], 60.0, 1e-3);
}

TEST(Alta, UnsupportedParameterizationsNameTheLine) {
  ScratchDir dir;
  const std::string header = "#DIM 3 1\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n";
  struct Case {
    std::string name, text, line, says;
  } cases[] = {
      {"in.dat", "#DIM 3 1\n#PARAM_IN RUSIN_TH_TD_PD\n#PARAM_OUT INV_STERADIAN\n0 0 0 1\n",
       "line 2", "#PARAM_IN RUSIN_TH_TD_PD is not supported"},
      {"out.dat", header + "#PARAM_OUT ENERGY\n0.1 0.2 0 1\n", "line 3",
       "#PARAM_OUT ENERGY is not supported"},
      {"dim.dat", "#DIM 4 1\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n", "line 1",
       "#DIM input count 4"},
      {"vs.dat", header + "#VS 2\n", "line 3", "confidence columns"},
      {"short.dat", header + "#PARAM_OUT INV_STERADIAN\n0.1 0.2 0\n", "line 4",
       "expected 4 values"},
      {"beyond.dat", header + "#PARAM_OUT INV_STERADIAN\n0.1 1.5 0.5 1\n", "line 4",
       "beyond the horizon"},
      {"nan.dat", header + "#PARAM_OUT INV_STERADIAN\n0.1 0.2 0 nan\n", "line 4", "BRDF value"},
  };
  for (const Case& c : cases) {
    const std::string path = dir.Write(c.name, c.text);
    const testing::CommandResult result = RunBrdf("info '" + path + "'");
    EXPECT_EQ(result.exit_status, 2) << c.name << "\n" << result.err;
    EXPECT_EQ(testing::CountLines(result.err), 1) << result.err;
    EXPECT_NE(result.err.find(path + ": " + c.line + ":"), std::string::npos) << result.err;
    EXPECT_NE(result.err.find(c.says), std::string::npos) << c.name << "\n" << result.err;
  }
}

// INV_STERADIAN rows are f already; three outputs are r, g, b.
TEST(Alta, InvSteradianWithThreeChannels) {
  ScratchDir dir;
  const std::string path =
      dir.Write("rgb.dat",
                "#DIM 3 3\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n#PARAM_OUT INV_STERADIAN\n"
                "0.5 0 0.5 0.1 0.2 0.3\n");
  const Measurement measurement = ReadMeasurement(path);
  ASSERT_EQ(measurement.samples.size(), 1u);
  const Sample& sample = measurement.samples[0];
  EXPECT_NEAR(Theta(sample.wo), 0.5, 1e-12);
  EXPECT_NEAR(Phi(sample.wo), 0.5 * kPi, 1e-12);  // dphi = atan2(0.5, 0)
  EXPECT_DOUBLE_EQ(sample.value[0], 0.1);
  EXPECT_DOUBLE_EQ(sample.value[1], 0.2);
  EXPECT_DOUBLE_EQ(sample.value[2], 0.3);
}

}  // namespace
}  // namespace brdf
