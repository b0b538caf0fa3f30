// Which detector cones contain a direction: the tracer bins every escaping path with it
// (traced_surface.cpp).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/vec.h"

namespace brdf::gonio {

// Detector cones indexed by a grid over the directions' projection onto the sample plane, (x, y)
// in the unit disk, so that an escaping ray is compared with the few detectors that can contain
// it, not with all of them; finding a direction's cell takes two multiplications, no angle. The
// cells' lists are stored one after another (offsets into one array), each entry with its
// detector's direction, so a look-up reads the offsets and then the entries in a row.
class DetectorLookup {
 public:
  // Cells for detector directions (unit vectors, copied) and the cosine of the cones' common
  // half-angle.
  DetectorLookup(const std::vector<Vec3>& detectors, double cos_half_angle);

  // Every detector is listed in each cell its cone's projection can reach, one cell beyond
  // (the constructor's margin, for the rounding of a cell's bounds), so the cell of w lists every
  // cone that contains w; the dot product decides, and visits each once.
  template <typename Visit>
  void ForEachContaining(const Vec3& w, Visit&& visit) const {
    const int cell = Cell(w.y()) * kCells + Cell(w.x());
    for (uint32_t m = offsets_[cell]; m < offsets_[cell + 1]; ++m) {
      const Member& member = members_[m];
      if (w.dot(member.direction) >= cos_half_angle_) visit(member.detector);
    }
  }

 private:
  // Cells per axis over [-1, 1], 1/128 wide: a 1e-3 sr detector cone (radius 1°) spans about five.
  static constexpr int kCells = 256;
  static int Cell(double coordinate) {
    return std::clamp(static_cast<int>((coordinate + 1.0) * (0.5 * kCells)), 0, kCells - 1);
  }

  struct Member {
    Vec3 direction;  // the detector's, a copy
    int detector;    // its index
  };
  double cos_half_angle_;
  std::vector<uint32_t> offsets_;  // cell c holds members_[offsets_[c] .. offsets_[c + 1])
  std::vector<Member> members_;
};

}  // namespace brdf::gonio
