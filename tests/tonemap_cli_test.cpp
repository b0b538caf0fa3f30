// `brdf tonemap` end to end: real HDR photographs in, 8-bit PNG out; bad input exits 2 with
// one line naming the file and leaves no output; NaN/Inf pixels are counted and kept out of
// the picture.
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

int CountLinesOf(const std::string& text) { return testing::CountLines(text); }

TEST(TonemapCli, RealPhotographsBecomePngs) {
  ScratchDir dir;
  for (const char* name : {"memorial.hdr", "memorial.exr", "venice_sunset_1k.hdr"}) {
    for (const char* options : {"", "--operator reinhard --bloom dual",
                                "--operator exposure --ev -1 --bloom gauss --gamma 2.2"}) {
      const std::string out = dir.File("out.png");
      const testing::CommandResult result = RunBrdf(
          "tonemap '" + DataPath(std::string("hdr/") + name) + "' --out '" + out + "' " + options);
      ASSERT_EQ(result.exit_status, 0) << name << " " << options << ": " << result.err;
      const cv::Mat png = cv::imread(out, cv::IMREAD_COLOR);
      ASSERT_FALSE(png.empty());
      // Not black, not white: the median grey of a tone-mapped photograph is mid-range.
      const double mean = cv::mean(png)[0] + cv::mean(png)[1] + cv::mean(png)[2];
      EXPECT_GT(mean / 3, 20.0) << name << " " << options;
      EXPECT_LT(mean / 3, 235.0) << name << " " << options;
    }
  }
}

TEST(TonemapCli, BadInputExitsTwoWithOneLineNamingTheFile) {
  ScratchDir dir;
  const std::string out = dir.File("out.png");
  const std::vector<std::string> inputs = {
      dir.File("missing.exr"),
      dir.Write("garbage.exr", "not an image at all"),
      dir.Write("cut.exr", testing::ReadFileText(DataPath("hdr/memorial.exr")).substr(0, 5000)),
      dir.Write("cut.hdr", testing::ReadFileText(DataPath("hdr/memorial.hdr")).substr(0, 5000)),
      dir.Write("header.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 0 +X 0\n"),
  };
  for (const std::string& input : inputs) {
    const testing::CommandResult result = RunBrdf("tonemap '" + input + "' --out '" + out + "'");
    EXPECT_EQ(result.exit_status, 2) << input;
    EXPECT_EQ(CountLinesOf(result.err), 1) << result.err;
    EXPECT_NE(result.err.find(input), std::string::npos) << result.err;
  }
  EXPECT_EQ(dir.CountEntries(), 4);  // the inputs only: no PNG, no temporary
  EXPECT_EQ(
      RunBrdf("tonemap '" + DataPath("hdr/memorial.hdr") + "' --out '" + out + "' --bloom-sigma -3")
          .exit_status,
      2);
  EXPECT_EQ(RunBrdf("tonemap '" + DataPath("hdr/memorial.hdr") + "' --out '" + out +
                    "' --exposure 2 --ev 1")
                .exit_status,
            2);
}

TEST(TonemapCli, NonFinitePixelsAreCountedAndNotPropagated) {
  ScratchDir dir;
  Image image(8, 8);
  for (int64_t i = 0; i < image.pixel_count(); ++i) {
    for (int c = 0; c < 3; ++c) image.rgba[i * 4 + c] = 0.5f;
  }
  image.pixel(1, 1)[0] = std::nanf("");
  image.pixel(2, 5)[1] = INFINITY;
  image.pixel(7, 7)[2] = -INFINITY;
  const std::string input = dir.File("broken.exr");
  WriteExr(input, image, ExrPixelType::kFloat);
  const testing::CommandResult result =
      RunBrdf("tonemap '" + input + "' --out '" + dir.File("out.png") + "' --operator reinhard");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  EXPECT_NE(result.err.find("3 pixels"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find(input), std::string::npos) << result.err;
  const cv::Mat png = cv::imread(dir.File("out.png"), cv::IMREAD_COLOR);
  ASSERT_EQ(png.rows, 8);
  // The replaced pixels are black; every other pixel is the same mid grey.
  EXPECT_EQ(png.at<cv::Vec3b>(1, 1), cv::Vec3b(0, 0, 0));
  const cv::Vec3b grey = png.at<cv::Vec3b>(0, 0);
  EXPECT_GT(grey[0], 50);
  EXPECT_EQ(grey[0], grey[1]);
  EXPECT_EQ(png.at<cv::Vec3b>(4, 4), grey);
}

TEST(TonemapCli, BlackPixelsThatMoveTheExposureAreReported) {
  // Half the image black: the log-average is sqrt(1e-4 x 0.5), so the automatic exposure is
  // (0.5 / 1e-4)^(1/2) = 70.7 times what the lit half alone would get.
  ScratchDir dir;
  Image image(8, 8);
  for (int64_t i = 0; i < image.pixel_count() / 2; ++i) {
    for (int c = 0; c < 3; ++c) image.rgba[i * 4 + c] = 0.5f;
  }
  const std::string input = dir.File("half-black.exr");
  WriteExr(input, image, ExrPixelType::kFloat);
  const testing::CommandResult result =
      RunBrdf("tonemap '" + input + "' --out '" + dir.File("out.png") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  EXPECT_NE(result.err.find("32 of 64 pixels"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("70.7x"), std::string::npos) << result.err;
  // A chosen exposure is the user's: nothing to warn about.
  const testing::CommandResult fixed =
      RunBrdf("tonemap '" + input + "' --out '" + dir.File("fixed.png") + "' --exposure 1");
  ASSERT_EQ(fixed.exit_status, 0) << fixed.err;
  EXPECT_EQ(fixed.err.find("black"), std::string::npos) << fixed.err;
}

}  // namespace
}  // namespace brdf
