// Albedo of measured data through interpolation: a MERL table and scattered samples made from a
// Lambert model give back rho_d; holes in the data lower the reported coverage and raise a
// warning; the real Cornell files give finite albedos with the coverage warning (their samples
// stop near theta = 80 degrees).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "core/angles.h"
#include "core/errors.h"
#include "energy/albedo.h"
#include "energy/measured.h"
#include "io/formats.h"
#include "io/merl.h"
#include "test_util.h"

namespace brdf {
namespace {

// A MERL table holding rho / pi in every cell (the stored value is the BRDF over the scale).
std::shared_ptr<MerlTable> LambertTable(const Rgb& rho) {
  auto table = std::make_shared<MerlTable>();
  for (int c = 0; c < 3; ++c) {
    for (int64_t cell = 0; cell < MerlTable::kCells; ++cell) {
      table->raw(c, cell) = rho[c] * kInvPi / MerlTable::kScale[c];
    }
  }
  return table;
}

AlbedoOptions FewAngles(int steps) {
  AlbedoOptions options;
  options.theta_steps = steps;
  return options;
}

TEST(MeasuredAlbedo, MerlTableOfLambertGivesRhoD) {
  const Rgb rho(0.7, 0.4, 0.1);
  const AlbedoCurve curve =
      MeasuredAlbedoCurve(MerlMeasuredBrdf(LambertTable(rho), "lambert.binary"), FewAngles(10));
  for (const AlbedoPoint& point : curve.points) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(point.estimate.albedo[c], rho[c], 1e-6);
    EXPECT_NEAR(point.estimate.coverage, 1.0, 1e-9);
  }
  EXPECT_TRUE(curve.warnings.empty());
  EXPECT_EQ(curve.verdict().conservation, Conservation::kConserving);
}

TEST(MeasuredAlbedo, MissingMerlCellsLowerCoverageAndWarn) {
  // Remove every cell with theta_d above 60 degrees: configurations far from retro-reflection,
  // which at grazing incidence make up much of the hemisphere.
  std::shared_ptr<MerlTable> table = LambertTable(Rgb::Constant(0.5));
  for (int theta_h = 0; theta_h < MerlTable::kThetaHalfBins; ++theta_h) {
    for (int theta_d = 60; theta_d < MerlTable::kThetaDiffBins; ++theta_d) {
      for (int phi_d = 0; phi_d < MerlTable::kPhiDiffBins; ++phi_d) {
        for (int c = 0; c < 3; ++c)
          table->raw(c, MerlTable::CellIndex(theta_h, theta_d, phi_d)) = -1;
      }
    }
  }
  AlbedoOptions options = FewAngles(5);
  const AlbedoCurve curve = MeasuredAlbedoCurve(MerlMeasuredBrdf(table, "holes.binary"), options);
  const AlbedoPoint& grazing = curve.points.back();
  EXPECT_LT(grazing.estimate.coverage, 0.9);
  // Holes count as zero: the albedo there is rho_d times the covered share.
  EXPECT_NEAR(grazing.estimate.albedo[0], 0.5 * grazing.estimate.coverage, 2e-3);
  ASSERT_FALSE(curve.warnings.empty());
  EXPECT_NE(curve.warnings[0].find("cover"), std::string::npos);
}

// Scattered samples of a Lambert BRDF on a coarse grid up to theta = 80 degrees.
Measurement ScatteredLambert(double rho) {
  Measurement measurement;
  measurement.format = "native-csv";
  measurement.source = "lambert.csv";
  for (double theta_i = 0; theta_i <= 80; theta_i += 10) {
    for (double theta_o = 0; theta_o <= 80; theta_o += 5) {
      for (double phi_o = 0; phi_o <= 180; phi_o += 15) {
        Sample sample;
        sample.wi = SphericalDirection(DegToRad(theta_i), 0.0);
        sample.wo = SphericalDirection(DegToRad(theta_o), DegToRad(phi_o));
        sample.value = Rgb::Constant(rho * kInvPi);
        measurement.samples.push_back(sample);
      }
    }
  }
  return measurement;
}

TEST(MeasuredAlbedo, ScatteredLambertGivesRhoDAndWarnsAboveItsData) {
  AlbedoOptions options = FewAngles(4);  // 0, 29.67, 59.33, 89
  const AlbedoCurve curve =
      MeasuredAlbedoCurve(ScatteredMeasuredBrdf(ScatteredLambert(0.6)), options);
  for (const AlbedoPoint& point : curve.points) {
    // Inverse-distance weights of equal values reproduce them exactly.
    EXPECT_NEAR(point.estimate.albedo[0], 0.6, 1e-6) << point.theta_deg;
  }
  // Nothing above 80 degrees: at theta = 89 much of the hemisphere is extrapolated.
  EXPECT_GT(curve.points[1].estimate.coverage, curve.points.back().estimate.coverage);
  ASSERT_FALSE(curve.warnings.empty());
  EXPECT_FALSE(curve.notes.empty());
}

TEST(MeasuredAlbedo, CornellPaintGivesFiniteAlbedoWithCoverageWarning) {
  const Measurement cayman = ReadMeasurement(testing::DataPath("cornell-astm/cayman.astm"));
  AlbedoOptions options = FewAngles(4);
  const AlbedoCurve curve = MeasuredAlbedoCurve(ScatteredMeasuredBrdf(cayman), options);
  for (const AlbedoPoint& point : curve.points) {
    EXPECT_TRUE(point.estimate.albedo.allFinite()) << point.theta_deg;
    EXPECT_GT(point.estimate.albedo.maxCoeff(), 0.0) << point.theta_deg;
  }
  // The samples stop at theta = 80 degrees.
  EXPECT_LT(curve.points.back().estimate.coverage, 0.99);
  EXPECT_FALSE(curve.warnings.empty());
}

TEST(MeasuredAlbedo, ImportanceSamplingNeedsAModel) {
  AlbedoOptions options = FewAngles(2);
  options.method = AlbedoMethod::kImportance;
  EXPECT_THROW(
      MeasuredAlbedoCurve(MerlMeasuredBrdf(LambertTable(Rgb::Constant(0.5)), "x.binary"), options),
      UsageError);
}

TEST(MeasuredAlbedo, MonteCarloOnMerlAgreesWithQuadrature) {
  AlbedoOptions options = FewAngles(3);
  options.method = AlbedoMethod::kMonteCarlo;
  options.samples = 4096;
  const AlbedoCurve curve =
      MeasuredAlbedoCurve(MerlMeasuredBrdf(LambertTable(Rgb::Constant(0.3)), "x.binary"), options);
  // Cosine sampling of a constant BRDF has zero variance: pi f = rho_d at every draw.
  for (const AlbedoPoint& point : curve.points) {
    EXPECT_NEAR(point.estimate.albedo[0], 0.3, 1e-9);
  }
}

}  // namespace
}  // namespace brdf
