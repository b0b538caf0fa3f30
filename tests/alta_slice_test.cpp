// The BRDF slice image (io/alta_slice.cpp) against the real file in data/merl-derived/: cells
// converted by hand (pixel values read with OpenEXR outside brdfkit), the pixel-to-cell mapping
// checked through the HDR pipeline's independent EXR reader, and images that are not slices.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/angles.h"
#include "core/errors.h"
#include "hdr/image_files.h"
#include "io/formats.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::DataPath;
using testing::RunBrdf;
using testing::ScratchDir;

const char* const kSlice = "merl-derived/red-fabric_stark2d_slice.exr";
constexpr int kCells = 512;

TEST(AltaSlice, DetectedAndCounted) {
  const Measurement m = ReadMeasurement(DataPath(kSlice));
  EXPECT_EQ(m.format, "alta-slice");
  ASSERT_EQ(m.samples.size(), 512u * 512u);
  const MeasurementSummary summary = Summarize(m);
  EXPECT_EQ(summary.missing, 0u);
  EXPECT_EQ(summary.nan, 0u);
  EXPECT_EQ(summary.negative, 0u);
  EXPECT_NE(m.metadata.at("parameterization").find("ASSUMED"), std::string::npos);
  EXPECT_NE(m.metadata.at("units").find("sr^-1"), std::string::npos);
  EXPECT_EQ(m.tabulated, nullptr);  // one slice of the BRDF: no evaluator for all (wi, wo)
}

// Pixel (x = 100, y = 50) of the image (y = 0 the top scan line) holds, read with OpenEXR's
// InputFile: R 0.364501953, G 0.170898438, B 0.178222656. Its cell: theta_h = 100.5/512 * 90 =
// 17.666016 deg, theta_d = (511 - 50 + 0.5)/512 * 90 = 81.123047 deg, phi_d = 90 deg, so
// wi = (sin th cos td, sin td, cos th cos td) = (0.0468290, 0.9880220, 0.1470358) and wo the same
// with y negated. Pixel (0, 511), the bottom-left corner, is the cell nearest normal incidence
// and mirror reflection (theta_h = theta_d = 0.087891 deg): R 0.0881347656, G 0.0169525146,
// B 0.0109710693, wi = (0.0015340, 0.0015340, 0.9999976).
TEST(AltaSlice, CellsConvertedByHand) {
  const Measurement m = ReadMeasurement(DataPath(kSlice));
  const Sample& grazing = m.samples.at(50 * kCells + 100);
  EXPECT_NEAR(grazing.wi.x(), 0.0468290, 1e-7);
  EXPECT_NEAR(grazing.wi.y(), 0.9880220, 1e-7);
  EXPECT_NEAR(grazing.wi.z(), 0.1470358, 1e-7);
  EXPECT_NEAR(grazing.wo.x(), 0.0468290, 1e-7);
  EXPECT_NEAR(grazing.wo.y(), -0.9880220, 1e-7);
  EXPECT_NEAR(grazing.wo.z(), 0.1470358, 1e-7);
  EXPECT_NEAR(grazing.value[0], 0.364501953, 1e-9);
  EXPECT_NEAR(grazing.value[1], 0.170898438, 1e-9);
  EXPECT_NEAR(grazing.value[2], 0.178222656, 1e-9);

  const Sample& normal = m.samples.at(511 * kCells + 0);
  EXPECT_NEAR(normal.wi.x(), 0.0015340, 1e-7);
  EXPECT_NEAR(normal.wi.y(), 0.0015340, 1e-7);
  EXPECT_NEAR(normal.wi.z(), 0.9999976, 1e-7);
  EXPECT_NEAR(normal.value[0], 0.0881347656, 1e-10);
  EXPECT_NEAR(normal.value[1], 0.0169525146, 1e-10);
  EXPECT_NEAR(normal.value[2], 0.0109710693, 1e-10);
  // Red fabric: red dominates away from grazing; towards grazing the sheen whitens it.
  EXPECT_GT(normal.value[0], 4 * normal.value[1]);
  EXPECT_GT(grazing.value[1] / grazing.value[0], 2 * normal.value[1] / normal.value[0]);
}

// Every cell: wi and wo are unit, above the horizon, mirror images across the x-z plane, with
// the half/difference angles of their grid cell, and the value of their pixel as the HDR
// pipeline's own EXR reader sees it.
TEST(AltaSlice, EveryCellMatchesItsPixelAndGridAngles) {
  const std::string path = DataPath(kSlice);
  const Measurement m = ReadMeasurement(path);
  const Image image = ReadExr(path);
  ASSERT_EQ(image.width, kCells);
  ASSERT_EQ(image.height, kCells);
  for (int y = 0; y < kCells; y += 7) {
    for (int x = 0; x < kCells; x += 5) {
      const Sample& sample = m.samples[static_cast<size_t>(y) * kCells + x];
      ASSERT_NEAR(sample.wi.norm(), 1.0, 1e-12);
      ASSERT_GE(sample.wi.z(), 0.0);
      ASSERT_NEAR(sample.wo.y(), -sample.wi.y(), 1e-12);
      ASSERT_NEAR(sample.wo.z(), sample.wi.z(), 1e-12);
      const HalfDiff hd = ToHalfDiff(sample.wi, sample.wo);
      ASSERT_NEAR(hd.theta_h, (x + 0.5) / kCells * kPi / 2, 1e-9) << x << "," << y;
      ASSERT_NEAR(hd.theta_d, (kCells - 1 - y + 0.5) / kCells * kPi / 2, 1e-9) << x << "," << y;
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(sample.value[c], image.pixel(x, y)[c]) << x << "," << y << " channel " << c;
      }
    }
  }
}

// Claimed by content only when square: the header's dataWindow decides, before any pixel.
TEST(AltaSlice, OnlySquareImagesAreClaimedByContent) {
  const FileFormat* slice = FormatByContent(DataPath(kSlice));
  ASSERT_NE(slice, nullptr);
  EXPECT_EQ(slice->name, "alta-slice");
  EXPECT_EQ(FormatByContent(DataPath("hdr/memorial.exr")), nullptr);  // 512 x 768
  EXPECT_EQ(FormatByContent(DataPath("hdr/memorial.hdr")), nullptr);  // Radiance, not EXR
}

TEST(AltaSlice, ImagesThatAreNotSlicesAreRefused) {
  ScratchDir dir;
  struct Case {
    std::string path, says;
  } cases[] = {
      // Debevec's Memorial Church, 512 x 768: an image, not a square grid of cells.
      {DataPath("hdr/memorial.exr"), "512 x 768 pixels, not a BRDF slice"},
      {dir.Write("text.exr", "this is not an OpenEXR file\n"), "not a readable OpenEXR"},
      // The real slice cut after 2000 bytes.
      {dir.Write("cut.exr", testing::ReadFileText(DataPath(kSlice)).substr(0, 2000)),
       "not a readable OpenEXR"},
  };
  for (const Case& c : cases) {
    const testing::CommandResult result = RunBrdf("info '" + c.path + "'");
    EXPECT_EQ(result.exit_status, 2) << c.path << "\n" << result.err;
    EXPECT_EQ(testing::CountLines(result.err), 1) << result.err;
    EXPECT_NE(result.err.find(c.path + ": "), std::string::npos) << result.err;
    EXPECT_NE(result.err.find(c.says), std::string::npos) << result.err;
  }
}

}  // namespace
}  // namespace brdf
