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
  const auto at = [&](double a, double b) {
    return reading((w + sigma * (a * frame.x + b * frame.y)).normalized());
  };
  const Rgb centre = at(0, 0);
  const Rgb px = at(1, 0), mx = at(-1, 0), py = at(0, 1), my = at(0, -1);
  // First order: (slope · sigma)² per axis, slope = difference / 2 sigma.
  Rgb variance = (0.5 * (px - mx)).square() + (0.5 * (py - my)).square();
  // Second order: for e ~ N(0, sigma² I), var(e^T H e / 2) = sigma^4 tr(H²) / 2, with the
  // Hessian H (times sigma²) by differences one sigma wide. Where the slope vanishes (a lobe's
  // peak) this is all of the jitter's scatter.
  const Rgb hxx = px - 2 * centre + mx, hyy = py - 2 * centre + my;
  const Rgb hxy = 0.25 * (at(1, 1) - at(1, -1) - at(-1, 1) + at(-1, -1));
  variance += 0.5 * (hxx.square() + hyy.square() + 2 * hxy.square());
  return variance.sqrt();
}

}  // namespace brdf::gonio
