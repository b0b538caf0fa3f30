#include "gonio/detector_lookup.h"

#include <algorithm>
#include <cmath>

namespace brdf::gonio {

DetectorLookup::DetectorLookup(const std::vector<Vec3>& detectors, double cos_half_angle)
    : detectors_(detectors), cos_half_angle_(cos_half_angle) {
  std::vector<std::vector<int>> cells(kThetaCells * kPhiCells);
  const double radius = std::acos(cos_half_angle);
  for (size_t k = 0; k < detectors.size(); ++k) {
    const double theta = Theta(detectors[k]), phi = Phi(detectors[k]);
    const int theta_low = std::max(0, CellTheta(theta - radius) - 1);
    const int theta_high = std::min(kThetaCells - 1, CellTheta(theta + radius) + 1);
    const double sin_low = std::sin(std::max(theta - radius, 0.0));
    const bool all_phi = theta - radius <= DegToRad(1) || radius / sin_low >= kPi;
    const double phi_radius = all_phi ? kPi : std::asin(std::min(1.0, std::sin(radius) / sin_low));
    const int phi_span = static_cast<int>(std::ceil(RadToDeg(phi_radius))) + 1;
    const int first = all_phi ? 0 : CellPhi(phi) - phi_span;
    const int last = all_phi ? kPhiCells - 1 : CellPhi(phi) + phi_span;
    for (int t = theta_low; t <= theta_high; ++t) {
      for (int p = first; p <= last; ++p) {
        cells[t * kPhiCells + ((p % kPhiCells) + kPhiCells) % kPhiCells].push_back(int(k));
      }
    }
  }
  offsets_.reserve(cells.size() + 1);
  offsets_.push_back(0);
  for (auto& cell : cells) {  // a detector may have been added twice through phi wrap
    std::sort(cell.begin(), cell.end());
    cell.erase(std::unique(cell.begin(), cell.end()), cell.end());
    members_.insert(members_.end(), cell.begin(), cell.end());
    offsets_.push_back(static_cast<uint32_t>(members_.size()));
  }
}

}  // namespace brdf::gonio
