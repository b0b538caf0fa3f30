#include "io/merl_preview.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/angles.h"

namespace brdf {
namespace {

constexpr int kBins[3] = {MerlTable::kThetaHalfBins, MerlTable::kThetaDiffBins,
                          MerlTable::kPhiDiffBins};

// The lower of the two cells a coordinate u (in cell units, centres at i + 1/2) falls between
// and the weight of the upper one, clamped to the first and last centres.
void ClampedNeighbours(double u, int bins, int* lower, int* upper, double* t) {
  const double centred = std::clamp(u - 0.5, 0.0, double(bins - 1));
  *lower = std::min(static_cast<int>(centred), bins - 2);
  *upper = *lower + 1;
  *t = centred - *lower;
}

}  // namespace

MerlPreviewTable::MerlPreviewTable(const MerlTable& table) : values_(3 * MerlTable::kCells) {
  // Multi-source breadth-first search from every valid cell: each missing cell is reached first
  // from a nearest valid one (in steps of one bin) and copies its value.
  std::vector<int64_t> queue;
  queue.reserve(MerlTable::kCells);
  std::vector<char> known(MerlTable::kCells, 0);
  for (int64_t cell = 0; cell < MerlTable::kCells; ++cell) {
    bool valid = true;
    for (int c = 0; c < 3; ++c) valid = valid && table.raw(c, cell) >= 0.0;
    if (!valid) continue;
    for (int c = 0; c < 3; ++c) {
      values_[3 * cell + c] = static_cast<float>(table.raw(c, cell) * MerlTable::kScale[c]);
    }
    known[cell] = 1;
    queue.push_back(cell);
  }
  empty_ = queue.empty();
  for (size_t next = 0; next < queue.size(); ++next) {
    const int64_t cell = queue[next];
    const int index[3] = {static_cast<int>(cell / MerlTable::kRowCells),
                          static_cast<int>(cell / MerlTable::kPhiDiffBins % kBins[1]),
                          static_cast<int>(cell % MerlTable::kPhiDiffBins)};
    for (int axis = 0; axis < 3; ++axis) {
      for (int step : {-1, 1}) {
        int neighbour[3] = {index[0], index[1], index[2]};
        neighbour[axis] += step;
        if (axis == 2) {
          neighbour[2] = (neighbour[2] + kBins[2]) % kBins[2];  // phi_d is periodic
        } else if (neighbour[axis] < 0 || neighbour[axis] >= kBins[axis]) {
          continue;
        }
        const int64_t other = MerlTable::CellIndex(neighbour[0], neighbour[1], neighbour[2]);
        if (known[other]) continue;
        known[other] = 1;
        std::copy_n(&values_[3 * cell], 3, &values_[3 * other]);
        ++filled_cells_;
        queue.push_back(other);
      }
    }
  }
}

Rgb MerlPreviewTable::Cell(int64_t cell) const {
  if (empty_) return Rgb::Constant(std::numeric_limits<double>::quiet_NaN());
  return Rgb(values_[3 * cell], values_[3 * cell + 1], values_[3 * cell + 2]);
}

Rgb MerlPreviewTable::Eval(const Vec3& wi, const Vec3& wo) const {
  if (empty_) return Rgb::Constant(std::numeric_limits<double>::quiet_NaN());
  const HalfDiff hd = ToHalfDiff(wi, wo);
  int h[2], d[2], p[2];
  double t_h, t_d;
  ClampedNeighbours(std::sqrt(std::max(0.0, hd.theta_h) / (0.5 * kPi)) * kBins[0], kBins[0], &h[0],
                    &h[1], &t_h);
  ClampedNeighbours(hd.theta_d / (0.5 * kPi) * kBins[1], kBins[1], &d[0], &d[1], &t_d);
  // phi_d folded into [0, pi) (reciprocity); the cells wrap around.
  double phi_d = std::fmod(hd.phi_d, kPi);
  if (phi_d < 0.0) phi_d += kPi;
  const double u_p = phi_d / kPi * kBins[2] - 0.5;
  const double below = std::floor(u_p);
  const double t_p = u_p - below;
  p[0] = (static_cast<int>(below) + kBins[2]) % kBins[2];
  p[1] = (p[0] + 1) % kBins[2];
  const double weight_h[2] = {1.0 - t_h, t_h}, weight_d[2] = {1.0 - t_d, t_d},
               weight_p[2] = {1.0 - t_p, t_p};
  Rgb value = Rgb::Zero();
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b) {
      for (int c = 0; c < 2; ++c) {
        const double weight = weight_h[a] * weight_d[b] * weight_p[c];
        if (weight == 0.0) continue;
        const float* cell = &values_[3 * MerlTable::CellIndex(h[a], d[b], p[c])];
        value += weight * Rgb(cell[0], cell[1], cell[2]);
      }
    }
  }
  return value;
}

std::string MerlPreviewTable::Describe() const {
  return "MERL table: trilinear in (sqrt theta_h, theta_d, phi_d) between cell centres; " +
         std::to_string(filled_cells_) + " of " + std::to_string(MerlTable::kCells) +
         " missing cells take the nearest valid cell's value";
}

std::string MerlPreviewTable::LookupName() const {
  return "MERL table, trilinear in its grid, gaps from the nearest valid cell";
}

std::shared_ptr<const TabulatedBrdf> MerlPreviewTabulated(const MerlTable& table) {
  return std::make_shared<const MerlPreviewTable>(table);
}

}  // namespace brdf
