// The in-plane spectral gonio table (io/gonio_csv.cpp) against the real file in
// data/gonio-csv/: a row typed in by hand, the sign convention checked against the file's own
// specular peaks, the missing rows, and hostile inputs whose errors name the file and the line.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
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
using testing::RunBrdf;
using testing::ScratchDir;

const char* const kFile = "gonio-csv/test_brdf_viewer_2D_data.csv";

std::vector<double> FileWavelengths() {  // the header: 390nm .. 730nm every 10 nm
  std::vector<double> wavelengths;
  for (int lambda = 390; lambda <= 730; lambda += 10) wavelengths.push_back(lambda);
  return wavelengths;
}

TEST(GonioCsv, DetectedByItsHeaderAndCounted) {
  const std::string path = DataPath(kFile);
  EXPECT_EQ(DetectFormat(path).name, "gonio-csv");  // not the native CSV, which shares .csv
  const Measurement m = ReadMeasurement(path);
  EXPECT_EQ(m.format, "gonio-csv");
  ASSERT_EQ(m.samples.size(), 329u);  // 330 lines, one of them the header
  const MeasurementSummary summary = Summarize(m);
  EXPECT_EQ(summary.incidence_directions, 5u);  // 10, 25, 40, 60 and 80 deg
  EXPECT_NEAR(summary.theta_i_deg[0], 10.0, 1e-9);
  EXPECT_NEAR(summary.theta_i_deg[1], 80.0, 1e-9);
  EXPECT_NEAR(summary.theta_o_deg[1], 80.0, 1e-9);
  // 26 rows read 0 in all 35 bands (910 zero cells, all in those rows; counted with awk).
  EXPECT_EQ(summary.missing, 26u);
  EXPECT_EQ(m.metadata.at("incidences_deg"), "10, 25, 40, 60, 80");
  EXPECT_EQ(m.metadata.at("spectral"), "35 bands 390-730 nm -> RGB via CIE 1931 2deg");
  EXPECT_NE(m.metadata.at("units").find("ASSUMED"), std::string::npos);
  EXPECT_NE(m.metadata.at("geometry").find("ASSUMED"), std::string::npos);
}

// Line 38 of the file, typed in:
//   10,10,59.8637,60.7789,...,73.9149
// theta_i = 10 deg at azimuth 0: wi = (sin 10, 0, cos 10) = (0.1736482, 0, 0.9848078); the
// detector at +10 deg lies on the specular side: wo = (-0.1736482, 0, 0.9848078).
TEST(GonioCsv, ARowTypedInByHand) {
  const std::vector<double> spectrum = {
      59.8637, 60.7789, 61.7493, 62.8521, 63.8181, 64.5703, 65.2785, 65.7366, 66.2017,
      67.0294, 67.7442, 68.3159, 68.7991, 69.0106, 69.4207, 70.1119, 70.2961, 70.5799,
      71.0112, 71.267,  71.5336, 71.6152, 71.8233, 72.2856, 72.7676, 72.7017, 72.7004,
      72.9892, 73.0682, 73.3872, 73.4981, 73.726,  73.869,  73.9164, 73.9149};
  const std::string path = DataPath(kFile);
  ASSERT_EQ(testing::Lines(testing::ReadFileText(path), 38, 38).substr(0, 16), "10,10,59.8637,60");
  const Measurement m = ReadMeasurement(path);
  const Sample& sample = m.samples.at(36);  // line 38: the 37th data row
  EXPECT_NEAR(sample.wi.x(), 0.1736482, 1e-7);
  EXPECT_NEAR(sample.wi.y(), 0.0, 1e-12);
  EXPECT_NEAR(sample.wi.z(), 0.9848078, 1e-7);
  EXPECT_NEAR(sample.wo.x(), -0.1736482, 1e-7);
  EXPECT_NEAR(sample.wo.y(), 0.0, 1e-12);
  EXPECT_NEAR(sample.wo.z(), 0.9848078, 1e-7);
  EXPECT_FALSE(sample.missing);
  const Rgb expected = SpectrumToRgb(FileWavelengths(), Illuminant::kD65)(spectrum.data());
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sample.value[c], expected[c], 1e-12) << c;
  // A spectrum rising from 60 to 74 towards the red: red > blue.
  EXPECT_GT(sample.value[0], sample.value[2]);
  // Line 2, "10,-78,...": a negative angle puts the detector on the light's side.
  const Sample& first = m.samples.at(0);
  EXPECT_NEAR(first.wo.x(), std::sin(DegToRad(78)), 1e-12);
  EXPECT_NEAR(first.wo.z(), std::cos(DegToRad(78)), 1e-12);
}

// The convention the reader assumes is the one the data obey: at every incidence the brightest
// reading is the mirror direction of wi.
TEST(GonioCsv, EachIncidencePeaksInTheMirrorDirection) {
  const Measurement m = ReadMeasurement(DataPath(kFile));
  std::map<long, const Sample*> brightest;
  for (const Sample& sample : m.samples) {
    if (sample.missing) continue;
    const long incidence = std::lround(RadToDeg(Theta(sample.wi)));
    const Sample*& best = brightest[incidence];
    if (best == nullptr || sample.value.sum() > best->value.sum()) best = &sample;
  }
  ASSERT_EQ(brightest.size(), 5u);
  for (const auto& [incidence, sample] : brightest) {
    EXPECT_LT((sample->wo - MirrorDirection(sample->wi)).norm(), 1e-12) << incidence << " deg";
  }
}

TEST(GonioCsv, HostileInputsNameTheFileAndLine) {
  ScratchDir dir;
  const std::string header = "Incident_angle,Measure_angle,400nm,500nm,600nm\n";
  struct Case {
    std::string name, text, line, says;
  } cases[] = {
      {"order.csv", "Incident_angle,Measure_angle,500nm,400nm\n10,0,1,1\n", "line 1",
       "wavelengths must increase"},
      {"name.csv", "Incident_angle,Measure_angle,400nm,green\n10,0,1,1\n", "line 1",
       "is not a wavelength"},
      {"short.csv", header + "10,0,1,1\n", "line 2", "expected 5 comma-separated values"},
      {"incidence.csv", header + "90,0,1,1,1\n", "line 2", "Incident_angle 90 deg"},
      {"measure.csv", header + "10,0,1,1,1\n10,-95,1,1,1\n", "line 3", "Measure_angle -95 deg"},
      {"text.csv", header + "10,0,1,x,1\n", "line 2", "expected a number for a BRDF value"},
      {"nan.csv", header + "10,0,1,nan,1\n", "line 2", "finite number"},
      {"rows.csv", header, "line 1", "no data rows"},
  };
  for (const Case& c : cases) {
    const std::string path = dir.Write(c.name, c.text);
    const testing::CommandResult result = RunBrdf("info '" + path + "'");
    EXPECT_EQ(result.exit_status, 2) << c.name << "\n" << result.err;
    EXPECT_EQ(testing::CountLines(result.err), 1) << result.err;
    EXPECT_NE(result.err.find(path + ": " + c.line + ": "), std::string::npos) << result.err;
    EXPECT_NE(result.err.find(c.says), std::string::npos) << c.name << "\n" << result.err;
  }
}

// Binary bytes in a header that claims the format are quoted as '?', never printed raw.
TEST(GonioCsv, BinaryBytesAreNotPrinted) {
  ScratchDir dir;
  const std::string path = dir.Write(
      "binary.csv", std::string("Incident_angle,Measure_angle,400nm,\x01\xff\x1b[2Jnm\n"));
  const testing::CommandResult result = RunBrdf("info '" + path + "'");
  EXPECT_EQ(result.exit_status, 2) << result.err;
  EXPECT_EQ(result.err.find('\x1b'), std::string::npos);
  EXPECT_EQ(result.err.find('\xff'), std::string::npos);
  EXPECT_NE(result.err.find(path + ": line 1: "), std::string::npos) << result.err;
}

}  // namespace
}  // namespace brdf
