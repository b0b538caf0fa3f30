#include "energy/lobe_quadrature.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <queue>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/errors.h"
#include "core/sampling.h"

namespace brdf {
namespace {

constexpr double kHalfPi = 0.5 * kPi;
constexpr double kNegligibleWarp = 1e-280;

// The 15-point Gauss-Kronrod rule and its embedded 7-point Gauss rule on [-1, 1] (QUADPACK's
// qk15, Piessens et al. 1983): positive abscissae, largest first, the last one the centre.
constexpr double kKronrodNodes[8] = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.000000000000000000000000000000000};
constexpr double kKronrodWeights[8] = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
// Weights of the Gauss rule at kKronrodNodes[1], [3], [5] and [7].
constexpr double kGaussWeights[4] = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

// Integrated quantities: the RGB albedo, the cosine-weighted measure without data support, and
// the inner (azimuthal) rule's own error estimate.
enum Channel { kRed, kGreen, kBlue, kUnsupported, kInnerError, kNumChannels };
using Quantities = Eigen::Array<double, kNumChannels, 1>;

struct RuleResult {
  Quantities kronrod = Quantities::Zero();
  Quantities gauss = Quantities::Zero();
  int64_t evaluations = 0;
};

template <typename Integrand>
RuleResult ApplyGaussKronrod15(const Integrand& integrand, double a, double b) {
  const double centre = 0.5 * (a + b), half_length = 0.5 * (b - a);
  RuleResult result;
  const Quantities at_centre = integrand(centre);
  result.kronrod = kKronrodWeights[7] * at_centre;
  result.gauss = kGaussWeights[3] * at_centre;
  for (int k = 0; k < 7; ++k) {
    const double offset = half_length * kKronrodNodes[k];
    const Quantities pair = integrand(centre - offset) + integrand(centre + offset);
    result.kronrod += kKronrodWeights[k] * pair;
    if (k % 2 == 1) result.gauss += kGaussWeights[k / 2] * pair;
  }
  result.kronrod *= half_length;
  result.gauss *= half_length;
  result.evaluations = 15;
  return result;
}

// |Kronrod - Gauss| per colour channel: the usual (pessimistic) error estimate of the pair.
Rgb ColourError(const RuleResult& rule) { return (rule.kronrod - rule.gauss).head<3>().abs(); }

// Half-width w of the arc {phi : a + b cos(phi) > 0} = (-w, w), for b >= 0: the part of a ring
// that lies above the horizon when the ring's cos(theta_i) is a + b cos(phi).
double AboveHorizonHalfWidth(double a, double b) {
  if (b <= 1e-300) return a > 0.0 ? kPi : 0.0;
  const double c = -a / b;
  if (c <= -1.0) return kPi;
  if (c >= 1.0) return 0.0;
  return std::acos(c);
}

// Rings of constant polar angle beta about the lobe's centre, azimuth phi measured so that
// phi = 0 points up, toward the normal; on every ring cos(theta_i) = a + b cos(phi), b >= 0.
class LobeRings {
 public:
  LobeRings(const Vec3& wo, const LobeFrame& frame) : wo_(wo), half_vector_(frame.half_vector) {
    const double theta_o = Theta(wo), phi_o = Phi(wo);
    cos_theta_o_ = std::cos(theta_o);
    sin_theta_o_ = std::sin(theta_o);
    phi_o_ = phi_o;
    // Axis at polar angle theta_a, azimuth phi_a; tangent_up_ is the unit vector in the plane
    // of the axis and the normal, perpendicular to the axis, with a non-negative z.
    // The axis in wi that the frame names (the normal, the mirror direction of wo, wo itself);
    // a half-vector lobe's rings lie about the normal in h.
    const Vec3 axis = frame.half_vector ? Vec3::UnitZ() : frame.Axis(wo).normalized();
    const double theta_a = Theta(axis), phi_a = Phi(axis);
    axis_ = SphericalDirection(theta_a, phi_a);
    tangent_up_ = Vec3(-std::cos(theta_a) * std::cos(phi_a), -std::cos(theta_a) * std::sin(phi_a),
                       std::sin(theta_a));
    tangent_side_ = axis_.cross(tangent_up_);
    axis_sin_theta_ = std::sin(theta_a);
    axis_cos_theta_ = std::cos(theta_a);
    if (half_vector_) {
      // h with theta_h <= pi/4 + theta_o/2 reflects wo above the horizon for some phi; rings
      // start to cross the horizon at pi/4 - theta_o/2 (cos(theta_i) = cos(theta_o) cos(2
      // theta_h) + sin(theta_o) sin(2 theta_h) cos(phi), see RingCosine).
      max_polar_ = std::min(kHalfPi, 0.25 * kPi + 0.5 * theta_o);
      crossing_polar_ = 0.25 * kPi - 0.5 * theta_o;
    } else {
      max_polar_ = kHalfPi;
      crossing_polar_ = kHalfPi - theta_a;
    }
  }

  double max_polar() const { return max_polar_; }
  // Polar angle where rings begin to cross the horizon: the integrand's kink in beta.
  double crossing_polar() const { return crossing_polar_; }

  // cos(theta_i) = a + b cos(phi) on the ring at polar angle beta.
  void RingCosine(double cos_beta, double sin_beta, double* a, double* b) const {
    if (half_vector_) {
      // wi = 2 (wo.h) h - wo with h = (sin b cos(phi_o+phi), sin b sin(phi_o+phi), cos b).
      *a = cos_theta_o_ * (2.0 * cos_beta * cos_beta - 1.0);
      *b = sin_theta_o_ * 2.0 * sin_beta * cos_beta;
    } else {
      *a = cos_beta * axis_cos_theta_;
      *b = sin_beta * axis_sin_theta_;
    }
  }

  // wi on the ring, and the Jacobian of wi's solid angle with respect to the ring's own
  // solid angle (1 about an axis in wi; 4 (wo.h) in half-vector space, Walter et al. 2007).
  Vec3 Incident(double cos_beta, double sin_beta, double phi, double* jacobian) const {
    if (half_vector_) {
      const Vec3 h(sin_beta * std::cos(phi_o_ + phi), sin_beta * std::sin(phi_o_ + phi), cos_beta);
      const double wo_dot_h = wo_.dot(h);
      *jacobian = 4.0 * wo_dot_h;
      return Reflect(wo_, h);
    }
    *jacobian = 1.0;
    return cos_beta * axis_ +
           sin_beta * (std::cos(phi) * tangent_up_ + std::sin(phi) * tangent_side_);
  }

 private:
  Vec3 wo_;
  bool half_vector_;
  double cos_theta_o_ = 1, sin_theta_o_ = 0, phi_o_ = 0;
  Vec3 axis_, tangent_up_, tangent_side_;
  double axis_sin_theta_ = 0, axis_cos_theta_ = 1;
  double max_polar_ = kHalfPi, crossing_polar_ = kHalfPi;
};

class LobeIntegrand {
 public:
  LobeIntegrand(const BrdfFunction& brdf, const Vec3& wo, const LobeCoordinates& coordinates)
      : brdf_(brdf), wo_(wo), rings_(wo, coordinates.frame), lobe_(coordinates) {}

  const LobeRings& rings() const { return rings_; }
  // The warp variable u = the lobe's mass beyond beta (cos^(e+1)(beta) for a power cosine), so
  // d(u) is uniform over the lobe (models/lobe.h).
  double WarpOf(double polar) const { return LobeMassBeyond(lobe_, std::cos(polar)); }

  // The ring integral at warp value u, times the warp's Jacobian: du = -2π p(beta) sin(beta)
  // d(beta) for the lobe's density p, so sin(beta) d(beta) = du / (2π p); for the power cosine
  // that is du / ((e+1) cos^e(beta)) = cos(beta) du / ((e+1) u), written so to stay finite for
  // huge exponents.
  Quantities operator()(double u) const {
    const double cos_beta = LobeCosAt(lobe_, u);
    const double sin_beta = std::sqrt(std::max(0.0, 1.0 - cos_beta * cos_beta));
    double a = 0, b = 0;
    rings_.RingCosine(cos_beta, sin_beta, &a, &b);
    const double half_width = AboveHorizonHalfWidth(a, b);
    // Below kNegligibleWarp the matching lobe holds less than that share of its weight, and
    // cos(beta) / u would overflow: such rings contribute nothing.
    if (half_width <= 0.0 || u <= kNegligibleWarp) return Quantities::Zero();
    auto on_ring = [&](double phi) -> Quantities {
      double jacobian = 0;
      const Vec3 wi = rings_.Incident(cos_beta, sin_beta, phi, &jacobian);
      const double cos_theta_i = CosTheta(wi);
      Quantities value = Quantities::Zero();
      if (cos_theta_i <= 0.0 || jacobian <= 0.0) return value;
      const double measure = cos_theta_i * jacobian;
      const BrdfSample sample = brdf_(wi, wo_);
      if (sample.value.allFinite()) value.head<3>() = sample.value * measure;
      if (!sample.supported || !sample.value.allFinite()) value[kUnsupported] = measure;
      return value;
    };
    // On every ring of a matching term the lobe is constant and cos(theta_i) (times the
    // half-vector Jacobian) is a low-degree trigonometric polynomial in phi, which one 15-point
    // Kronrod rule (degree 23) integrates to about 1e-12 even over a whole ring; the embedded
    // Gauss rule (degree 13) is much rougher, so |K - G| overstates this error.
    // A lobe that is not constant on its rings (models/lobe.h: ring_panels) gets the rule on
    // equal panels of the arc.
    Quantities ring = Quantities::Zero();
    double inner_error = 0;
    const int panels = std::max(1, lobe_.ring_panels);
    for (int k = 0; k < panels; ++k) {
      const double start = -half_width + 2.0 * half_width * k / panels;
      const double end = -half_width + 2.0 * half_width * (k + 1) / panels;
      const RuleResult arc = ApplyGaussKronrod15(on_ring, start, end);
      evaluations_ += arc.evaluations;
      ring += arc.kronrod;
      inner_error += ColourError(arc).maxCoeff();
    }
    ring[kInnerError] = inner_error;
    if (lobe_.distribution == nullptr) return ring * (cos_beta / ((lobe_.exponent + 1.0) * u));
    const double density = LobeDensity(lobe_, cos_beta);
    if (!(density > 0.0)) return Quantities::Zero();
    return ring * (1.0 / (2.0 * kPi * density));
  }

  int64_t evaluations() const { return evaluations_; }

 private:
  const BrdfFunction& brdf_;
  Vec3 wo_;
  LobeRings rings_;
  LobeCoordinates lobe_;
  mutable int64_t evaluations_ = 0;
};

struct Interval {
  double a = 0, b = 0;
  RuleResult rule;
  double error = 0;  // largest colour channel of |Kronrod - Gauss|
  bool operator<(const Interval& other) const { return error < other.error; }
};

}  // namespace

void LobeQuadratureOptions::Validate() const {
  if (!(tolerance > 0.0)) throw UsageError("quadrature tolerance must be > 0");
  if (max_intervals < 1) throw UsageError("quadrature needs at least one interval");
}

AlbedoEstimate IntegrateInLobeCoordinates(const BrdfFunction& brdf, const Vec3& wo,
                                          const LobeCoordinates& coordinates,
                                          const LobeQuadratureOptions& options) {
  const LobeIntegrand integrand(brdf, wo, coordinates);
  const LobeRings& rings = integrand.rings();
  // Pieces in u, split where rings start to cross the horizon (u decreases as beta grows).
  const double u_end = integrand.WarpOf(rings.max_polar());
  std::vector<double> breaks = {u_end, 1.0};
  if (rings.crossing_polar() > 0.0 && rings.crossing_polar() < rings.max_polar()) {
    const double u_crossing = integrand.WarpOf(rings.crossing_polar());
    if (u_crossing > std::max(u_end, kNegligibleWarp) && u_crossing < 1.0)
      breaks.insert(breaks.begin() + 1, u_crossing);
  }
  std::priority_queue<Interval> worst_first;
  // Only the polar rule's error drives the refinement: the rings' own error estimates add up
  // to ∫ (ring error) du, which bisecting in u cannot reduce. They are reported, not chased;
  // the Gauss half of the ring rule is far less exact than its Kronrod value on whole rings
  // (degree 13 against 23), so that part of the estimate is very pessimistic.
  double total_error = 0;
  auto add = [&](double a, double b) {
    Interval interval{a, b, ApplyGaussKronrod15(integrand, a, b), 0.0};
    interval.error = ColourError(interval.rule).maxCoeff();
    total_error += interval.error;
    worst_first.push(interval);
  };
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    if (!(breaks[k + 1] > breaks[k])) continue;
    const double middle = 0.5 * (breaks[k] + breaks[k + 1]);
    add(breaks[k], middle);
    add(middle, breaks[k + 1]);
  }
  int intervals = static_cast<int>(worst_first.size());
  while (intervals < options.max_intervals && !worst_first.empty() &&
         total_error > options.tolerance) {
    const Interval worst = worst_first.top();
    const double middle = 0.5 * (worst.a + worst.b);
    if (!(middle > worst.a && middle < worst.b)) break;  // cannot split further
    worst_first.pop();
    total_error -= worst.error;
    add(worst.a, middle);
    add(middle, worst.b);
    ++intervals;
  }
  AlbedoEstimate estimate;
  double unsupported = 0;
  for (; !worst_first.empty(); worst_first.pop()) {
    const Interval& interval = worst_first.top();
    estimate.albedo += interval.rule.kronrod.head<3>();
    estimate.error += ColourError(interval.rule) + interval.rule.kronrod[kInnerError];
    unsupported += interval.rule.kronrod[kUnsupported];
  }
  estimate.coverage = std::clamp(1.0 - unsupported * kInvPi, 0.0, 1.0);
  estimate.evaluations = integrand.evaluations();
  return estimate;
}

AlbedoEstimate IntegrateOnUniformGrid(const BrdfFunction& brdf, const Vec3& wo, int theta_cells,
                                      int phi_cells) {
  if (theta_cells < 1 || phi_cells < 1) throw UsageError("a grid needs at least one cell");
  const double d_theta = kHalfPi / theta_cells, d_phi = 2.0 * kPi / phi_cells;
  AlbedoEstimate estimate;
  double unsupported = 0;
  for (int i = 0; i < theta_cells; ++i) {
    const double theta = (i + 0.5) * d_theta;
    // dω = sin(theta) dtheta dphi (DESIGN §1), times cos(theta_i).
    const double measure = std::cos(theta) * std::sin(theta) * d_theta * d_phi;
    for (int j = 0; j < phi_cells; ++j) {
      const BrdfSample sample = brdf(SphericalDirection(theta, (j + 0.5) * d_phi), wo);
      if (sample.value.allFinite()) estimate.albedo += sample.value * measure;
      if (!sample.supported || !sample.value.allFinite()) unsupported += measure;
    }
  }
  estimate.coverage = std::clamp(1.0 - unsupported * kInvPi, 0.0, 1.0);
  estimate.evaluations = int64_t{theta_cells} * phi_cells;
  return estimate;
}

}  // namespace brdf
