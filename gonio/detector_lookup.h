// Which detector cones contain a direction: the tracer bins every escaping path with it
// (traced_surface.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/angles.h"
#include "core/vec.h"

namespace brdf::gonio {

// atan2(y, x) within about 2e-8 radians, without libm: the octant is folded onto [0, 1] and
// arctan t / t there is the polynomial of Abramowitz & Stegun (1964), 4.4.49.
inline double FastAtan2(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double big = std::max(ax, ay), small = std::min(ax, ay);
  if (big == 0) return 0;
  const double t = small / big, t2 = t * t;
  double angle =
      t * (1 + t2 * (-0.3333314528 +
                     t2 * (0.1999355085 +
                           t2 * (-0.1420889944 +
                                 t2 * (0.1065626393 +
                                       t2 * (-0.0752896400 +
                                             t2 * (0.0429096138 +
                                                   t2 * (-0.0161657367 + t2 * 0.0028662257))))))));
  if (ay > ax) angle = 0.5 * kPi - angle;
  if (x < 0) angle = kPi - angle;
  return y < 0 ? -angle : angle;
}

// Detector cones indexed by 1° cells of (theta, phi) so that an escaping ray is compared with
// the few detectors that can contain it, not with all of them. The cells' lists are stored one
// after another (offsets into one array), so a look-up touches two cache lines, not a
// separately allocated list per cell.
class DetectorLookup {
 public:
  // Cells for detector directions (unit vectors, kept by reference) and the cosine of the
  // cones' common half-angle.
  DetectorLookup(const std::vector<Vec3>& detectors, double cos_half_angle);

  // The cell of w comes from angles accurate to about 1e-6 degrees (FastAtan2). One that far
  // off can land only in a neighbouring cell, and every detector is listed one cell beyond its
  // cone in theta and in phi (the constructor's margins), so the same detectors are found as
  // with exact angles; the dot product decides.
  template <typename Visit>
  void ForEachContaining(const Vec3& w, Visit&& visit) const {
    const double theta = FastAtan2(std::sqrt(w.x() * w.x() + w.y() * w.y()), w.z());
    const int cell = CellTheta(theta) * kPhiCells + CellPhi(FastAtan2(w.y(), w.x()));
    for (uint32_t m = offsets_[cell]; m < offsets_[cell + 1]; ++m) {
      const int k = members_[m];
      if (w.dot(detectors_[k]) >= cos_half_angle_) visit(k);
    }
  }

 private:
  static constexpr int kThetaCells = 90, kPhiCells = 360;
  static int CellTheta(double theta) {
    return std::clamp(static_cast<int>(std::floor(RadToDeg(theta))), 0, kThetaCells - 1);
  }
  static int CellPhi(double phi) {
    const int cell = static_cast<int>(std::floor(RadToDeg(phi)));
    return ((cell % kPhiCells) + kPhiCells) % kPhiCells;
  }

  const std::vector<Vec3>& detectors_;
  double cos_half_angle_;
  std::vector<uint32_t> offsets_;  // cell c holds members_[offsets_[c] .. offsets_[c + 1])
  std::vector<int> members_;
};

}  // namespace brdf::gonio
