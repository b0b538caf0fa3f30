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

  // a <= 1 in every channel at every angle (DESIGN §1), up to twice the error estimate: only a
  // significant excess makes a material non-conserving.
  bool conserving() const;
  // Largest max_albedo - 1 over the channels: > 0 is the excess, < 0 the margin.
  double excess() const;
  // "conserving ..." or "NOT conserving ...", with the amount and the error estimate.
  std::string Verdict() const;
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
