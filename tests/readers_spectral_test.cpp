// The spectral Cornell readers: ASTM E1392 (io/astm.cpp) and pbrt-v2 .brdf (io/pbrt_brdf.cpp),
// against numbers read by hand from the real files in data/, against each other (the same
// measurements in two layouts), and against hostile inputs whose errors must name the file and
// the line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/colour.h"
#include "core/errors.h"
#include "io/formats.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::DataPath;
using testing::ReplaceFirst;
using testing::RunBrdf;
using testing::ScratchDir;
// Comma-separated doubles, parsed independently of the reader under test.
std::vector<double> CommaSeparated(const std::string& line) {
  std::vector<double> values;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) values.push_back(std::stod(field));
  return values;
}

std::vector<double> CornellWavelengths() {
  std::vector<double> wavelengths;
  for (int lambda = 400; lambda <= 700; lambda += 10) wavelengths.push_back(lambda);
  return wavelengths;
}

std::string Head(const std::string& path) { return testing::ReadFileText(path).substr(0, 4096); }
// ---------------------------------------------------------------------------------------------
// ASTM E1392 against the real file.

// data/cornell-astm/cayman.astm, line 23 (the first row) begins
//   0.872665,0.000000,0.573513,0.000000,0.000874,0.001991,...
TEST(Astm, CaymanFirstRowAnglesAndCount) {
  const Measurement m = ReadAstm(DataPath("cornell-astm/cayman.astm"), {});
  ASSERT_EQ(m.samples.size(), 1439u);  // NUM_POINTS 1439
  EXPECT_EQ(m.format, "astm");
  const Sample& first = m.samples[0];
  EXPECT_NEAR(Theta(first.wi), 0.872665, 1e-12);
  EXPECT_NEAR(Phi(first.wi), 0.0, 1e-12);
  EXPECT_NEAR(Theta(first.wo), 0.573513, 1e-12);
  EXPECT_NEAR(Phi(first.wo), 0.0, 1e-12);
  EXPECT_FALSE(first.missing);
  // wi at phi 0 lies in the x-z plane on the +x side (DESIGN §1).
  EXPECT_NEAR(first.wi.x(), std::sin(0.872665), 1e-12);
  EXPECT_NEAR(first.wi.y(), 0.0, 1e-12);
}

// Line 100 (sample 77), typed in from the file:
//   0.174533,0.000000,0.283794,-2.356194,0.005104,0.019097,...,0.011755
TEST(Astm, CaymanRow77ThroughSpectrumToRgb) {
  const std::vector<double> spectrum = {
      0.005104, 0.019097, 0.026772, 0.033398, 0.042389, 0.055622, 0.074097, 0.095864,
      0.114385, 0.124166, 0.122741, 0.110753, 0.090266, 0.066131, 0.044444, 0.027442,
      0.016305, 0.010489, 0.007725, 0.006143, 0.005217, 0.004866, 0.005002, 0.005538,
      0.006299, 0.007188, 0.008105, 0.008963, 0.009578, 0.010233, 0.011755};
  const std::string path = DataPath("cornell-astm/cayman.astm");
  // Guard the typing with an independent parse of the same line.
  const std::vector<double> row =
      CommaSeparated(testing::Lines(testing::ReadFileText(path), 100, 100));
  ASSERT_EQ(row.size(), 35u);
  EXPECT_EQ(row[0], 0.174533);
  EXPECT_EQ(row[3], -2.356194);
  for (size_t k = 0; k < spectrum.size(); ++k) EXPECT_EQ(row[4 + k], spectrum[k]) << k;

  const Measurement m = ReadAstm(path, {});
  const Sample& sample = m.samples.at(77);
  EXPECT_NEAR(Theta(sample.wi), 0.174533, 1e-12);
  EXPECT_NEAR(Theta(sample.wo), 0.283794, 1e-12);
  // phi_s = -2.356194 (-135 deg); Phi() reports azimuths in [0, 2 pi).
  EXPECT_NEAR(Phi(sample.wo), 2 * kPi - 2.356194, 1e-12);
  const Rgb expected = SpectrumToRgb(CornellWavelengths(), Illuminant::kD65)(spectrum.data());
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sample.value[c], expected[c], 1e-15) << c;
  // A blue-green paint: the spectrum peaks at 490 nm, so blue > red.
  EXPECT_GT(sample.value[2], sample.value[0]);
}

TEST(Astm, MetadataStatesSourceAndAssumptions) {
  const Measurement m = ReadAstm(DataPath("cornell-astm/cayman.astm"), {});
  EXPECT_EQ(m.metadata.at("sample"), "Cayman Metallic");
  EXPECT_EQ(m.metadata.at("sample_type"), "High-gloss Paint");
  EXPECT_EQ(m.metadata.at("lab"), "Cornell University, Program of Computer Graphics");
  EXPECT_EQ(m.metadata.at("instrument"), "Cornell/Kodak gonioreflectometer");
  EXPECT_EQ(m.metadata.at("operator"), "Eric P. F. Lafortune");
  EXPECT_EQ(m.metadata.at("comments"), "Ford Cayman lacquer");
  EXPECT_EQ(m.metadata.at("illuminant"), "D65");
  EXPECT_EQ(m.metadata.at("spectral"), "31 bands 400-700 nm -> RGB via CIE 1931 2deg");
  EXPECT_EQ(m.metadata.at("units"), "sr^-1");
  EXPECT_EQ(m.metadata.at("negative_spectral_values"), "0");
}

TEST(Astm, IlluminantOptionIsUsedAndRecorded) {
  ReadOptions options;
  options.illuminant = Illuminant::kE;
  const std::string path = DataPath("cornell-astm/cayman.astm");
  const Measurement e = ReadAstm(path, options);
  const Measurement d65 = ReadAstm(path, {});
  EXPECT_EQ(e.metadata.at("illuminant"), "E");
  // Same geometry, different colour: a coloured spectrum looks different under E and D65.
  EXPECT_EQ(e.samples[77].wo, d65.samples[77].wo);
  EXPECT_GT((e.samples[77].value - d65.samples[77].value).abs().maxCoeff(), 1e-6);
}

// A spectrally flat BRDF v becomes (v, v, v) under either illuminant (core/colour.h).
TEST(Astm, FlatSpectrumIsGrey) {
  ScratchDir dir;
  std::string vars = "VARS theta_i,phi_i,theta_s,phi_s";
  std::string row = "0.5,0,0.25,3.14159";
  for (int lambda = 400; lambda <= 700; lambda += 10) {
    vars += "," + std::to_string(lambda) + "nm";
    row += ",0.25";
  }
  const std::string path = dir.Write("flat.astm", "NUM_POINTS 1\n" + vars + "\n" + row + "\n");
  for (Illuminant illuminant : {Illuminant::kD65, Illuminant::kE}) {
    ReadOptions options;
    options.illuminant = illuminant;
    const Measurement m = ReadAstm(path, options);
    ASSERT_EQ(m.samples.size(), 1u);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.samples[0].value[c], 0.25, 1e-12);
    // No SAMPLE_NAME: the file name stands in (Measurement::SampleName).
    EXPECT_EQ(m.SampleName(), "flat.astm");
  }
}

// Negative spectral values are measurement noise, not a format error: kept and counted.
TEST(Astm, NegativeSpectralValuesAreDataAndCounted) {
  ScratchDir dir;
  const std::string path = dir.Write("negative.astm",
                                     "NUM_POINTS 2\nVARS theta_i,phi_i,theta_s,phi_s,500nm,600nm\n"
                                     "0.1,0,0.2,0,-0.001,0.5\n0.1,0,0.3,0,-0.002,-0.003\n");
  const Measurement m = ReadAstm(path, {});
  ASSERT_EQ(m.samples.size(), 2u);
  EXPECT_EQ(m.metadata.at("negative_spectral_values"), "3");
  EXPECT_EQ(m.metadata.at("spectral"), "2 bands 500-600 nm -> RGB via CIE 1931 2deg");
  EXPECT_LT(Luminance(m.samples[1].value), 0.0);
}

TEST(Astm, SniffsByContent) {
  EXPECT_TRUE(SniffAstm(Head(DataPath("cornell-astm/cayman.astm")), 455350));
  EXPECT_TRUE(SniffAstm("SAMPLE_NAME x\nNUM_POINTS 3\n", 30));
  EXPECT_FALSE(SniffAstm(Head(DataPath("cornell-pbrt-v2/cayman.brdf")), 456436));
  EXPECT_FALSE(
      SniffAstm(Head(DataPath("zemax-bsdf/test_13_planesymmetric_brdf_zemax.bsdf")), 27758));
  EXPECT_FALSE(SniffAstm("# brdfkit measurement v1\n", 25));
  // Content decides, not the extension.
  ScratchDir dir;
  const std::string renamed =
      dir.Write("cayman.txt", testing::ReadFileText(DataPath("cornell-astm/cayman.astm")));
  EXPECT_EQ(ReadMeasurement(renamed).format, "astm");
}

// ---------------------------------------------------------------------------------------------
// pbrt-v2 .brdf against the real files.

TEST(Pbrt, CaymanFirstRecordAndMetadata) {
  const Measurement m = ReadPbrtBrdf(DataPath("cornell-pbrt-v2/cayman.brdf"), {});
  ASSERT_EQ(m.samples.size(), 1439u);
  EXPECT_EQ(m.format, "pbrt-brdf");
  EXPECT_NEAR(Theta(m.samples[0].wi), 0.872665, 1e-12);
  EXPECT_NEAR(Theta(m.samples[0].wo), 0.573513, 1e-12);
  // Header comments "# Cornell University, ...", "# Cayman Metallic", "# High-gloss Paint".
  EXPECT_EQ(m.metadata.at("sample"), "Cayman Metallic");
  EXPECT_EQ(m.metadata.at("comments"),
            "Cornell University, Program of Computer Graphics; Cayman Metallic; "
            "High-gloss Paint");
  EXPECT_EQ(m.metadata.at("illuminant"), "D65");
  EXPECT_EQ(m.metadata.at("spectral"), "31 bands 400-700 nm -> RGB via CIE 1931 2deg");
  EXPECT_EQ(m.metadata.at("units"), "sr^-1");
}

// acryl_blue.brdf opens directly with "# num wls": no description, so the file names it (without
// its extension).
TEST(Pbrt, FileWithoutHeaderCommentsIsNamedByItsFile) {
  const Measurement m = ReadPbrtBrdf(DataPath("cornell-pbrt-v2/acryl_blue.brdf"), {});
  EXPECT_EQ(m.samples.size(), 1439u);
  EXPECT_EQ(m.metadata.at("sample"), "acryl_blue");
  EXPECT_EQ(m.metadata.count("comments"), 0u);
}

// krylon_blue.brdf, line 2: "# Krylon spray enamel 7205, "True Blue"; overcoat Plasti-kote 33
// Glass Frosting Spray": the name is the first clause; the whole line stays in the comments.
TEST(Pbrt, ADescriptiveCommentIsNamedByItsFirstClause) {
  const Measurement m = ReadPbrtBrdf(DataPath("cornell-pbrt-v2/krylon_blue.brdf"), {});
  EXPECT_EQ(m.SampleName(), "Krylon spray enamel 7205, \"True Blue\"");
  EXPECT_NE(m.metadata.at("comments").find("overcoat Plasti-kote 33 Glass Frosting Spray"),
            std::string::npos);
}

// mystique.brdf exists only in this layout: "# Ford Mystic lacquer (BASF, 2-2-95)" on line 2.
TEST(Pbrt, MystiqueReadsOnlyInPbrtLayout) {
  const Measurement m = ReadPbrtBrdf(DataPath("cornell-pbrt-v2/mystique.brdf"), {});
  EXPECT_EQ(m.samples.size(), 1439u);
  EXPECT_EQ(m.metadata.at("sample"), "Ford Mystic lacquer (BASF, 2-2-95)");
  // Line 12: 0.872665 0.000000 0.573513 0.000000 0.014082 0.005146 ...: reddish at 400 nm
  // falling fast, a red-purple lacquer.
  EXPECT_NEAR(Theta(m.samples[0].wo), 0.573513, 1e-12);
}

TEST(Pbrt, SniffsOnlyTheNumWlsComment) {
  EXPECT_TRUE(SniffPbrtBrdf(Head(DataPath("cornell-pbrt-v2/cayman.brdf")), 456436));
  EXPECT_TRUE(SniffPbrtBrdf(Head(DataPath("cornell-pbrt-v2/acryl_blue.brdf")), 456291));
  EXPECT_FALSE(SniffPbrtBrdf(Head(DataPath("cornell-astm/cayman.astm")), 455350));
  EXPECT_FALSE(SniffPbrtBrdf("# just a comment\n31\n", 20));
  ScratchDir dir;
  const std::string renamed =
      dir.Write("cayman.dat", testing::ReadFileText(DataPath("cornell-pbrt-v2/cayman.brdf")));
  EXPECT_EQ(ReadMeasurement(renamed).format, "pbrt-brdf");
}

// pbrt ignores line breaks; records may wrap onto following lines as long as each starts on a
// new line.
TEST(Pbrt, WrappedRecordsAndCommentsAnywhere) {
  ScratchDir dir;
  const std::string path =
      dir.Write("wrapped.brdf",
                "# lab\n# Sample X\n# num wls\n2 # two\n500\n600\n"
                "0.1 0 0.2 0  # angles\n0.5 0.5\n0.2 0 0.3 3.14159 0.25 0.25\n");
  const Measurement m = ReadPbrtBrdf(path, {});
  ASSERT_EQ(m.samples.size(), 2u);
  EXPECT_EQ(m.metadata.at("sample"), "Sample X");
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.samples[0].value[c], 0.5, 1e-12);
  EXPECT_NEAR(Theta(m.samples[1].wo), 0.3, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// The same four Cornell measurements in both layouts (../shared/data-real/README.md: max
// difference < 1e-9): a two-reader cross-check.

TEST(Cornell, AstmAndPbrtLayoutsAgree) {
  for (const char* name : {"acryl_blue", "cayman", "garnet_red", "krylon_blue"}) {
    SCOPED_TRACE(name);
    const Measurement astm = ReadAstm(DataPath(std::string("cornell-astm/") + name + ".astm"), {});
    const Measurement pbrt =
        ReadPbrtBrdf(DataPath(std::string("cornell-pbrt-v2/") + name + ".brdf"), {});
    ASSERT_EQ(astm.samples.size(), 1439u);
    ASSERT_EQ(pbrt.samples.size(), astm.samples.size());
    double worst = 0.0;
    for (size_t k = 0; k < astm.samples.size(); ++k) {
      worst = std::max(worst, (astm.samples[k].wi - pbrt.samples[k].wi).lpNorm<Eigen::Infinity>());
      worst = std::max(worst, (astm.samples[k].wo - pbrt.samples[k].wo).lpNorm<Eigen::Infinity>());
      worst = std::max(worst, (astm.samples[k].value - pbrt.samples[k].value).abs().maxCoeff());
    }
    EXPECT_LE(worst, 1e-9);
    EXPECT_EQ(astm.metadata.at("spectral"), pbrt.metadata.at("spectral"));
  }
}

// Physics of the data: all directions are unit vectors above the surface, the samples cover
// incidences 10..80 deg (0.174533..1.396263 rad in the files), and the blue paints are blue.
TEST(Cornell, DirectionsAreAboveTheSurfaceAndColoursPlausible) {
  const Measurement blue = ReadAstm(DataPath("cornell-astm/krylon_blue.astm"), {});
  const Measurement red = ReadAstm(DataPath("cornell-astm/garnet_red.astm"), {});
  double theta_i_min = 10, theta_i_max = 0;
  Rgb blue_sum = Rgb::Zero(), red_sum = Rgb::Zero();
  for (size_t k = 0; k < blue.samples.size(); ++k) {
    const Sample& sample = blue.samples[k];
    EXPECT_NEAR(sample.wi.norm(), 1.0, 1e-12);
    EXPECT_NEAR(sample.wo.norm(), 1.0, 1e-12);
    EXPECT_GE(sample.wi.z(), 0.0);
    EXPECT_GE(sample.wo.z(), 0.0);
    theta_i_min = std::min(theta_i_min, Theta(sample.wi));
    theta_i_max = std::max(theta_i_max, Theta(sample.wi));
    blue_sum += sample.value;
    red_sum += red.samples[k].value;
  }
  // The spectra are non-negative, yet saturated blues fall outside the sRGB gamut: some
  // samples get a negative channel, and the metadata counts them.
  EXPECT_EQ(blue.metadata.at("negative_spectral_values"), "0");
  const auto out_of_gamut =
      std::count_if(blue.samples.begin(), blue.samples.end(),
                    [](const Sample& sample) { return (sample.value < 0).any(); });
  EXPECT_GT(out_of_gamut, 0);
  const std::string gamut_note = blue.metadata.at("rgb_out_of_gamut");
  EXPECT_EQ(gamut_note.substr(0, gamut_note.find(' ')), std::to_string(out_of_gamut));
  EXPECT_NEAR(RadToDeg(theta_i_min), 10.0, 1e-4);
  EXPECT_NEAR(RadToDeg(theta_i_max), 80.0, 1e-4);
  EXPECT_GT(blue_sum[2], blue_sum[0]);
  EXPECT_GT(red_sum[0], red_sum[2]);
}

// ---------------------------------------------------------------------------------------------
// Hostile inputs. Each case names the expected line; the reader must throw an InputError whose
// message names the file and that line, and `brdf info` must exit 2 with that one line.

struct SpectralHostileCase {
  const char* name;  // file name, with the extension that routes it to the reader
  std::string contents;
  int line;  // expected "line N"
};

using Reader = Measurement (*)(const std::string&, const ReadOptions&);

void ExpectRejected(Reader read, const std::vector<SpectralHostileCase>& cases) {
  ScratchDir dir;
  for (const SpectralHostileCase& hostile : cases) {
    SCOPED_TRACE(hostile.name);
    const std::string path = dir.Write(hostile.name, hostile.contents);
    const std::string where = "line " + std::to_string(hostile.line) + ":";
    try {
      read(path, {});
      ADD_FAILURE() << "accepted";
    } catch (const InputError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(path), std::string::npos) << message;
      EXPECT_NE(message.find(where), std::string::npos) << message;
    }
  }
}

// Through the command line: exit status 2, exactly one line on stderr naming file and line.
// An empty file is refused before any reader sees it, at byte 0.
void ExpectCliRejects(const std::vector<SpectralHostileCase>& cases) {
  ScratchDir dir;
  for (const SpectralHostileCase& hostile : cases) {
    SCOPED_TRACE(hostile.name);
    const std::string path = dir.Write(hostile.name, hostile.contents);
    const testing::CommandResult result = RunBrdf("info '" + path + "'");
    EXPECT_EQ(result.exit_status, 2) << result.err;
    EXPECT_EQ(testing::CountLines(result.err), 1) << result.err;
    EXPECT_NE(result.err.find(path), std::string::npos) << result.err;
    const std::string where =
        hostile.contents.empty() ? "byte 0" : "line " + std::to_string(hostile.line) + ":";
    EXPECT_NE(result.err.find(where), std::string::npos) << result.err;
  }
}

// The real cayman.astm: lines 1-21 header (NUM_POINTS on 20, VARS on 21), 22 blank, rows from
// 23. `Astm(n, rows)` is that header with NUM_POINTS n followed by `rows` real rows.
std::string AstmFile(int num_points, int rows) {
  const std::string text = testing::ReadFileText(DataPath("cornell-astm/cayman.astm"));
  return testing::Lines(text, 1, 19) + "NUM_POINTS " + std::to_string(num_points) + "\n" +
         testing::Lines(text, 21, 22 + rows);
}

std::vector<SpectralHostileCase> AstmHostileCases() {
  const std::string good = AstmFile(3, 3);  // rows on lines 23, 24, 25
  const std::string row25 = testing::Lines(good, 25, 25);
  return {
      {"empty.astm", "", 1},
      {"truncated-rows.astm", AstmFile(1439, 3), 25},
      {"truncated-mid-row.astm", good.substr(0, good.size() - row25.size() / 2), 25},
      {"wrong-vars.astm", ReplaceFirst(good, "VARS theta_i,phi_i", "VARS phi_i,theta_i"), 21},
      {"vars-not-wavelength.astm", ReplaceFirst(good, ",700nm", ",BRDF"), 21},
      {"vars-decreasing.astm", ReplaceFirst(good, "400nm,410nm", "410nm,400nm"), 21},
      {"no-num-points.astm", ReplaceFirst(good, "NUM_POINTS 3\n", "\n"), 23},
      {"huge-num-points.astm", ReplaceFirst(good, "NUM_POINTS 3", "NUM_POINTS 999999999999"), 20},
      {"too-many-rows.astm", ReplaceFirst(good, "NUM_POINTS 3", "NUM_POINTS 2"), 25},
      {"columns.astm", ReplaceFirst(good, ",0.001869\n", "\n"), 24},
      {"non-number.astm", ReplaceFirst(good, "0.001945", "0.00l945"), 24},
      {"nan.astm", ReplaceFirst(good, "0.001945", "nan"), 24},
      {"inf.astm", ReplaceFirst(good, "0.001945", "inf"), 24},
      {"theta-out-of-range.astm",
       ReplaceFirst(good, "0.698132,0.000000,0.427512", "0.698132,0.000000,1.6"), 24},
      {"degrees-not-radians.astm", ReplaceFirst(good, "0.349066,0.000000", "20,0.000000"), 25},
      {"phi-out-of-range.astm", ReplaceFirst(good, "0.427512,-0.261799", "0.427512,-7.0"), 24},
  };
}

TEST(Astm, HostileInputsNameFileAndLine) { ExpectRejected(&ReadAstm, AstmHostileCases()); }

// The real file cut after 12 of its 1439 rows (line 34): the error says where the file ended.
TEST(Astm, TruncatedRealFileSaysWhereItEnded) {
  ScratchDir dir;
  const std::string path =
      dir.Write("cut.astm",
                testing::Lines(testing::ReadFileText(DataPath("cornell-astm/cayman.astm")), 1, 34));
  try {
    ReadAstm(path, {});
    ADD_FAILURE() << "accepted";
  } catch (const ParseError& error) {
    EXPECT_EQ(error.line(), 34);
    EXPECT_EQ(std::string(error.what()),
              path + ": line 34: expected 1439 data rows, found 12 (truncated?)");
  }
}

TEST(Astm, HostileInputsFailTheCliWithOneLine) { ExpectCliRejects(AstmHostileCases()); }

// The real cayman.brdf (CRLF line ends): comments on 1-3, "# num wls" 5, 31 on 6, the
// wavelengths on 9-10, records from 14.
std::string PbrtFile(int records) {
  return testing::Lines(testing::ReadFileText(DataPath("cornell-pbrt-v2/cayman.brdf")), 1,
                        13 + records);
}

std::vector<SpectralHostileCase> PbrtHostileCases() {
  const std::string good = PbrtFile(3);  // records on lines 14, 15, 16
  const std::string record16 = testing::Lines(good, 16, 16);
  const std::string no_records = PbrtFile(0);
  return {
      {"empty.brdf", "", 1},
      {"comments-only.brdf", "# num wls\r\n", 1},
      {"truncated-record.brdf", good.substr(0, good.size() - record16.size() / 2), 16},
      {"truncated-wavelengths.brdf", testing::Lines(good, 1, 9), 9},
      {"zero-wavelengths.brdf", ReplaceFirst(good, "# num wls\r\n31", "# num wls\r\n0"), 6},
      {"too-many-wavelengths.brdf", ReplaceFirst(good, "# num wls\r\n31", "# num wls\r\n5000"), 6},
      {"count-not-a-number.brdf", ReplaceFirst(good, "# num wls\r\n31", "# num wls\r\nthirty"), 6},
      {"wavelengths-decreasing.brdf", ReplaceFirst(good, "400 410", "410 400"), 9},
      {"short-line.brdf", ReplaceFirst(good, " 0.001869\r\n", "\r\n"), 15},
      {"long-line.brdf", ReplaceFirst(good, " 0.001869\r\n", " 0.001869 0.5\r\n"), 15},
      {"non-number.brdf", ReplaceFirst(good, "0.001945", "0.00l945"), 15},
      {"nan.brdf", ReplaceFirst(good, "0.001945", "NaN"), 15},
      {"theta-out-of-range.brdf",
       ReplaceFirst(good, "0.698132 0.000000 0.427512", "0.698132 0.000000 -0.5"), 15},
      {"degrees-not-radians.brdf", ReplaceFirst(good, "0.349066 0.000000", "20 0.000000"), 16},
      {"no-records.brdf", no_records, 13},
  };
}

TEST(Pbrt, HostileInputsNameFileAndLine) { ExpectRejected(&ReadPbrtBrdf, PbrtHostileCases()); }

TEST(Pbrt, HostileInputsFailTheCliWithOneLine) { ExpectCliRejects(PbrtHostileCases()); }

}  // namespace
}  // namespace brdf
