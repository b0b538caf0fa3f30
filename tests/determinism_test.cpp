// Determinism: the same inputs and seed give the same output bytes, run after run and for any
// thread count (docs/reliability.md). `brdf measure` is checked per sample kind in the gonio
// tests; here fit (library and command line) and render (PNG and EXR) with 1 and 2 threads.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <sstream>

#include "core/angles.h"
#include "fitters/fit.h"
#include "models/model_string.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::DataPath;
using testing::ReadFileText;
using testing::RunBrdf;
using testing::ScratchDir;

// Bitwise equality of doubles (NaN equal to NaN): "agrees to 1e-15" is not the claim.
void ExpectSameBits(const std::vector<double>& a, const std::vector<double>& b,
                    const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(std::memcmp(&a[k], &b[k], sizeof(double)), 0)
        << what << "[" << k << "]: " << a[k] << " vs " << b[k];
  }
}

// Random directions and a noisy glossy material, with a few outliers for the robust loss.
Measurement NoisyGloss(size_t count) {
  const Model truth = ParseModel("blinn-phong:rho_d=0.3,0.2,0.1:rho_s=0.2,0.25,0.3:m=120");
  Measurement measurement;
  measurement.format = "synthetic";
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gaussian;
  for (size_t k = 0; k < count; ++k) {
    Sample sample;
    sample.wi = SphericalDirection(std::acos(uniform(random)), 2 * kPi * uniform(random));
    sample.wo = SphericalDirection(std::acos(uniform(random)), 2 * kPi * uniform(random));
    sample.value = truth.Eval(sample.wi, sample.wo) * (1.0 + 0.02 * gaussian(random));
    if (k % 97 == 0) sample.value *= 10.0;  // outliers
    measurement.samples.push_back(sample);
  }
  return measurement;
}

TEST(Determinism, FitGivesTheSameBitsForOneAndTwoThreads) {
  const Measurement measurement = NoisyGloss(3000);
  // Huber: a subsample, a multi-start, a refinement, reweighting rounds and a polish on every
  // sample, so every stage of a fit (and of a plain one) is covered.
  fitters::FitOptions options;
  options.robust = fitters::Robust::kHuber;
  options.max_samples = 1000;
  options.start_exponents = {16, 256};
  options.threads = 1;
  const fitters::FitResult one = fitters::FitModel(measurement, "blinn-phong", options);
  options.threads = 2;
  const fitters::FitResult two = fitters::FitModel(measurement, "blinn-phong", options);
  const fitters::FitResult again = fitters::FitModel(measurement, "blinn-phong", options);
  ExpectSameBits(one.model.params(), two.model.params(), "params");
  ExpectSameBits(two.model.params(), again.model.params(), "params, second run");
  ExpectSameBits(one.stderr_values, two.stderr_values, "stderr");
  ExpectSameBits({one.metrics.rmse, one.metrics.log_rmse, one.bic, one.final_cost},
                 {two.metrics.rmse, two.metrics.log_rmse, two.bic, two.final_cost}, "metrics");
  EXPECT_EQ(one.iterations, two.iterations);
  EXPECT_TRUE(one.converged);
}

// The report without its one timing line ("time_s", DESIGN §6).
std::string WithoutTiming(const std::string& report) {
  std::istringstream lines(report);
  std::string line, kept;
  while (std::getline(lines, line)) {
    if (line.find("\"time_s\"") == std::string::npos) kept += line + "\n";
  }
  return kept;
}

TEST(Determinism, FitReportBytesDoNotDependOnThreads) {
  ScratchDir dir;
  const std::string common =
      "fit '" + DataPath("cornell-astm/cayman.astm") + "' --model blinn-phong --out ";
  std::vector<std::string> reports;
  for (const char* run : {"1", "2", "2"}) {
    const std::string path =
        dir.File(std::string("fit-") + run + "-" + std::to_string(reports.size()) + ".json");
    const testing::CommandResult result = RunBrdf(common + "'" + path + "' --threads " + run);
    ASSERT_EQ(result.exit_status, 0) << result.err;
    reports.push_back(ReadFileText(path));
    ASSERT_NE(reports.back().find("\"time_s\""), std::string::npos);
  }
  EXPECT_EQ(WithoutTiming(reports[0]), WithoutTiming(reports[1]));
  EXPECT_EQ(WithoutTiming(reports[1]), WithoutTiming(reports[2]));
}

TEST(Determinism, RenderBytesDoNotDependOnThreads) {
  ScratchDir dir;
  // An environment (importance sampling, auto exposure over the image) and a direct light.
  const std::string common =
      "render 'phong:rho_d=0.4,0.3,0.2:rho_s=0.3:n=80' --preset office --env '" +
      DataPath("hdr/memorial.hdr") + "' --size 48 --spp 4 --bloom dual --quiet --exr-type float";
  std::vector<std::string> png, exr;
  for (const char* threads : {"1", "2", "2"}) {
    const std::string name = std::to_string(png.size());
    const testing::CommandResult result =
        RunBrdf(common + " --threads " + threads + " --out '" + dir.File(name + ".png") +
                "' --exr '" + dir.File(name + ".exr") + "'");
    ASSERT_EQ(result.exit_status, 0) << result.err;
    png.push_back(ReadFileText(dir.File(name + ".png")));
    exr.push_back(ReadFileText(dir.File(name + ".exr")));
    ASSERT_FALSE(png.back().empty());
    ASSERT_FALSE(exr.back().empty());
  }
  EXPECT_TRUE(png[0] == png[1] && png[1] == png[2]) << "PNG bytes differ";
  EXPECT_TRUE(exr[0] == exr[1] && exr[1] == exr[2]) << "EXR bytes differ";
}

}  // namespace
}  // namespace brdf
