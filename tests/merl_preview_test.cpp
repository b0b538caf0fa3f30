// The MERL table as a preview draws it (io/merl_preview.h): missing cells take the value of the
// nearest valid cell in the table's own index space (planted cells at known distances), and
// lookups are trilinear between cell centres in the table's coordinates (values linear in the
// cell index come back linear in between, and exact at the centres).
#include "io/merl_preview.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "core/angles.h"
#include "io/merl.h"

namespace brdf {
namespace {

// A value per channel in sr^-1, stored unscaled as the file holds it.
void Plant(MerlTable* table, int64_t cell, const Rgb& value) {
  for (int c = 0; c < 3; ++c) table->raw(c, cell) = value[c] / MerlTable::kScale[c];
}

TEST(MerlPreview, MissingCellsTakeTheNearestValidCell) {
  MerlTable table;  // every cell missing
  const Rgb a(0.1, 0.2, 0.3), b(2.0, 3.0, 4.0);
  Plant(&table, MerlTable::CellIndex(10, 20, 30), a);
  Plant(&table, MerlTable::CellIndex(10, 20, 40), b);
  const MerlPreviewTable preview(table);
  EXPECT_EQ(preview.filled_cells(), MerlTable::kCells - 2);
  auto near = [&](const Rgb& got, const Rgb& expected) {
    return (got - expected).cwiseAbs().maxCoeff() < 1e-6 * expected.maxCoeff();
  };
  // Along phi_d: 3 bins from a, 7 from b; 3 from b, 7 from a.
  EXPECT_TRUE(near(preview.Cell(MerlTable::CellIndex(10, 20, 33)), a));
  EXPECT_TRUE(near(preview.Cell(MerlTable::CellIndex(10, 20, 37)), b));
  // phi_d is periodic: bin 179 lies 31 bins from bin 30 the short way round, 41 from bin 40.
  EXPECT_TRUE(near(preview.Cell(MerlTable::CellIndex(10, 20, 179)), a));
  // Far along theta_h and theta_d: Manhattan distances 40 + 5 (to a) against 40 + 5 + 10.
  EXPECT_TRUE(near(preview.Cell(MerlTable::CellIndex(50, 25, 30)), a));
  EXPECT_TRUE(near(preview.Cell(MerlTable::CellIndex(89, 89, 45)), b));
  // The valid cells keep their own values.
  EXPECT_TRUE(near(preview.Cell(MerlTable::CellIndex(10, 20, 30)), a));
  EXPECT_TRUE(near(preview.Cell(MerlTable::CellIndex(10, 20, 40)), b));

  // A lookup in a missing cell beside valid ones gives a value, where the reader's evaluator
  // gives NaN (the renderer would draw it black).
  Vec3 wi, wo;
  FromHalfDiff(MerlTable::CellCentre(10, 20, 35), &wi, &wo);
  EXPECT_TRUE(std::isnan(table.Lookup(wi, wo)[0]));
  const Rgb value = preview.Eval(wi, wo);
  ASSERT_TRUE(value.allFinite());
  EXPECT_GT(value.minCoeff(), 0.0);
  // The same evaluator is what the reader's capability hands to previews.
  const auto tabulated = MerlTabulated(std::make_shared<const MerlTable>(table));
  const std::shared_ptr<const TabulatedBrdf> for_preview = tabulated->PreviewEvaluator();
  ASSERT_NE(for_preview, nullptr);
  EXPECT_TRUE(near(for_preview->Eval(wi, wo), value));
  EXPECT_TRUE(std::isnan(tabulated->Eval(wi, wo)[0]));  // energy and fits still see the hole
}

TEST(MerlPreview, EmptyTableStaysWithoutValue) {
  const MerlPreviewTable preview{MerlTable()};
  EXPECT_EQ(preview.filled_cells(), 0);
  EXPECT_TRUE(std::isnan(preview.Eval(SphericalDirection(0.3, 0.0), Vec3(0, 0, 1))[0]));
}

TEST(MerlPreview, TrilinearBetweenCellCentresInTheTablesOwnCoordinates) {
  // Values linear in each cell index: h + 2 d + 0.5 p (red), constants in the other channels.
  MerlTable table;
  for (int h = 0; h < MerlTable::kThetaHalfBins; ++h) {
    for (int d = 0; d < MerlTable::kThetaDiffBins; ++d) {
      for (int p = 0; p < MerlTable::kPhiDiffBins; ++p) {
        Plant(&table, MerlTable::CellIndex(h, d, p), Rgb(1.0 + h + 2.0 * d + 0.5 * p, 1.0, 2.0));
      }
    }
  }
  const MerlPreviewTable preview(table);
  EXPECT_EQ(preview.filled_cells(), 0);
  // At a cell centre: the cell's value (the nearest-cell lookup agrees there).
  Vec3 wi, wo;
  FromHalfDiff(MerlTable::CellCentre(30, 40, 50), &wi, &wo);
  EXPECT_NEAR(preview.Eval(wi, wo)[0], 1.0 + 30 + 80 + 25, 1e-4);
  EXPECT_NEAR(preview.Eval(wi, wo)[2], 2.0, 1e-6);
  // Between centres, at fractions (0.25, 0.5, 0.75) of the way to the next centre along each
  // axis, in the table's coordinates: sqrt(theta_h) for theta_h, linear for theta_d, phi_d.
  HalfDiff hd;
  const double u_h = (30.5 + 0.25) / MerlTable::kThetaHalfBins;
  hd.theta_h = u_h * u_h * 0.5 * kPi;
  hd.theta_d = (40.5 + 0.5) / MerlTable::kThetaDiffBins * 0.5 * kPi;
  hd.phi_d = (50.5 + 0.75) / MerlTable::kPhiDiffBins * kPi;
  hd.phi_h = 1.0;  // isotropic: any phi_h
  FromHalfDiff(hd, &wi, &wo);
  EXPECT_NEAR(preview.Eval(wi, wo)[0], 1.0 + 30.25 + 2.0 * 40.5 + 0.5 * 50.75, 1e-4);
  // The nearest-cell lookup steps instead: one cell's value, a whole step (0.5 or more) away.
  EXPECT_GE(std::abs(table.Lookup(wi, wo)[0] - (1.0 + 30.25 + 2.0 * 40.5 + 0.5 * 50.75)), 0.2);
  // phi_d wraps around (period pi): halfway between the last centre and the first, the mean
  // of the last and the first cell.
  hd.phi_d = kPi - 1e-9;
  FromHalfDiff(hd, &wi, &wo);
  const double last = 1.0 + 30.25 + 81.0 + 0.5 * 179, first = 1.0 + 30.25 + 81.0;
  EXPECT_NEAR(preview.Eval(wi, wo)[0], 0.5 * (last + first), 1e-3);
}

}  // namespace
}  // namespace brdf
