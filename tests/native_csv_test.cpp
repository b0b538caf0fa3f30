// Native CSV: round trip through the writer and reader, and hostile inputs with line numbers.
#include <gtest/gtest.h>

#include "core/angles.h"
#include "core/errors.h"
#include "io/formats.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::ScratchDir;

constexpr const char* kHeader =
    "# brdfkit measurement v1\n# sample: test patch\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n";

TEST(NativeCsv, RoundTripKeepsValuesSigmaWeightAndMetadata) {
  ScratchDir dir;
  Measurement measurement;
  measurement.metadata["sample"] = "grey card";
  measurement.metadata["seed"] = "42";
  for (int k = 0; k < 20; ++k) {
    Sample sample;
    sample.wi = SphericalDirection(DegToRad(3.0 * k), DegToRad(10.0 * k));
    sample.wo = SphericalDirection(DegToRad(80.0 - 2.5 * k), DegToRad(181.0 + 7.0 * k));
    sample.value = Rgb(0.1 * k + 1e-7, 1.0 / 3.0, 12345.678);
    measurement.samples.push_back(sample);
    measurement.sigma.push_back(Rgb(0.01, 0.02, 0.03 * k));
    measurement.weight.push_back(0.5 + k);
  }
  const std::string path = dir.File("round.csv");
  WriteMeasurement(measurement, path);
  const Measurement read = ReadMeasurement(path);
  EXPECT_EQ(read.format, "native-csv");
  EXPECT_EQ(read.metadata.at("sample"), "grey card");
  EXPECT_EQ(read.metadata.at("seed"), "42");
  ASSERT_EQ(read.samples.size(), measurement.samples.size());
  ASSERT_TRUE(read.has_sigma());
  ASSERT_TRUE(read.has_weight());
  for (size_t k = 0; k < read.samples.size(); ++k) {
    // Values are written with round-trip precision; angles pass through degrees.
    EXPECT_TRUE((read.samples[k].value == measurement.samples[k].value).all());
    EXPECT_NEAR((read.samples[k].wi - measurement.samples[k].wi).norm(), 0.0, 1e-12);
    EXPECT_NEAR((read.samples[k].wo - measurement.samples[k].wo).norm(), 0.0, 1e-12);
    EXPECT_TRUE((read.sigma[k] == measurement.sigma[k]).all());
    EXPECT_EQ(read.weight[k], measurement.weight[k]);
  }
}

TEST(NativeCsv, AnglesAreDegreesInTheFrameOfDesign) {
  ScratchDir dir;
  const std::string path =
      dir.Write("one.csv", std::string(kHeader) + "30,0,60,180,0.5,0.25,0.125\n");
  const Measurement read = ReadMeasurement(path);
  ASSERT_EQ(read.samples.size(), 1u);
  EXPECT_NEAR(read.samples[0].wi.x(), 0.5, 1e-15);  // sin 30
  EXPECT_NEAR(read.samples[0].wi.z(), std::sqrt(3.0) / 2, 1e-15);
  EXPECT_NEAR(read.samples[0].wo.x(), -std::sqrt(3.0) / 2, 1e-15);  // phi 180: -x
  EXPECT_NEAR(read.samples[0].wo.z(), 0.5, 1e-15);
  EXPECT_EQ(read.samples[0].value[2], 0.125);
}

struct CsvHostileCase {
  const char* name;
  std::string contents;
  const char* where;  // expected in the message, e.g. "line 4"
};

TEST(NativeCsv, HostileInputsNameFileAndLine) {
  ScratchDir dir;
  const std::string header(kHeader);
  const std::vector<CsvHostileCase> cases = {
      {"wrong-magic.csv", "# some other v1\n" + header.substr(25), "line 1"},
      {"no-header.csv", "# brdfkit measurement v1\n# sample: x\n", "line 2"},
      {"bad-header.csv",
       "# brdfkit measurement v1\ntheta_i,phi_i,theta_s,phi_o,r,g,b\n1,2,3,4,5,6,7\n", "line 2"},
      {"columns.csv", header + "10,0,20,0,0.1,0.1,0.1\n10,0,20,0,0.1,0.1\n", "line 5"},
      {"non-number.csv", header + "10,0,20,zero,0.1,0.1,0.1\n", "line 4"},
      {"nan.csv", header + "10,0,20,0,nan,0.1,0.1\n", "line 4"},
      {"inf.csv", header + "10,0,20,0,0.1,inf,0.1\n", "line 4"},
      {"theta.csv", header + "10,0,95,0,0.1,0.1,0.1\n", "line 4"},
      {"theta-negative.csv", header + "-1,0,5,0,0.1,0.1,0.1\n", "line 4"},
      {"duplicate-key.csv",
       "# brdfkit measurement v1\n# sample: a\n# sample: b\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n",
       "line 3"},
      {"no-rows.csv", header, "line 3"},
      {"empty-field.csv", header + "10,,20,0,0.1,0.1,0.1\n", "line 4"},
      {"negative-sigma.csv",
       "# brdfkit measurement v1\ntheta_i,phi_i,theta_o,phi_o,r,g,b,sigma_r,sigma_g,sigma_b\n"
       "1,0,2,0,0.1,0.1,0.1,0.1,-0.1,0.1\n",
       "line 3"},
  };
  for (const CsvHostileCase& hostile : cases) {
    const std::string path = dir.Write(hostile.name, hostile.contents);
    try {
      ReadMeasurement(path);
      ADD_FAILURE() << hostile.name << " was accepted";
    } catch (const InputError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(path), std::string::npos) << message;
      EXPECT_NE(message.find(hostile.where), std::string::npos) << hostile.name << ": " << message;
    }
  }
}

TEST(NativeCsv, EmptyFileIsAnError) {
  ScratchDir dir;
  const std::string path = dir.Write("empty.csv", "");
  EXPECT_THROW(ReadMeasurement(path), InputError);
}

}  // namespace
}  // namespace brdf
