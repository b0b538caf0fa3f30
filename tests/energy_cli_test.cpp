// `brdf energy` as a user meets it: the table, --json with DESIGN §7's fields, --out CSV and
// --plot PNG written whole, the lecture's Blinn-Phong factor reported as not conserving (exit
// status 0: the check ran), and bad input giving exit status 2 with one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "test_util.h"

namespace brdf {
namespace {

using testing::RunBrdf;
using testing::ScratchDir;

TEST(EnergyCli, JsonHasDesignFieldsAndLambertIsRhoD) {
  const testing::CommandResult result = RunBrdf("energy lambert:rho_d=0.8,0.5,0.2 --json --quiet");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(result.out);
  for (const char* key : {"max_albedo", "theta_deg_at_max", "albedo", "verdict", "reason"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["albedo"].size(), 90u);  // default: 90 steps over 0..89 degrees
  EXPECT_EQ(json["albedo"][89]["theta_deg"].get<double>(), 89.0);
  EXPECT_NEAR(json["max_albedo"][0].get<double>(), 0.8, 1e-6);
  EXPECT_NEAR(json["albedo"][45]["rgb"][2].get<double>(), 0.2, 1e-6);
  EXPECT_EQ(json["verdict"], "conserving");
  EXPECT_EQ(json["theta_deg_at_max"].size(), 3u);
}

TEST(EnergyCli, LectureBlinnPhongFactorIsNotConservingWithExitZero) {
  // (m+8)/pi is blinn-phong with rho_s = 8 in our (m+8)/(8 pi) convention.
  const testing::CommandResult result =
      RunBrdf("energy blinn-phong:rho_d=0:rho_s=8:m=100 --theta-steps 10 --quiet");
  EXPECT_EQ(result.exit_status, 0) << result.err;
  EXPECT_NE(result.out.find("verdict: not conserving"), std::string::npos) << result.out;
  const nlohmann::json json = nlohmann::json::parse(
      RunBrdf("energy blinn-phong:rho_d=0:rho_s=8:m=100 --theta-steps 10 --json --quiet").out);
  EXPECT_EQ(json["verdict"], "not conserving");
  EXPECT_GT(json["max_albedo"][0].get<double>(), 7.9);
}

TEST(EnergyCli, WritesCsvAndPngAtomically) {
  ScratchDir dir;
  const std::string csv = dir.File("albedo.csv"), png = dir.File("albedo.png");
  const testing::CommandResult result = RunBrdf(
      "energy phong:rho_d=0.3:rho_s=0.5:n=50 --method importance --samples 2000 "
      "--theta-steps 7 --quiet --out '" +
      csv + "' --plot '" + png + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const std::string table = testing::ReadFileText(csv);
  EXPECT_EQ(testing::CountLines(table), 8);  // header + 7 angles
  EXPECT_EQ(table.rfind("theta_deg,r,g,b,error_r,error_g,error_b,coverage\n", 0), 0u);
  EXPECT_EQ(testing::ReadFileText(png).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(dir.CountEntries(), 2);  // no temporary left behind
}

TEST(EnergyCli, MeasurementFileWarnsAboutCoverage) {
  const testing::CommandResult result =
      RunBrdf("energy '" + testing::DataPath("cornell-pbrt-v2/mystique.brdf") +
              "' --method mc --samples 2000 --theta-steps 4 --json --quiet");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(result.out);
  EXPECT_FALSE(json["warnings"].empty());
  EXPECT_NE(result.err.find("warning"), std::string::npos);
}

TEST(EnergyCli, BadInputIsExitTwoWithOneLine) {
  ScratchDir dir;
  for (const std::string& arguments :
       {std::string("energy no-such-model:m=3"), std::string("energy phong:n=-1"),
        std::string("energy lambert --method grid"), std::string("energy lambert --theta-steps 0"),
        std::string("energy '" + testing::DataPath("cornell-astm/cayman.astm") +
                    "' --method importance"),
        std::string("energy '" + dir.Write("broken.json", "{\"model\": 3}") + "'")}) {
    const testing::CommandResult result = RunBrdf(arguments);
    EXPECT_EQ(result.exit_status, 2) << arguments << "\n" << result.err;
    EXPECT_EQ(testing::CountLines(result.err), 1) << arguments << "\n" << result.err;
  }
}

// Microfacet model strings with values no material has are usage errors (exit 2), in one line
// naming the key, wherever a model is taken; a valid one integrates below 1.
TEST(EnergyCli, MicrofacetModelStringsAreCheckedAndIntegrated) {
  for (const auto& [spec, key] :
       {std::pair{"ggx:alpha=0", "alpha"}, std::pair{"beckmann:f0=-0.1", "f0"},
        std::pair{"ggx:f0=1.2", "f0"}, std::pair{"beckmann:roughness=0.1", "roughness"}}) {
    const testing::CommandResult result = RunBrdf(std::string("energy '") + spec + "' --quiet");
    EXPECT_EQ(result.exit_status, 2) << spec << ": " << result.err;
    EXPECT_NE(result.err.find(key), std::string::npos) << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
  }
  const testing::CommandResult ok =
      RunBrdf("energy ggx:rho_d=0.2:f0=0.04:alpha=0.2 --theta-steps 10 --json --quiet");
  ASSERT_EQ(ok.exit_status, 0) << ok.err;
  EXPECT_EQ(nlohmann::json::parse(ok.out)["verdict"], "conserving");
}

}  // namespace
}  // namespace brdf
