// What `brdf info`, the demo and the reports call a sample (Measurement::SampleName): the name
// the file gives it, or the one line describing it, before the file name.
#include <gtest/gtest.h>

#include <string>

#include "io/formats.h"
#include "test_util.h"

namespace brdf {
namespace {

// cc_ibiza_sunset_rgb.bsdf holds the u8 field "description" = "TeckWrap vinyl wrapping film
// (Ibiza Sunset RD02)" and no sample name of its own.
TEST(SampleNames, RglFilesAreNamedByTheirDescription) {
  const Measurement m = ReadMeasurement(testing::DataPath("rgl-bsdf/cc_ibiza_sunset_rgb.bsdf"));
  EXPECT_EQ(m.SampleName(), "TeckWrap vinyl wrapping film (Ibiza Sunset RD02)");
  const testing::CommandResult info =
      testing::RunBrdf("info " + testing::DataPath("rgl-bsdf/cc_ibiza_sunset_rgb.bsdf"));
  EXPECT_NE(info.out.find("sample      TeckWrap vinyl wrapping film (Ibiza Sunset RD02)\n"),
            std::string::npos)
      << info.out;
}

// A file with neither (the gonio CSV) keeps its file name.
TEST(SampleNames, FilesWithoutANameAreNamedByTheFile) {
  const Measurement m =
      ReadMeasurement(testing::DataPath("gonio-csv/test_brdf_viewer_2D_data.csv"));
  EXPECT_EQ(m.SampleName(), "test_brdf_viewer_2D_data.csv");
}

}  // namespace
}  // namespace brdf
