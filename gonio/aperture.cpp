#include "gonio/aperture.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/angles.h"
#include "core/colour.h"
#include "core/sampling.h"

namespace brdf::gonio {
namespace {

// Gauss-Legendre nodes and weights on [-1, 1]: Newton's method on the Legendre polynomial
// P_n from the Chebyshev-like first guess cos(π(i + 3/4)/(n + 1/2)) (Abramowitz & Stegun
// 25.4.29; Press et al., Numerical Recipes, §4.6).
void GaussLegendre(int n, std::vector<double>* nodes, std::vector<double>* weights) {
  nodes->assign(n, 0.0);
  weights->assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    double x = std::cos(kPi * (i + 0.75) / (n + 0.5));
    double derivative = 1;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1, p1 = x;  // P_0, P_1; recurrence k P_k = (2k−1) x P_{k−1} − (k−1) P_{k−2}
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) p0 = 1;
      derivative = n * (x * p1 - p0) / (x * x - 1);
      const double step = p1 / derivative;
      x -= step;
      if (std::abs(step) < 1e-15) break;
    }
    (*nodes)[i] = x;
    (*weights)[i] = 2 / ((1 - x * x) * derivative * derivative);
  }
}

}  // namespace

double LobeWidth(const Model& model) {
  const Vec3 normal(0, 0, 1);
  const auto luminance_at = [&](double theta_o) {
    return Luminance(model.Eval(normal, SphericalDirection(theta_o, 0)));
  };
  const double floor = luminance_at(DegToRad(80));
  const double peak = luminance_at(0) - floor;
  if (!(peak > 1e-6 * std::max(floor, 1e-12))) return std::numeric_limits<double>::infinity();
  // Bisection for lobe(theta) = e^(-1/2) peak on [0, 80°]; the lobes of DESIGN §2 decrease
  // monotonically away from the mirror direction.
  const double target = peak * std::exp(-0.5);
  double low = 0, high = DegToRad(80);
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double middle = 0.5 * (low + high);
    (luminance_at(middle) - floor > target ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

std::vector<AperturePoint> ApertureQuadrature(double aperture_radius, double lobe_width,
                                              double density) {
  if (aperture_radius <= 0) return {AperturePoint{0, 0, 1}};
  const double q =
      std::isfinite(lobe_width) ? (lobe_width > 0 ? aperture_radius / lobe_width : 1e9) : 0.0;
  // Cap the total at kMaxAperturePoints, keeping the ratio of rings to spokes: rings · spokes
  // grows as q², so scale q down by the square root of the excess.
  const auto count = [&](double scale, int* rings, int* spokes) {
    *rings = std::max(1, static_cast<int>(std::ceil(density * scale * q + 0.5)));
    *spokes = std::max(4, static_cast<int>(std::ceil(density * (2 * kPi * scale * q + 3))));
  };
  int rings = 1, spokes = 4;
  const double demand = std::pow(density * q + 1, 2) * 2 * kPi;
  double scale = demand > kMaxAperturePoints ? std::sqrt(kMaxAperturePoints / demand) : 1.0;
  for (count(scale, &rings, &spokes); double(rings) * spokes > kMaxAperturePoints;
       count(scale, &rings, &spokes)) {
    scale *= 0.95;
  }
  std::vector<double> nodes, weights;
  GaussLegendre(rings, &nodes, &weights);
  std::vector<AperturePoint> points;
  points.reserve(size_t(rings) * spokes);
  for (int i = 0; i < rings; ++i) {
    // u = r² in [0, 1] is the fraction of the aperture's area (and solid angle) inside radius
    // r; du dphi / 2π sums to 1. A BRDF that is smooth across the aperture is, after the
    // azimuthal average, smooth in u, so one ring integrates its quadratic part exactly.
    const double u = 0.5 * (nodes[i] + 1);
    for (int j = 0; j < spokes; ++j) {
      // Spokes of alternate rings are offset by half a step, so no two rings line up.
      const double turn = (j + 0.5 * (i % 2)) / spokes;
      points.push_back({u, turn, 0.5 * weights[i] / spokes});
    }
  }
  return points;
}

void AppendReadingNodes(const Instrument& instrument,
                        const std::vector<AperturePoint>& source_quadrature,
                        const std::vector<AperturePoint>& detector_quadrature, const Vec3& wi,
                        const Vec3& wo, std::vector<ReadingNode>* nodes) {
  const double cos_detector = instrument.DetectorCosHalfAngle();
  const Frame detector_frame = Frame::FromZ(wo);
  const size_t first = nodes->size();
  const double weight_sum = ForEachSourceDirection(
      instrument, wi, source_quadrature, [&](const Vec3& wi_source, double weight) {
        for (const AperturePoint& detector : detector_quadrature) {
          const Vec3 wo_detector = detector_frame.FromLocal(
              SampleUniformCone(Point2(detector.u1, detector.u2), cos_detector));
          if (wo_detector.z() <= 0) continue;
          nodes->push_back({wi_source, wo_detector, weight * detector.weight * wo_detector.z()});
        }
      });
  for (size_t n = first; n < nodes->size(); ++n) {
    (*nodes)[n].weight = weight_sum > 0 ? (*nodes)[n].weight / weight_sum : 0.0;
  }
}

}  // namespace brdf::gonio
