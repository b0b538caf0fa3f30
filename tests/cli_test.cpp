// The command line as a user meets it: info (text and JSON), convert, demo, and hostile input
// giving exit status 2 with one line naming the file, and no output file.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "browser_check.h"
#include "cli/demo.h"
#include "gonio/schedule.h"
#include "models/registry.h"
#include "test_util.h"

namespace brdf {
namespace {

// The models `--model auto` climbs (the ladder; compositions beyond it are fitted on request).
size_t DemoFitsPerDataset() {
  return std::count_if(ModelRegistry().begin(), ModelRegistry().end(),
                       [](const ModelInfo& info) { return info.auto_candidate; });
}

using testing::DataPath;
using testing::RunBrdf;
using testing::ScratchDir;
TEST(Cli, HelpDocumentsEveryCommand) {
  const testing::CommandResult result = RunBrdf("--help");
  EXPECT_EQ(result.exit_status, 0);
  for (const char* command : {"demo", "info", "convert", "energy", "export"}) {
    EXPECT_NE(result.out.find(command), std::string::npos) << command;
    EXPECT_EQ(RunBrdf(std::string(command) + " --help").exit_status, 0) << command;
  }
}

TEST(Cli, UnknownCommandIsUsageError) {
  EXPECT_EQ(RunBrdf("frobnicate").exit_status, 2);
  EXPECT_EQ(RunBrdf("info").exit_status, 2);  // FILE is required
}

TEST(Cli, UnknownCommandIsNamedWithTheNearestSuggestion) {
  const testing::CommandResult typo = RunBrdf("fitt x");
  EXPECT_EQ(typo.exit_status, 2);
  EXPECT_EQ(typo.err,
            "brdf: unknown command 'fitt' (did you mean 'fit'?); run 'brdf --help' for "
            "the list of commands\n");
  // Nothing near: named, with no guess.
  const testing::CommandResult far = RunBrdf("frobnicate");
  EXPECT_NE(far.err.find("unknown command 'frobnicate'"), std::string::npos) << far.err;
  EXPECT_EQ(far.err.find("did you mean"), std::string::npos) << far.err;
  // A known command is never called unknown.
  EXPECT_EQ(RunBrdf("info").err.find("unknown command"), std::string::npos);
}

TEST(Cli, ParserErrorsArePrefixedAndNameTheCommand) {
  const testing::CommandResult missing = RunBrdf("info");
  EXPECT_EQ(missing.exit_status, 2);
  EXPECT_EQ(missing.err, "brdf: info: FILE is required (run 'brdf info --help')\n");
  const testing::CommandResult range = RunBrdf("plan --model ggx --budget 0 --out plan.csv");
  EXPECT_EQ(range.exit_status, 2);
  EXPECT_EQ(range.err.rfind("brdf: plan: --budget: ", 0), 0u) << range.err;
  const testing::CommandResult none = RunBrdf("");
  EXPECT_EQ(none.err.rfind("brdf: ", 0), 0u) << none.err;
  // --help still succeeds and prints no error.
  const testing::CommandResult help = RunBrdf("fit --help");
  EXPECT_EQ(help.exit_status, 0);
  EXPECT_EQ(help.err.find("brdf: "), std::string::npos) << help.err;
}

TEST(Cli, InfoJsonOnRealCornellFile) {
  const testing::CommandResult result =
      RunBrdf("info --json '" + DataPath("cornell-astm/cayman.astm") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(result.out);
  EXPECT_EQ(json["format"], "astm");
  EXPECT_EQ(json["samples"], 1439);
  EXPECT_EQ(json["missing"], 0);
  EXPECT_EQ(json["sample"], "Cayman Metallic");
  // The first row of the file has theta_i = 0.872665 rad = 50.0000 deg; all incidences lie
  // in [0, 90).
  EXPECT_LE(json["theta_i_deg"][1].get<double>(), 90.0);
  EXPECT_GE(json["theta_i_deg"][1].get<double>(), 50.0);
  for (const char* key : {"format", "samples", "theta_i_deg", "theta_o_deg", "min", "max",
                          "missing", "negative", "nan", "incidence_directions"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
}

TEST(Cli, InfoTextOnZemax) {
  const testing::CommandResult result =
      RunBrdf("info '" + DataPath("zemax-bsdf/test_13_planesymmetric_brdf_zemax.bsdf") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  EXPECT_NE(result.out.find("zemax"), std::string::npos);
  EXPECT_NE(result.out.find("2717"), std::string::npos);  // 13 x 19 x 11 cells
}

TEST(Cli, ConvertAstmToCsvAndBack) {
  ScratchDir dir;
  const std::string csv = dir.File("cayman.csv");
  const testing::CommandResult convert =
      RunBrdf("convert '" + DataPath("cornell-astm/cayman.astm") + "' '" + csv + "'");
  ASSERT_EQ(convert.exit_status, 0) << convert.err;
  const testing::CommandResult info = RunBrdf("info --json '" + csv + "'");
  ASSERT_EQ(info.exit_status, 0) << info.err;
  const nlohmann::json json = nlohmann::json::parse(info.out);
  EXPECT_EQ(json["format"], "native-csv");
  EXPECT_EQ(json["samples"], 1439);
  EXPECT_EQ(json["metadata"]["converted_from"], "astm");
  EXPECT_EQ(json["metadata"]["illuminant"], "D65");
}

TEST(Cli, HostileInputExitsTwoWithOneLineAndNoOutput) {
  ScratchDir dir;
  const std::string out = dir.File("out.csv");
  const std::vector<std::pair<std::string, std::string>> inputs = {
      {"empty.astm", ""},
      {"garbage.csv", "hello, world\n"},
      {"truncated.brdf", "# num wls\n3\n400 500 600\n0.1 0.0 0.2 0.0 1 2\n"},
      {"nan.csv", "# brdfkit measurement v1\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n1,0,2,0,NaN,1,1\n"},
      {"dims.binary", std::string("\x5a\0\0\0\x5a\0\0\0\x5a\0\0\0", 12)},
  };
  for (const auto& [name, contents] : inputs) {
    const std::string path = dir.Write(name, contents);
    for (const std::string& command :
         {"info '" + path + "'", "convert '" + path + "' '" + out + "'"}) {
      const testing::CommandResult result = RunBrdf(command);
      EXPECT_EQ(result.exit_status, 2) << command << "\n" << result.err;
      EXPECT_EQ(testing::CountLines(result.err), 1) << command << "\n" << result.err;
      EXPECT_NE(result.err.find(path), std::string::npos) << result.err;
      EXPECT_TRUE(result.err.find("line") != std::string::npos ||
                  result.err.find("byte") != std::string::npos)
          << result.err;
    }
  }
  // Nothing was written: not the output, not a temporary.
  EXPECT_EQ(dir.CountEntries(), static_cast<int>(inputs.size()));
}

TEST(Cli, DirectoryAndMissingFileAreInputErrors) {
  ScratchDir dir;
  testing::CommandResult result = RunBrdf("info '" + dir.path() + "'");
  EXPECT_EQ(result.exit_status, 2);
  EXPECT_NE(result.err.find("directory"), std::string::npos) << result.err;
  result = RunBrdf("info '" + dir.File("nope.csv") + "'");
  EXPECT_EQ(result.exit_status, 2);
  EXPECT_NE(result.err.find("nope.csv"), std::string::npos) << result.err;
}

TEST(Cli, UnwritableOutputIsAnErrorAndLosesNothing) {
  ScratchDir dir;
  const testing::CommandResult result = RunBrdf("convert '" + DataPath("cornell-astm/cayman.astm") +
                                                "' '" + dir.path() + "/no/such/dir/out.csv'");
  EXPECT_EQ(result.exit_status, 2) << result.err;
  EXPECT_EQ(testing::CountLines(result.err), 1) << result.err;
  EXPECT_EQ(dir.CountEntries(), 0);
}

// The demo measures its ray-traced surface over the hemisphere, not in the plane only: its
// sheets then show the surface rather than an interpolation of a few in-plane readings.
TEST(Cli, DemoTracesTheSurfaceOverTheHemisphere) {
  const gonio::Schedule full = gonio::MakeSchedule(cli::DemoSchedule("rough-gold", false));
  EXPECT_GE(full.CountGeometries(), 10000u);
  EXPECT_EQ(full.kind, "hemisphere");
  EXPECT_EQ(gonio::MakeSchedule(cli::DemoSchedule("rough-gold", true)).kind, "hemisphere");
}

TEST(Cli, QuickDemoSimulatesFitsAndReports) {
  ScratchDir dir;
  const testing::CommandResult result = RunBrdf("demo --quick --quiet --out '" + dir.path() + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  EXPECT_NE(result.out.find("plastic-sphere"), std::string::npos);
  std::ifstream stream(dir.File("summary.json"));
  const nlohmann::json json = nlohmann::json::parse(stream);
  // data/ holds 4 ASTM, 5 pbrt-v2, 1 Zemax, 7 RGL-EPFL, 2 ALTA, 1 gonio CSV and 1 BRDF slice
  // file; the HDR images beside them are not measurements.
  EXPECT_EQ(json["measurements"].size(), 21u);
  for (const nlohmann::json& row : json["measurements"]) EXPECT_GT(row["samples"], 0);
  // Three simulated samples and one real file of each format, each fitted with every model. The
  // pbrt-v2 files that repeat the ASTM files' samples are passed over (mystique, the one only in
  // that layout, stands for pbrt-v2), and so is the 262,144-sample slice image (too large to
  // preview by scattered interpolation within the demo's budget; a note says so).
  ASSERT_EQ(json["datasets"].size(), 9u);
  std::vector<std::string> real;
  for (const nlohmann::json& dataset : json["datasets"]) {
    if (dataset["kind"] == "real") real.push_back(dataset["source"].get<std::string>());
  }
  EXPECT_EQ(real, (std::vector<std::string>{
                      "alta-retro/retro-3M-jaune.dat", "cornell-astm/acryl_blue.astm",
                      "cornell-pbrt-v2/mystique.brdf", "gonio-csv/test_brdf_viewer_2D_data.csv",
                      "rgl-bsdf/cc_ibiza_sunset_rgb.bsdf",
                      "zemax-bsdf/test_13_planesymmetric_brdf_zemax.bsdf"}));
  for (const nlohmann::json& dataset : json["datasets"]) {
    EXPECT_EQ(dataset["energy"], "conserving")
        << dataset["name"] << ": " << dataset["energy_reason"];
    ASSERT_EQ(dataset["fits"].size(), DemoFitsPerDataset());
    for (const nlohmann::json& fit : dataset["fits"]) {
      EXPECT_FALSE(testing::ReadFileText(dir.File(fit.get<std::string>())).empty()) << fit;
    }
  }
  // The simulated truths come back: lambert for the matte sample, the sphere's blinn-phong.
  EXPECT_EQ(json["datasets"][0]["chosen"], "lambert");
  EXPECT_LT(json["datasets"][0]["truth_error"].get<double>(), 0.01);
  EXPECT_LT(json["datasets"][1]["truth_error"].get<double>(), 0.03);
  // The truth's own fit raises no warning that cries wolf (the stated sigma carries the
  // instrument's positioning jitter): lambert on the matte sample, blinn-phong on the sphere.
  for (int d = 0; d < 2; ++d) {
    const std::string truth = d == 0 ? "lambert" : "blinn-phong";
    for (const nlohmann::json& fit_path : json["datasets"][d]["fits"]) {
      const nlohmann::json fit =
          nlohmann::json::parse(testing::ReadFileText(dir.File(fit_path.get<std::string>())));
      if (fit["model"] != truth) continue;
      for (const nlohmann::json& warning : fit["warnings"]) {
        const std::string text = warning.get<std::string>();
        EXPECT_NE(text.rfind("model mismatch", 0), 0u) << fit_path << ": " << text;
        EXPECT_NE(text.rfind("outliers", 0), 0u) << fit_path << ": " << text;
      }
    }
  }
  const std::string html = testing::ReadFileText(dir.File("report.html"));
  EXPECT_NE(html.find("<h1>brdfkit demo report</h1>"), std::string::npos);
  // Every picture links to itself at full size.
  EXPECT_NE(html.find("<a href=\"images/matte-slices.png\"><img src=\"images/matte-slices.png\""),
            std::string::npos);
  EXPECT_EQ(html.find("<figure><img"), std::string::npos);
  // Every dataset has its plane-of-incidence slice chart.
  for (const nlohmann::json& dataset : json["datasets"]) {
    const std::string slices = "images/" + dataset["name"].get<std::string>() + "-slices.png";
    EXPECT_NE(html.find("<img src=\"" + slices + "\""), std::string::npos) << slices;
  }
  // Every image the report links exists.
  size_t position = 0;
  int images = 0;
  while ((position = html.find("<img src=\"", position)) != std::string::npos) {
    position += 10;
    const std::string image = html.substr(position, html.find('"', position) - position);
    EXPECT_FALSE(testing::ReadFileText(dir.File(image)).empty()) << image;
    ++images;
  }
  EXPECT_GE(images, 5);
  // And a browser shows them.
  ExpectReportLoadsInBrowser(dir.path());
}

}  // namespace
}  // namespace brdf

namespace brdf {
namespace {

TEST(Cli, BatchTakesADirectoryAsItsReadableFilesSorted) {
  ScratchDir dir;
  const std::string in = dir.File("in");
  std::filesystem::create_directories(in);
  std::filesystem::copy_file(DataPath("zemax-bsdf/test_13_planesymmetric_brdf_zemax.bsdf"),
                             in + "/b.bsdf");
  std::filesystem::copy_file(DataPath("cornell-astm/cayman.astm"), in + "/a.astm");
  std::ofstream(in + "/notes.txt") << "not a measurement\n";
  std::ofstream(in + "/.hidden.astm") << "ignored\n";
  const testing::CommandResult result =
      RunBrdf("batch '" + in + "' --model lambert --out '" + dir.File("out") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  // The unreadable file is named and passed over; the hidden one is not looked at.
  EXPECT_NE(result.err.find("skipped 1 files in no format brdf reads: " + in + "/notes.txt"),
            std::string::npos)
      << result.err;
  EXPECT_EQ(result.err.find(".hidden"), std::string::npos) << result.err;
  std::ifstream table(dir.File("out/table.csv"));
  std::string header, first, second, extra;
  std::getline(table, header);
  std::getline(table, first);
  std::getline(table, second);
  EXPECT_EQ(first.rfind(in + "/a.astm,a.json,ok,lambert,", 0), 0u) << first;
  EXPECT_EQ(second.rfind(in + "/b.bsdf,b.json,ok,lambert,", 0), 0u) << second;
  EXPECT_FALSE(std::getline(table, extra));
  // A directory with nothing readable is bad input, named.
  const std::string empty = dir.File("empty");
  std::filesystem::create_directories(empty);
  std::ofstream(empty + "/notes.txt") << "nothing\n";
  const testing::CommandResult none = RunBrdf("batch '" + empty + "' --model lambert");
  EXPECT_EQ(none.exit_status, 2);
  EXPECT_NE(none.err.find(empty + ": no file in this directory"), std::string::npos) << none.err;
}

TEST(Cli, FitAndExportQuietPrintNothingOnSuccess) {
  ScratchDir dir;
  const std::string astm = "'" + DataPath("cornell-astm/cayman.astm") + "'";
  const std::string fit_json = dir.File("fit.json");
  const testing::CommandResult loud = RunBrdf("fit " + astm + " --model lambert");
  EXPECT_NE(loud.out.find("model       lambert"), std::string::npos) << loud.out;
  const testing::CommandResult quiet =
      RunBrdf("fit " + astm + " --model lambert --quiet --out '" + fit_json + "'");
  EXPECT_EQ(quiet.exit_status, 0) << quiet.err;
  EXPECT_EQ(quiet.out, "");
  EXPECT_EQ(quiet.err, "");
  EXPECT_TRUE(std::filesystem::exists(fit_json));  // the report is still written
  const std::string xml = dir.File("m.xml");
  const testing::CommandResult exported =
      RunBrdf("export '" + fit_json + "' --to mitsuba3 --quiet --out '" + xml + "'");
  EXPECT_EQ(exported.exit_status, 0) << exported.err;
  EXPECT_EQ(exported.out, "");
  EXPECT_TRUE(std::filesystem::exists(xml));
  EXPECT_NE(RunBrdf("export '" + fit_json + "' --to mitsuba3 --out '" + xml + "'").out, "");
}

}  // namespace
}  // namespace brdf
