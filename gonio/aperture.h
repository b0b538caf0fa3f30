// How finely the instrument integrates over its apertures: "as many points as the lobe's width
// requires" (DESIGN §5). A BRDF lobe of angular width sigma seen through an aperture of angular
// radius a is averaged by a deterministic equal-area point set (sampling.h, VogelPoint) whose
// spacing sqrt(π a² / N) is at most sigma/2, i.e. N = ceil(4π (a/sigma)²), clamped to
// [kMinAperturePoints, kMaxAperturePoints]. A smooth BRDF (no lobe) gets the minimum, which
// already averages the cos(theta_o) variation across the aperture to second order.
#pragma once

#include <limits>

#include "models/registry.h"

namespace brdf::gonio {

inline constexpr int kMinAperturePoints = 7;
inline constexpr int kMaxAperturePoints = 1024;

// Angular half-width (radians) at which the model's glossy lobe has fallen to e^(-1/2) of its
// peak above the diffuse floor, probed numerically at normal incidence along theta_o; infinity
// when the model has no lobe (e.g. lambert) — so the rule works for any registered model.
double LobeWidth(const Model& model);

// Points for an aperture of angular radius `aperture_radius` (radians) and a lobe of angular
// width `lobe_width` (radians, may be infinite); 1 for a point aperture (radius 0).
int AperturePoints(double aperture_radius, double lobe_width);

}  // namespace brdf::gonio
