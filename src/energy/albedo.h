// Directional albedo curves and the energy-conservation check (DESIGN §7): a(theta) per RGB
// channel over a range of incidence angles, for a model or for measured data, by one of three
// methods, each with an error estimate; the maximum, where it occurs, and the verdict.
//
// By reciprocity the albedo for light arriving at theta equals the albedo for viewing at theta
// (DESIGN §1); the curve fixes wo at polar angle theta, azimuth 0, and integrates over wi.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/progress.h"
#include "energy/integrand.h"
#include "energy/lobe_quadrature.h"
#include "energy/measured.h"
#include "energy/verdict.h"
#include "models/registry.h"

namespace brdf {

enum class AlbedoMethod {
  kQuadrature,  // adaptive Gauss-Kronrod in lobe-centred coordinates (lobe_quadrature.h)
  kMonteCarlo,  // cosine-weighted sampling
  kImportance,  // a mixture of cosine sampling and the model's lobes (models only)
};
const char* AlbedoMethodName(AlbedoMethod method);      // "quadrature", "mc", "importance"
AlbedoMethod ParseAlbedoMethod(std::string_view name);  // throws UsageError

struct AlbedoOptions {
  AlbedoMethod method = AlbedoMethod::kQuadrature;
  int theta_steps = 90;         // incidence angles, evenly spaced over [0, theta_max_deg]
  double theta_max_deg = 89.0;  // the albedo is defined up to 90; 89 keeps clear of grazing
  int64_t samples = 65536;      // per angle, for the Monte Carlo methods
  uint64_t seed = 1;            // Monte Carlo: angle k always uses stream (seed, k)
  LobeQuadratureOptions quadrature;
  // Interpolated data are not smooth (nearest cells, inverse-distance blends): refining the
  // quadrature past the data's own resolution buys nothing, so measured data stop here.
  int measured_max_intervals = 8;

  void Validate() const;  // throws UsageError naming the bad option
  std::vector<double> ThetaDegrees() const;
};

// An albedo within this of 1 is at the bound: ten times the quadrature's default tolerance
// (lobe_quadrature.h), so that a material exactly at the bound (lambert:rho_d=1, phong with
// rho_d + rho_s = 1) reads as conserving whatever the rounding, while an excess of 0.001 is
// still found.
inline constexpr double kAlbedoResolution = 1e-4;

struct AlbedoPoint {
  double theta_deg = 0;
  AlbedoEstimate estimate;
};

struct AlbedoCurve {
  std::string source;  // the model string or the measurement's path
  AlbedoMethod method = AlbedoMethod::kQuadrature;
  std::vector<AlbedoPoint> points;
  std::vector<std::string> notes;     // what the integrand assumes (interpolation scheme)
  std::vector<std::string> warnings;  // coverage holes

  // Filled from `points` by FinishAlbedoCurve().
  Rgb max_albedo = Rgb::Zero();
  Rgb error_at_max = Rgb::Zero();
  std::array<double, 3> theta_deg_at_max = {0, 0, 0};
  double min_coverage = 1.0;
  double coverage_at_max = 1.0;  // at the angle of the largest channel's maximum
  int64_t evaluations = 0;

  // The largest incidence the data were measured at (90 for a model): beyond it the curve is
  // the interpolation's extrapolation, which cannot decide the verdict.
  double largest_measured_incidence_deg = 90.0;

  // The verdict (verdict.h), judged on twice each albedo's error estimate:
  //  - not conserving when an albedo at a measured incidence exceeds 1 by more than that;
  //  - undecided when the largest albedo lies beyond the measured incidences, or when an albedo's
  //    error estimate straddles 1;
  //  - conserving otherwise.
  // Where the data cover less than 99 % of the hemisphere at the albedo the verdict rests on,
  // the reason says so.
  // Albedos within kAlbedoResolution of 1 are at the bound, neither excess nor margin.
  EnergyVerdict verdict() const;
  // Largest max_albedo - 1 over the channels: > 0 is the excess, < 0 the margin.
  double excess() const;
  // One line: source, method, max albedo per channel and where, the verdict.
  std::string Summary() const;
  // The whole curve as a table, then notes, warnings, maximum and verdict.
  std::string Report() const;
};

// Computes the maxima, coverage warnings and evaluation count of a curve from its points.
void FinishAlbedoCurve(AlbedoCurve* curve);

// One incidence angle. `stream` selects the Monte Carlo random stream (the angle's index).
AlbedoEstimate ModelDirectionalAlbedo(const Model& model, double theta_o,
                                      const AlbedoOptions& options, uint64_t stream = 0);
AlbedoEstimate MeasuredDirectionalAlbedo(const MeasuredBrdf& measured, double theta_o,
                                         const AlbedoOptions& options, uint64_t stream = 0);

// The whole curve, angles in parallel (TBB); identical for any thread count. `progress` may be
// null; it advances once per angle.
AlbedoCurve ModelAlbedoCurve(const Model& model, const AlbedoOptions& options,
                             Progress* progress = nullptr);
AlbedoCurve MeasuredAlbedoCurve(const MeasuredBrdf& measured, const AlbedoOptions& options,
                                Progress* progress = nullptr);

}  // namespace brdf
