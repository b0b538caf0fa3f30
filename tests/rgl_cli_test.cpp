// The RGL-EPFL files through the commands a user runs: info, energy, render --vs, convert to
// MERL and to CSV (own samples or a schedule), and the same fit from the file and from its MERL
// conversion.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "test_util.h"

namespace brdf {
namespace {

using testing::DataPath;
using testing::RunBrdf;
using testing::ScratchDir;

std::string Quoted(const std::string& path) { return "'" + path + "'"; }

TEST(RglCli, InfoShowsDescriptionGridIncidencesRangesAndClippedCount) {
  const testing::CommandResult result =
      RunBrdf("info --json " + Quoted(DataPath("rgl-bsdf/vch_golden_yellow_rgb.bsdf")));
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(result.out);
  EXPECT_EQ(json["format"], "rgl-bsdf");
  EXPECT_EQ(json["samples"], 8 * 32 * 32);
  const nlohmann::json& metadata = json["metadata"];
  EXPECT_EQ(metadata["description"], "TeckWrap vinyl wrapping film (Golden Yellow VCH508N)");
  EXPECT_NE(metadata["grid"].get<std::string>().find("32x32"), std::string::npos);
  EXPECT_NE(metadata["incidence"].get<std::string>().find("8 theta_i (0, 31.62,"),
            std::string::npos);
  // The blue channel of this yellow film goes out of gamut (stored_range b starts below 0).
  EXPECT_EQ(metadata["clipped_negative"].get<std::string>().rfind("1118 of 24576", 0), 0u);
  EXPECT_NE(metadata["stored_range"].get<std::string>().find("b -0.03964"), std::string::npos);
}

TEST(RglCli, EnergyOfWhitePaperIsTheMeasuredAlbedoCurve) {
  const testing::CommandResult result =
      RunBrdf("energy --json --quiet " + Quoted(DataPath("rgl-bsdf/paper_white_rgb.bsdf")));
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(result.out);
  EXPECT_EQ(json["verdict"], "conserving");
  ASSERT_EQ(json["albedo"].size(), 90u);
  for (const nlohmann::json& point : json["albedo"]) {
    const double green = point["rgb"][1];
    EXPECT_GT(green, 0.75) << point;
    EXPECT_LT(green, 0.9) << point;
  }
}

double Param(const nlohmann::json& fit, const std::string& name, int channel) {
  const nlohmann::json& value = fit["params"][name];
  return value.is_array() ? value[channel].get<double>() : value.get<double>();
}

// A glossy film fitted with blinn-phong from the file's own grid nodes and from its MERL table
// (every cell centre through the evaluator): the exponent agrees within 10 %, the specular and
// diffuse albedos within 0.05 (measured: m 350 and 362, rho_s within 0.04, rho_d within 0.05;
// the two fits see the same function sampled on different grids).
TEST(RglCli, FitOfTheMerlConversionMatchesTheFitOfTheFile) {
  ScratchDir dir;
  const std::string source = DataPath("rgl-bsdf/vch_golden_yellow_rgb.bsdf");
  const std::string merl = dir.File("vch.binary");
  // A MERL table is reciprocal by its parameterization: both sides read the file reciprocally.
  ASSERT_EQ(
      RunBrdf("convert --quiet --reciprocal " + Quoted(source) + " " + Quoted(merl)).exit_status,
      0);
  const testing::CommandResult direct =
      RunBrdf("fit --model blinn-phong --reciprocal --json " + Quoted(source));
  const testing::CommandResult converted =
      RunBrdf("fit --model blinn-phong --json " + Quoted(merl));
  ASSERT_EQ(direct.exit_status, 0) << direct.err;
  ASSERT_EQ(converted.exit_status, 0) << converted.err;
  const nlohmann::json a = nlohmann::json::parse(direct.out);
  const nlohmann::json b = nlohmann::json::parse(converted.out);
  EXPECT_NEAR(Param(a, "m", 0), Param(b, "m", 0), 0.1 * Param(b, "m", 0));
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(Param(a, "rho_s", c), Param(b, "rho_s", c), 0.05) << c;
    EXPECT_NEAR(Param(a, "rho_d", c), Param(b, "rho_d", c), 0.05) << c;
  }
}

TEST(RglCli, ConvertToCsvWritesTheGridOrASchedule) {
  ScratchDir dir;
  const std::string source = DataPath("rgl-bsdf/paper_white_rgb.bsdf");
  const std::string own = dir.File("own.csv"), scheduled = dir.File("inplane.csv");
  ASSERT_EQ(RunBrdf("convert --quiet " + Quoted(source) + " " + Quoted(own)).exit_status, 0);
  testing::CommandResult info = RunBrdf("info --json " + Quoted(own));
  ASSERT_EQ(info.exit_status, 0) << info.err;
  // 8192 nodes less the 1974 missing ones (below the horizon, or the 90-degree incidence).
  EXPECT_EQ(nlohmann::json::parse(info.out)["samples"], 8192 - 1974);
  ASSERT_EQ(RunBrdf("convert --quiet --schedule inplane:step=10 " + Quoted(source) + " " +
                    Quoted(scheduled))
                .exit_status,
            0);
  info = RunBrdf("info --json " + Quoted(scheduled));
  ASSERT_EQ(info.exit_status, 0) << info.err;
  const nlohmann::json json = nlohmann::json::parse(info.out);
  EXPECT_EQ(json["metadata"]["schedule"], "inplane:step=10");
  EXPECT_EQ(json["samples"], 9 * 17);  // theta_i 0..80 by 10, theta_o -80..80 in the plane
  // A scattered measurement has no evaluator to take to a schedule.
  const testing::CommandResult refused =
      RunBrdf("convert --schedule inplane " + Quoted(DataPath("cornell-astm/cayman.astm")) + " " +
              Quoted(dir.File("x.csv")));
  EXPECT_EQ(refused.exit_status, 2);
  EXPECT_NE(refused.err.find("--schedule needs a dense input"), std::string::npos) << refused.err;
}

TEST(RglCli, RenderShowsTheMeasurementNextToItsFit) {
  ScratchDir dir;
  const std::string source = DataPath("rgl-bsdf/paper_white_rgb.bsdf");
  const std::string fit = dir.File("fit.json"), sheet = dir.File("sheet.png");
  ASSERT_EQ(RunBrdf("fit --model lambert --out " + Quoted(fit) + " " + Quoted(source)).exit_status,
            0);
  const testing::CommandResult result = RunBrdf("render --quiet --size 64 " + Quoted(source) +
                                                " --vs " + Quoted(fit) + " --out " + Quoted(sheet));
  ASSERT_EQ(result.exit_status, 0) << result.err;
  std::ifstream png(sheet, std::ios::binary);
  EXPECT_TRUE(png.good());
}

}  // namespace
}  // namespace brdf
