// Direction sampling particular to the instrument; the shared warps and frames are in
// core/sampling.h.
#pragma once

#include <cmath>

#include "core/sampling.h"

namespace brdf::gonio {

// Rotates unit vector `w` by a small random angle: a 2D Gaussian offset of standard deviation
// `sigma` (radians) in the plane perpendicular to w, given two standard normal numbers.
inline Vec3 PerturbDirection(const Vec3& w, double sigma, double g1, double g2) {
  if (sigma <= 0) return w;
  const Frame frame = Frame::FromZ(w);
  return (w + sigma * (g1 * frame.x + g2 * frame.y)).normalized();
}

// One standard deviation of a reading caused by positioning jitter of `sigma` (radians, per
// axis, as PerturbDirection draws it) of the direction `w`, to first order: the slope of
// `reading` along the two axes perpendicular to w, by central differences one sigma wide
// (wide enough to average a lobe narrower than the jitter, as the jitter itself does), times
// sigma. `reading` maps a direction to an Rgb.
template <typename Reading>
Rgb JitterSigma(const Vec3& w, double sigma, const Reading& reading) {
  if (sigma <= 0) return Rgb::Zero();
  const Frame frame = Frame::FromZ(w);
  Rgb variance = Rgb::Zero();
  for (const Vec3& axis : {frame.x, frame.y}) {
    // The same offsets PerturbDirection makes for (g1, g2) = (±1, 0) and (0, ±1).
    const Rgb difference =
        reading((w + sigma * axis).normalized()) - reading((w - sigma * axis).normalized());
    variance += (0.5 * difference).square();  // (slope · sigma)², slope = difference / 2 sigma
  }
  return variance.sqrt();
}

}  // namespace brdf::gonio
