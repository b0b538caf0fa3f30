// Labels a person reads: a long label keeps a file's name (core/text.h ShortLabel), and the tone
// summary names the operator apart from the exposure factor.
#include <gtest/gtest.h>

#include <string>

#include "core/text.h"
#include "test_util.h"

namespace brdf {
namespace {

TEST(Labels, ALongPathKeepsItsFileName) {
  const std::string label =
      "/home/someone/measurements/2024/rgl-bsdf/cc_ibiza_sunset_rgb.bsdf (RGL-EPFL tensor lookup)";
  const std::string shown = ShortLabel(label, 60);
  EXPECT_EQ(shown, "cc_ibiza_sunset_rgb.bsdf (RGL-EPFL tensor lookup)");
  EXPECT_LE(shown.size(), 60u);
}

TEST(Labels, ShortLabelsAndModelStringsAreLeftOrCutAtTheEnd) {
  EXPECT_EQ(ShortLabel("data/a.csv", 60), "data/a.csv");  // fits: untouched
  const std::string model = "ggx:rho_d=0.1234567,0.2345678,0.3456789:f0=0.04:alpha=0.1234567";
  const std::string shown = ShortLabel(model, 20);
  EXPECT_EQ(shown, "ggx:rho_d=0.12345...");  // the model's name stays in front
  EXPECT_EQ(shown.size(), 20u);
}

// `tonemap --operator exposure --ev 2` printed "exposure 4, exposure": the factor and the
// operator now read apart.
TEST(Labels, TheExposureOperatorIsNamedApartFromTheExposureFactor) {
  testing::ScratchDir dir;
  const std::string out = dir.File("memorial.png");
  const testing::CommandResult result =
      testing::RunBrdf("tonemap '" + testing::DataPath("hdr/memorial.hdr") + "' --out '" + out +
                       "' --operator exposure --ev 2");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  EXPECT_NE(result.out.find("exposure 4, tone map exposure (1 - exp(-x))"), std::string::npos)
      << result.out;
  const testing::CommandResult reinhard = testing::RunBrdf(
      "tonemap '" + testing::DataPath("hdr/memorial.hdr") + "' --out '" + out + "'");
  EXPECT_NE(reinhard.out.find(", tone map reinhard"), std::string::npos) << reinhard.out;
  EXPECT_EQ(reinhard.out.find("exp(-x)"), std::string::npos) << reinhard.out;
}

}  // namespace
}  // namespace brdf
