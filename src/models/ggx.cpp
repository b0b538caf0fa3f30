#include "models/ggx.h"

#include <algorithm>

namespace brdf::models {

void GgxLobe::SampleVisibleNormals(const Vec3T<float>& wo, const float* u0, const float* u1,
                                   int count, float* x, float* y, float* z, float alpha) {
  const VisibleNormalFrame<float> frame = VisibleNormalFrameOf(wo, alpha);
  // Into arrays of its own first: x, y, z might alias u0 and u1 as far as the compiler knows.
  constexpr int kChunk = 16;
  alignas(16) float drawn_x[kChunk], drawn_y[kChunk], drawn_z[kChunk];
  for (int first = 0; first < count; first += kChunk) {
    const int n = std::min(kChunk, count - first);
    for (int k = 0; k < n; ++k) {
      const Vec3T<float> h = SampleVisibleNormal(frame, u0[first + k], u1[first + k]);
      drawn_x[k] = h.x(), drawn_y[k] = h.y(), drawn_z[k] = h.z();
    }
    std::copy(drawn_x, drawn_x + n, x + first);
    std::copy(drawn_y, drawn_y + n, y + first);
    std::copy(drawn_z, drawn_z + n, z + first);
  }
}

}  // namespace brdf::models
