// The MERL table as a preview draws it (DESIGN §8), the evaluator MerlTabulated hands out as its
// PreviewEvaluator (core/measurement.h):
//   * no holes: every missing cell takes the value of the nearest cell that has one, nearest
//     in the table's own index space (steps of one bin along theta_h, theta_d or phi_d, phi_d
//     periodic; ties go to the cell found first in a breadth-first search from all valid
//     cells). A lookup beside a missing cell near grazing then shows its neighbour, not black.
//   * interpolation in the table's own coordinates: trilinear between cell centres in
//     (sqrt(theta_h / (pi/2)) * 90, theta_d / (pi/2) * 90, phi_d / pi * 180), clamped at the
//     ends of theta_h and theta_d and periodic in phi_d (period pi, reciprocity). The
//     nearest-cell lookup of MerlTable::Lookup draws the square-root grid of theta_h as rings
//     around a highlight.
// Energy and fits keep MerlTable::Lookup, whose NaN counts a missing cell as a hole.
#pragma once

#include <memory>
#include <vector>

#include "core/measurement.h"
#include "io/merl.h"

namespace brdf {

class MerlPreviewTable : public TabulatedBrdf {
 public:
  explicit MerlPreviewTable(const MerlTable& table);

  // f in sr^-1 (DESIGN §1); NaN only when the table has no valid cell at all.
  Rgb Eval(const Vec3& wi, const Vec3& wo) const override;
  std::string Describe() const override;
  std::string LookupName() const override;

  // The value a cell holds after filling (sr^-1), and how many cells were filled.
  Rgb Cell(int64_t cell) const;
  int64_t filled_cells() const { return filled_cells_; }

 private:
  std::vector<float> values_;  // 3 per cell, cell-major (CellIndex order), in sr^-1
  int64_t filled_cells_ = 0;
  bool empty_ = false;  // no valid cell at all
};

std::shared_ptr<const TabulatedBrdf> MerlPreviewTabulated(const MerlTable& table);

}  // namespace brdf
