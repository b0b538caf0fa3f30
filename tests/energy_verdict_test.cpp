// The three energy verdicts (DESIGN §7), each from both sides: planted albedo curves whose
// numbers put them on one side of a rule or the other, analytic models that conserve or create
// energy, a noisy Monte Carlo curve that straddles 1 where the quadrature does not, and measured
// files whose largest albedo lies beyond, or within, the incidences they were measured at.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "energy/albedo.h"
#include "energy/measured.h"
#include "models/model_string.h"
#include "test_util.h"

namespace brdf {
namespace {

// A curve over 0..89 degrees in steps of 1, grey, with albedo `albedo(theta)` and error `error`
// everywhere, measured up to `measured_deg`.
template <typename Albedo>
AlbedoCurve PlantedCurve(Albedo albedo, double error, double measured_deg = 90.0) {
  AlbedoCurve curve;
  curve.source = "planted";
  for (int theta = 0; theta < 90; ++theta) {
    AlbedoPoint point;
    point.theta_deg = theta;
    point.estimate.albedo = Rgb::Constant(albedo(theta));
    point.estimate.error = Rgb::Constant(error);
    curve.points.push_back(point);
  }
  curve.largest_measured_incidence_deg = measured_deg;
  FinishAlbedoCurve(&curve);
  return curve;
}

// Peaks at `peak` at 60 degrees, falls to `peak` - 0.3 at 0 and 89.
AlbedoCurve PeakAt60(double peak, double error) {
  return PlantedCurve([peak](int theta) { return peak - 0.3 * std::abs(theta - 60) / 60.0; },
                      error);
}

Conservation VerdictOf(const AlbedoCurve& curve) { return curve.verdict().conservation; }

TEST(EnergyVerdict, TwiceTheErrorEstimateDecides) {
  // 1.05: excess 0.05. Error 0.01 puts 1 outside the 2-sigma interval, 0.05 inside.
  EXPECT_EQ(VerdictOf(PeakAt60(1.05, 0.01)), Conservation::kNotConserving);
  EXPECT_EQ(VerdictOf(PeakAt60(1.05, 0.05)), Conservation::kUndecided);
  // 0.95: margin 0.05, the same two errors.
  EXPECT_EQ(VerdictOf(PeakAt60(0.95, 0.01)), Conservation::kConserving);
  EXPECT_EQ(VerdictOf(PeakAt60(0.95, 0.05)), Conservation::kUndecided);
  // The reason gives the numbers: the albedo, its error, the interval.
  const EnergyVerdict straddling = PeakAt60(1.05, 0.05).verdict();
  EXPECT_EQ(straddling.reason,
            "albedo 1.0500 ± 0.05 (r, theta 60.0 deg) lies between 0.95 and 1.15 within twice "
            "its error estimate, on both sides of 1");
  const EnergyVerdict excess = PeakAt60(1.05, 0.01).verdict();
  EXPECT_EQ(excess.reason,
            "albedo 1.0500 ± 0.01 (r, theta 60.0 deg) exceeds 1 by 0.05, more than twice its "
            "error estimate");
}

TEST(EnergyVerdict, AnAlbedoAtTheResolutionOfOneIsAtTheBound) {
  // Within kAlbedoResolution (1e-4) of 1, rounding cannot flip the verdict either way.
  for (double peak : {1.0 - 5e-5, 1.0, 1.0 + 5e-5}) {
    const EnergyVerdict verdict = PeakAt60(peak, 1e-7).verdict();
    EXPECT_EQ(verdict.conservation, Conservation::kConserving) << peak << ": " << verdict.Text();
    EXPECT_NE(verdict.reason.find("at the bound"), std::string::npos) << verdict.reason;
  }
  EXPECT_EQ(VerdictOf(PeakAt60(1.0 + 3e-4, 1e-7)), Conservation::kNotConserving);
}

TEST(EnergyVerdict, AMaximumBeyondTheMeasuredIncidencesIsUndecided) {
  // Rising to 0.95 at 70 degrees, the last measured incidence, then on to 1.1875 at 89.
  const auto rising = [](int theta) {
    return theta <= 70 ? 0.9 + 0.05 * theta / 70.0 : 0.95 + 0.0125 * (theta - 70);
  };
  const AlbedoCurve measured_to_70 = PlantedCurve(rising, 0.001, 70.0);
  const EnergyVerdict verdict = measured_to_70.verdict();
  EXPECT_EQ(verdict.conservation, Conservation::kUndecided) << verdict.Text();
  EXPECT_NE(verdict.reason.find("theta 89.0 deg), lies beyond the largest measured incidence "
                                "(70.0 deg)"),
            std::string::npos)
      << verdict.reason;
  EXPECT_NE(verdict.reason.find("largest is 0.9500 ± 0.001 (r, theta 70.0 deg)"), std::string::npos)
      << verdict.reason;
  // The same curve measured everywhere: its excess is a finding.
  EXPECT_EQ(VerdictOf(PlantedCurve(rising, 0.001, 90.0)), Conservation::kNotConserving);
  // An excess within the measured incidences decides, wherever the maximum lies: measured to 80
  // the curve reaches 1.075 ± 0.001 there.
  EXPECT_EQ(VerdictOf(PlantedCurve(rising, 0.001, 80.0)), Conservation::kNotConserving);
  // Falling beyond the measured incidences: the maximum is measured, and below 1.
  const auto falling = [](int theta) { return 0.9 - 0.4 * theta / 89.0; };
  const EnergyVerdict measured = PlantedCurve(falling, 0.001, 70.0).verdict();
  EXPECT_EQ(measured.conservation, Conservation::kConserving) << measured.Text();
  EXPECT_NE(measured.reason.find("over the measured incidences (up to 70.0 deg)"),
            std::string::npos)
      << measured.reason;
}

TEST(EnergyVerdict, AnalyticModelsConserveOrCreateEnergy) {
  const EnergyVerdict ggx =
      ModelAlbedoCurve(ParseModel("ggx:rho_d=0.2:f0=0.04:alpha=0.2"), AlbedoOptions{}).verdict();
  EXPECT_EQ(ggx.conservation, Conservation::kConserving) << ggx.Text();
  EXPECT_NE(ggx.reason.find("stays below 1"), std::string::npos) << ggx.reason;
  // The lecture's (m+8)/pi: eight times the normalised lobe.
  const EnergyVerdict lecture =
      ModelAlbedoCurve(ParseModel("blinn-phong:rho_d=0:rho_s=8:m=100"), AlbedoOptions{}).verdict();
  EXPECT_EQ(lecture.conservation, Conservation::kNotConserving) << lecture.Text();
}

TEST(EnergyVerdict, NoisyMonteCarloStraddlesWhereTheQuadratureDecides) {
  // phong with rho_d + rho_s = 1 has albedo exactly 1 at normal incidence. 64 cosine samples
  // leave an error near 0.5 at its sharp lobe: the verdict cannot be had from them.
  const Model at_bound = ParseModel("phong:rho_d=0.5:rho_s=0.5:n=100");
  AlbedoOptions noisy;
  noisy.method = AlbedoMethod::kMonteCarlo;
  noisy.samples = 64;
  const AlbedoCurve noisy_curve = ModelAlbedoCurve(at_bound, noisy);
  const EnergyVerdict undecided = noisy_curve.verdict();
  EXPECT_EQ(undecided.conservation, Conservation::kUndecided) << undecided.Text();
  EXPECT_NE(undecided.reason.find("on both sides of 1"), std::string::npos) << undecided.reason;
  EXPECT_GT(noisy_curve.error_at_max.maxCoeff(), 0.05);
  // The quadrature resolves it to 1e-5: at the bound, conserving.
  const EnergyVerdict decided = ModelAlbedoCurve(at_bound, AlbedoOptions{}).verdict();
  EXPECT_EQ(decided.conservation, Conservation::kConserving) << decided.Text();
}

TEST(EnergyVerdict, SatinsMaximumLiesBeyondItsMeasuredIncidences) {
  // RGL-EPFL satin_rosaline: measured at theta_i up to 78.68 deg (its 90-degree incidence holds
  // no values); the tensor's extrapolation peaks above 1 near 85 deg, while at the measured
  // incidences the albedo stays within twice its error of 1.
  const AlbedoCurve satin = MeasuredAlbedoCurve(
      LoadMeasuredBrdf(testing::DataPath("rgl-bsdf/satin_rosaline_rgb.bsdf")), AlbedoOptions{});
  EXPECT_NEAR(satin.largest_measured_incidence_deg, 78.68, 0.01);
  EXPECT_GT(satin.theta_deg_at_max[0], 78.68);
  EXPECT_GT(satin.max_albedo[0], 1.1);
  const EnergyVerdict verdict = satin.verdict();
  EXPECT_EQ(verdict.conservation, Conservation::kUndecided) << verdict.Text();
  EXPECT_NE(verdict.reason.find("beyond the largest measured incidence (78.7 deg)"),
            std::string::npos)
      << verdict.reason;
  // White paper from the same instrument peaks inside its measured incidences, below 1.
  const AlbedoCurve paper = MeasuredAlbedoCurve(
      LoadMeasuredBrdf(testing::DataPath("rgl-bsdf/paper_white_rgb.bsdf")), AlbedoOptions{});
  EXPECT_LE(paper.theta_deg_at_max[1], paper.largest_measured_incidence_deg);
  EXPECT_EQ(paper.verdict().conservation, Conservation::kConserving) << paper.verdict().Text();
}

TEST(EnergyVerdict, RetroReflectorsNoisyMaximumStraddlesOne) {
  // The CEA gray tape (ALTA): three incidences, so the interpolated albedo near 30 deg carries an
  // error estimate larger than its distance to 1.
  const AlbedoCurve tape = MeasuredAlbedoCurve(
      LoadMeasuredBrdf(testing::DataPath("alta-retro/retro-gray-tape.dat")), AlbedoOptions{});
  const EnergyVerdict verdict = tape.verdict();
  EXPECT_EQ(verdict.conservation, Conservation::kUndecided) << verdict.Text();
  EXPECT_GT(tape.max_albedo[0], 1.0);
  EXPECT_LT(tape.max_albedo[0] - 2.0 * tape.error_at_max[0], 1.0);
  EXPECT_NE(verdict.reason.find("on both sides of 1"), std::string::npos) << verdict.reason;
}

}  // namespace
}  // namespace brdf
