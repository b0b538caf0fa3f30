#include "gonio/aperture.h"

#include <algorithm>
#include <cmath>

#include "core/angles.h"

namespace brdf::gonio {
namespace {

double Luminance(const Rgb& rgb) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

}  // namespace

double LobeWidth(const Model& model) {
  const Vec3 normal(0, 0, 1);
  const auto lobe_above_floor = [&](double theta_o) {
    return Luminance(model.Eval(normal, SphericalDirection(theta_o, 0)));
  };
  const double floor = lobe_above_floor(DegToRad(80));
  const double peak = lobe_above_floor(0) - floor;
  if (!(peak > 1e-6 * std::max(floor, 1e-12))) return std::numeric_limits<double>::infinity();
  // Bisection for lobe(theta) = e^(-1/2) peak on [0, 80°]; the lobes of DESIGN §2 decrease
  // monotonically away from the mirror direction.
  const double target = peak * std::exp(-0.5);
  double low = 0, high = DegToRad(80);
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double middle = 0.5 * (low + high);
    (lobe_above_floor(middle) - floor > target ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

int AperturePoints(double aperture_radius, double lobe_width) {
  if (aperture_radius <= 0) return 1;
  if (!std::isfinite(lobe_width)) return kMinAperturePoints;
  const double ratio = aperture_radius / lobe_width;
  const double points = std::ceil(4 * kPi * ratio * ratio);
  return static_cast<int>(
      std::clamp(points, double{kMinAperturePoints}, double{kMaxAperturePoints}));
}

}  // namespace brdf::gonio
