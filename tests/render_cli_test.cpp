// `brdf render` end to end: models, fit reports and measurements become PNG and EXR; bad
// input exits 2 with one line naming the culprit and leaves nothing behind.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "hdr/image_files.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::DataPath;
using testing::RunBrdf;
using testing::ScratchDir;

TEST(RenderCli, HelpDocumentsEveryOptionWithItsDefault) {
  for (const char* command : {"render", "tonemap"}) {
    const testing::CommandResult result = RunBrdf(std::string(command) + " --help");
    ASSERT_EQ(result.exit_status, 0) << command;
    for (const char* option :
         {"--operator", "--exposure", "--ev", "--key", "--white", "--bloom", "--bloom-threshold",
          "--bloom-strength", "--bloom-sigma", "--gamma", "--out"}) {
      EXPECT_NE(result.out.find(option), std::string::npos) << command << " " << option;
    }
    EXPECT_NE(result.out.find("reinhard-extended"), std::string::npos) << command;
    EXPECT_NE(result.out.find("0.18"), std::string::npos) << command;
  }
  const std::string render = RunBrdf("render --help").out;
  for (const char* option : {"--light", "--preset", "--env", "--size", "--spp", "--seed", "--exr",
                             "100000 lx", "512", "64"}) {
    EXPECT_NE(render.find(option), std::string::npos) << option;
  }
}

TEST(RenderCli, ModelUnderPresetAndEnvironmentWritesPngAndExr) {
  ScratchDir dir;
  const testing::CommandResult result =
      RunBrdf("render 'blinn-phong:rho_d=0.5,0.1,0.1:rho_s=0.04:m=200' --preset sunny --env '" +
              DataPath("hdr/venice_sunset_1k.hdr") + "' --size 64 --spp 8 --bloom dual --out '" +
              dir.File("a.png") + "' --exr '" + dir.File("a.exr") + "' --quiet");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const cv::Mat png = cv::imread(dir.File("a.png"), cv::IMREAD_COLOR);
  ASSERT_EQ(png.rows, 64);
  const Image exr = ReadExr(dir.File("a.exr"));
  ASSERT_EQ(exr.width, 64);
  // Radiometric units: a diffuse albedo of 0.5 under 20 000 lx (29 W/m^2 at 683 lm/W) gives
  // about 0.5/pi * 29 ~ 4.7 W/m^2/sr where the light falls square on.
  float largest = 0.0f;
  for (int64_t i = 0; i < exr.pixel_count(); ++i) largest = std::max(largest, exr.rgba[i * 4]);
  EXPECT_GT(largest, 3.0f);
  EXPECT_LT(largest, 100.0f);
  EXPECT_EQ(exr.pixel(0, 0)[3], 0.0f);    // background
  EXPECT_EQ(exr.pixel(32, 32)[3], 1.0f);  // sphere
  EXPECT_EQ(dir.CountEntries(), 2);
}

// The summary gives luminance with its unit and in cd/m² beside it: a Lambertian of albedo rho
// under E lux at normal incidence has L = rho E / pi, which is the sphere's brightest pixel.
TEST(RenderCli, SummaryGivesLuminanceInWattsAndNits) {
  ScratchDir dir;
  const testing::CommandResult result =
      RunBrdf("render lambert:rho_d=0.5 --preset office --size 64 --spp 4 --out '" +
              dir.File("o.png") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const size_t max = result.out.find("max ");
  ASSERT_NE(max, std::string::npos) << result.out;
  const size_t equals = result.out.find(" W/(m^2 sr) = ", max);
  ASSERT_NE(equals, std::string::npos) << result.out;
  const double nits = std::stod(result.out.substr(equals + 14));
  EXPECT_NE(result.out.find("cd/m^2", equals), std::string::npos);
  const double expected = 0.5 * 500.0 / 3.14159265358979;  // office: 500 lx
  EXPECT_NEAR(nits, expected, 0.01 * expected) << result.out;
}

TEST(RenderCli, MeasurementsRenderThroughInterpolation) {
  ScratchDir dir;
  const testing::CommandResult result =
      RunBrdf("render '" + DataPath("cornell-astm/cayman.astm") + "' --size 48 --out '" +
              dir.File("c.png") + "' --quiet");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  EXPECT_FALSE(cv::imread(dir.File("c.png")).empty());
}

TEST(RenderCli, BadInputExitsTwoWithOneLineNamingTheCulprit) {
  ScratchDir dir;
  const std::string out = dir.File("out.png");
  const std::string broken_env = dir.Write("broken.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"lambert --size 0", "--size"},
      {"lambert --size -5", "--size"},
      {"lambert --spp 0", "--spp"},
      {"'" + dir.File("missing.binary") + "'", dir.File("missing.binary")},
      {"lambert --env '" + dir.File("missing.exr") + "'", dir.File("missing.exr")},
      {"lambert --env '" + broken_env + "'", broken_env},
      {"lambert --light dir:theta=10:lumens=4", "dir:theta=10:lumens=4"},
      {"lambert --preset disco", "disco"},
  };
  for (const auto& [arguments, culprit] : cases) {
    const testing::CommandResult result = RunBrdf("render " + arguments + " --out '" + out + "'");
    EXPECT_EQ(result.exit_status, 2) << arguments;
    EXPECT_EQ(testing::CountLines(result.err), 1) << arguments << ": " << result.err;
    EXPECT_NE(result.err.find(culprit), std::string::npos) << arguments << ": " << result.err;
  }
  EXPECT_EQ(dir.CountEntries(), 1);  // only the broken input
}

}  // namespace
}  // namespace brdf

namespace brdf {
namespace {

TEST(RenderCli, VersusSheetShowsTheRelativeError) {
  ScratchDir dir;
  // Twice the albedo: |A - B| / B = 1 on every pixel; the light comes from the viewer, so
  // every sphere pixel is lit.
  const testing::CommandResult result = RunBrdf(
      "render lambert:rho_d=0.5 --vs lambert:rho_d=0.25 --light dir:theta=0:lux=1000 "
      "--size 80 --out '" +
      dir.File("sheet.png") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  EXPECT_NE(result.out.find("median 1, 90th percentile 1, 99th percentile 1, max 1"),
            std::string::npos)
      << result.out;
  const cv::Mat sheet = cv::imread(dir.File("sheet.png"), cv::IMREAD_COLOR);
  ASSERT_FALSE(sheet.empty());
  EXPECT_GT(sheet.cols, 3 * 80);  // A, B, error map, colour bar
  EXPECT_GT(sheet.rows, 80);      // plus the label row
  // A is brighter than B at the same place: one tone mapping for both.
  const int row = sheet.rows - 40, column = 40;
  EXPECT_GT(cv::sum(sheet.at<cv::Vec3b>(row, column))[0],
            cv::sum(sheet.at<cv::Vec3b>(row, column + 80))[0]);

  const testing::CommandResult same =
      RunBrdf("render phong --vs phong --size 40 --quiet --out '" + dir.File("same.png") + "'");
  EXPECT_EQ(same.exit_status, 0) << same.err;
}

}  // namespace
}  // namespace brdf

namespace brdf {
namespace {

TEST(RenderCli, OutputNamesMustMatchTheFormatWritten) {
  ScratchDir dir;
  for (const std::string& out : {dir.File("sphere.jpg"), dir.File("sphere")}) {
    const testing::CommandResult result = RunBrdf("render lambert --size 16 --out '" + out + "'");
    EXPECT_EQ(result.exit_status, 2) << out;
    EXPECT_NE(result.err.find(out + ": the file written is PNG; name it *.png"), std::string::npos)
        << result.err;
  }
  const testing::CommandResult exr =
      RunBrdf("render lambert --size 16 --exr '" + dir.File("s.png") + "' --out '" +
              dir.File("s.png") + "'");
  EXPECT_EQ(exr.exit_status, 2);
  EXPECT_NE(exr.err.find("--exr"), std::string::npos) << exr.err;
  EXPECT_EQ(dir.CountEntries(), 0);  // nothing written
  // Any case of the right extension is fine, and so is tonemap's.
  EXPECT_EQ(
      RunBrdf("render lambert --size 16 --quiet --out '" + dir.File("S.PNG") + "'").exit_status, 0);
  const testing::CommandResult tonemap = RunBrdf("tonemap '" + DataPath("hdr/memorial.hdr") +
                                                 "' --out '" + dir.File("memorial.jpg") + "'");
  EXPECT_EQ(tonemap.exit_status, 2);
  EXPECT_NE(tonemap.err.find("name it *.png"), std::string::npos) << tonemap.err;
}

TEST(RenderCli, WarnsOnAMaterialThatCreatesEnergyAndOnlyThen) {
  ScratchDir dir;
  const std::string out = " --size 16 --spp 2 --quiet --out '" + dir.File("s.png") + "'";
  // Diffuse albedo 1.5 reflects half as much again as it receives.
  const testing::CommandResult bright = RunBrdf("render 'ggx:rho_d=1.5:f0=0.04:alpha=0.2'" + out);
  EXPECT_EQ(bright.exit_status, 0) << bright.err;
  EXPECT_NE(bright.err.find("reflects more light than it receives"), std::string::npos)
      << bright.err;
  // The same against a conserving one, in either place of --vs.
  const testing::CommandResult versus =
      RunBrdf("render 'ggx:rho_d=0.5:f0=0.04:alpha=0.2' --vs 'lambert:rho_d=1.2'" + out);
  EXPECT_NE(versus.err.find("lambert:rho_d=1.2 reflects more"), std::string::npos) << versus.err;
  EXPECT_EQ(versus.err.find("ggx:rho_d=0.5:f0=0.04:alpha=0.2 reflects"), std::string::npos);
  // A conserving material: silent.
  const testing::CommandResult fine = RunBrdf("render 'ggx:rho_d=0.5:f0=0.04:alpha=0.2'" + out);
  EXPECT_EQ(fine.exit_status, 0);
  EXPECT_EQ(fine.err, "");
}

}  // namespace
}  // namespace brdf
