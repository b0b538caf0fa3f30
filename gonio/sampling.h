// Direction sampling particular to the instrument; the shared warps and frames are in
// core/sampling.h.
#pragma once

#include "core/sampling.h"

namespace brdf::gonio {

// Rotates unit vector `w` by a small random angle: a 2D Gaussian offset of standard deviation
// `sigma` (radians) in the plane perpendicular to w, given two standard normal numbers.
inline Vec3 PerturbDirection(const Vec3& w, double sigma, double g1, double g2) {
  if (sigma <= 0) return w;
  const Frame frame = Frame::FromZ(w);
  return (w + sigma * (g1 * frame.x + g2 * frame.y)).normalized();
}

}  // namespace brdf::gonio
