#include "gonio/detector_lookup.h"

#include <algorithm>
#include <cmath>

namespace brdf::gonio {

DetectorLookup::DetectorLookup(const std::vector<Vec3>& detectors, double cos_half_angle)
    : cos_half_angle_(cos_half_angle) {
  std::vector<std::vector<int>> cells(kCells * kCells);
  const double radius = std::acos(std::clamp(cos_half_angle, -1.0, 1.0));
  // Over a cone of half-angle r about a, the largest w.e is cos(max(0, angle(a, e) - r)): the
  // cone's projection lies within these bounds on each axis.
  const auto largest = [&](double a_dot_e) {
    return std::cos(std::max(0.0, std::acos(std::clamp(a_dot_e, -1.0, 1.0)) - radius));
  };
  for (size_t k = 0; k < detectors.size(); ++k) {
    const Vec3& a = detectors[k];
    const int x_low = std::max(0, Cell(-largest(-a.x())) - 1);
    const int x_high = std::min(kCells - 1, Cell(largest(a.x())) + 1);
    const int y_low = std::max(0, Cell(-largest(-a.y())) - 1);
    const int y_high = std::min(kCells - 1, Cell(largest(a.y())) + 1);
    for (int y = y_low; y <= y_high; ++y) {
      for (int x = x_low; x <= x_high; ++x) cells[y * kCells + x].push_back(int(k));
    }
  }
  offsets_.reserve(cells.size() + 1);
  offsets_.push_back(0);
  for (const std::vector<int>& cell : cells) {
    for (int k : cell) members_.push_back({detectors[k], k});
    offsets_.push_back(static_cast<uint32_t>(members_.size()));
  }
}

}  // namespace brdf::gonio
