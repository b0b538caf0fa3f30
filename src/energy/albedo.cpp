#include "energy/albedo.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>

#include "core/angles.h"
#include "core/enum_names.h"
#include "core/errors.h"
#include "core/text.h"
#include "energy/model_terms.h"
#include "energy/monte_carlo.h"

namespace brdf {
namespace {

// Below this coverage an angle gets a warning: 1% of the cosine-weighted hemisphere.
constexpr double kCoverageWarning = 0.99;
// The cosine-sampling share kept in an importance mixture whatever the lobe's weight, so that
// the mixture's pdf never falls far below the cosine pdf where the BRDF is still non-zero
// (Hesterberg 1995, defensive mixtures).
constexpr double kDefensiveCosineShare = 0.1;

const char* const kChannelNames[3] = {"r", "g", "b"};

// Cosine-weighted Monte Carlo finds a sharp lobe only by chance. The lobe's power-cosine
// density (e+1)/(2 pi) cos^e holds 1 - 1/e of its mass in a cone of solid angle 2 pi/(e+1)
// about its centre (cos^(e+1) falls to 1/e there); a cosine sample lands in it with probability
// cos(theta) 2/(e+1) (pdf cos/pi), times 4 cos(theta) for a half-vector lobe, whose cone in wi
// is that much wider (dwi = 4 (wo.h) dwh, h at the normal). With lambda expected hits the lobe
// is missed entirely with probability exp(-lambda), and then the value and its error estimate
// both leave the lobe out: the error bar does not show the failure. Over a 90-angle curve,
// lambda >= 10 keeps the chance of any such silent miss below 90 exp(-10) = 0.4 %.
constexpr double kMinExpectedLobeHits = 10.0;

// The warning for a curve computed by cosine-weighted Monte Carlo, or "" when every lobe is
// expected to receive enough samples at every angle.
std::string SparseLobeWarning(const Model& model, const AlbedoOptions& options) {
  double worst_hits = std::numeric_limits<double>::infinity();
  double worst_theta = 0, worst_exponent = 0;
  for (const AlbedoTerm& term : AlbedoTerms(model)) {
    if (term.coordinates.frame.AboutNormal() || !(term.scale > 0)) continue;
    // The lobe's half width as a power-cosine exponent (the exponent itself for the power-cosine
    // models; the same half width for a microfacet lobe).
    const double e = term.model.info().EquivalentExponent(term.model.params().data());
    for (double theta_deg : options.ThetaDegrees()) {
      const double cos_theta = std::cos(DegToRad(theta_deg));
      double probability = 2.0 * cos_theta / (e + 1.0);
      if (term.coordinates.frame.half_vector) probability *= 4.0 * cos_theta;
      const double hits = static_cast<double>(options.samples) * std::min(probability, 1.0);
      if (hits < worst_hits) {
        worst_hits = hits;
        worst_theta = theta_deg;
        worst_exponent = e;
      }
    }
  }
  if (!(worst_hits < kMinExpectedLobeHits)) return "";
  std::ostringstream text;
  text << "Monte Carlo: the lobe (power-cosine exponent " << std::setprecision(4) << worst_exponent
       << ") expects only " << std::setprecision(3) << worst_hits << " of " << options.samples
       << " cosine samples at theta = " << std::fixed << std::setprecision(1) << worst_theta
       << " deg; a lobe no sample hits is left out of both the albedo and its error estimate, "
          "so the error bar can hide the miss (quadrature or importance sampling does not miss it)";
  return text.str();
}

std::vector<SamplingStrategy> ImportanceStrategies(const std::vector<AlbedoTerm>& terms) {
  double total_scale = 0;
  for (const AlbedoTerm& term : terms) total_scale += term.scale;
  std::vector<SamplingStrategy> strategies = {{{kNormalFrame, 1.0}, 0.0}};
  for (const AlbedoTerm& term : terms) {
    if (term.coordinates.frame.AboutNormal()) {
      strategies[0].weight += term.scale;
    } else {
      strategies.push_back({term.coordinates, term.scale});
    }
  }
  strategies[0].weight =
      std::max(strategies[0].weight, kDefensiveCosineShare * std::max(total_scale, 1e-300));
  return strategies;
}

Vec3 OutgoingAt(double theta_o) { return SphericalDirection(theta_o, 0.0); }

// Runs `estimate_at(theta_radians, angle_index)` for every angle of the options, in parallel.
AlbedoCurve ComputeCurve(const std::string& source, const AlbedoOptions& options,
                         Progress* progress,
                         const std::function<AlbedoEstimate(double, uint64_t)>& estimate_at) {
  options.Validate();
  AlbedoCurve curve;
  curve.source = source;
  curve.method = options.method;
  const std::vector<double> thetas = options.ThetaDegrees();
  curve.points.resize(thetas.size());
  tbb::parallel_for(size_t{0}, thetas.size(), [&](size_t k) {
    curve.points[k] = {thetas[k], estimate_at(DegToRad(thetas[k]), k)};
    if (progress != nullptr) progress->Advance();
  });
  return curve;
}

std::string Fixed(double value, int digits) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(digits) << value;
  return text.str();
}

// Four significant digits: amounts from 1e-7 to 1e3 read alike.
std::string Significant(double value) {
  std::ostringstream text;
  text << std::setprecision(4) << value;
  return text.str();
}

constexpr EnumName<AlbedoMethod> kAlbedoMethodNames[] = {
    {AlbedoMethod::kQuadrature, "quadrature"},
    {AlbedoMethod::kMonteCarlo, "mc"},
    {AlbedoMethod::kImportance, "importance"},
};

std::string Rgb3(const Rgb& value, int digits) {
  return Fixed(value[0], digits) + " " + Fixed(value[1], digits) + " " + Fixed(value[2], digits);
}

}  // namespace

const char* AlbedoMethodName(AlbedoMethod method) { return NameOf(kAlbedoMethodNames, method); }

AlbedoMethod ParseAlbedoMethod(std::string_view name) {
  return ParseEnum(kAlbedoMethodNames, name, "albedo method");
}

void AlbedoOptions::Validate() const {
  if (theta_steps < 1 || theta_steps > 100000) {
    throw UsageError("the number of incidence angles (theta steps) must lie in [1, 100000], got " +
                     std::to_string(theta_steps));
  }
  if (!(theta_max_deg >= 0.0 && theta_max_deg < 90.0)) {
    throw UsageError("the largest theta must be in [0, 90) degrees");
  }
  if (method != AlbedoMethod::kQuadrature && samples < 2) {
    throw UsageError("the Monte Carlo sample count must be at least 2, got " +
                     std::to_string(samples));
  }
  quadrature.Validate();
  if (measured_max_intervals < 1) throw UsageError("measured data need at least one interval");
}

std::vector<double> AlbedoOptions::ThetaDegrees() const {
  std::vector<double> thetas(theta_steps, 0.0);
  for (int k = 1; k < theta_steps; ++k) thetas[k] = theta_max_deg * k / (theta_steps - 1);
  return thetas;
}

namespace {

// One channel's albedo at one incidence, with its error estimate.
struct ChannelAlbedo {
  double albedo = 0, error = 0, theta_deg = 0;
  int channel = 0;
  double coverage = 1.0;

  double lower() const { return albedo - 2.0 * error; }
  double upper() const { return albedo + 2.0 * error; }
  // "1.079 ± 0.042 (r, theta 78.0 deg)"
  std::string Text() const {
    return Fixed(albedo, 4) + " ± " + Significant(error) + " (" + kChannelNames[channel] +
           ", theta " + Fixed(theta_deg, 1) + " deg)";
  }
  // Holes in the data make the albedo less certain than its error estimate says: "" or a clause.
  std::string CoverageCaveat() const {
    if (coverage >= kCoverageWarning) return "";
    return "; the data there cover only " + Fixed(100 * coverage, 1) +
           "% of the cosine-weighted hemisphere, the rest extrapolated or zero";
  }
};

}  // namespace

EnergyVerdict AlbedoCurve::verdict() const {
  EnergyVerdict verdict;
  // The albedos the data decide: those at measured incidences. Of them, the one most surely
  // above 1, the one that may lie highest, and the largest.
  std::optional<ChannelAlbedo> surest, highest, largest;
  for (const AlbedoPoint& point : points) {
    if (point.theta_deg > largest_measured_incidence_deg + 1e-9) continue;
    for (int c = 0; c < 3; ++c) {
      const ChannelAlbedo value{point.estimate.albedo[c], point.estimate.error[c], point.theta_deg,
                                c, point.estimate.coverage};
      if (!surest || value.lower() > surest->lower()) surest = value;
      if (!highest || value.upper() > highest->upper()) highest = value;
      if (!largest || value.albedo > largest->albedo) largest = value;
    }
  }
  if (!largest) {
    verdict.reason = "no albedo was computed at a measured incidence (the data reach " +
                     Fixed(largest_measured_incidence_deg, 1) + " deg)";
    return verdict;
  }
  if (surest->lower() > 1.0 + kAlbedoResolution) {
    verdict.conservation = Conservation::kNotConserving;
    verdict.reason = "albedo " + surest->Text() + " exceeds 1 by " +
                     Significant(surest->albedo - 1.0) + ", more than twice its error estimate" +
                     surest->CoverageCaveat();
    return verdict;
  }
  int worst = 0;
  max_albedo.maxCoeff(&worst);
  const ChannelAlbedo maximum{max_albedo[worst], error_at_max[worst], theta_deg_at_max[worst],
                              worst, coverage_at_max};
  if (maximum.theta_deg > largest_measured_incidence_deg + 1e-9) {
    verdict.reason =
        "the largest albedo, " + maximum.Text() + ", lies beyond the largest measured incidence (" +
        Fixed(largest_measured_incidence_deg, 1) +
        " deg), where the data are extrapolated; at the measured incidences the largest is " +
        largest->Text();
    return verdict;
  }
  if (highest->upper() > 1.0 + kAlbedoResolution) {
    // The largest albedo when it is the one that straddles 1, else the one that reaches highest.
    const ChannelAlbedo& cited = largest->upper() > 1.0 + kAlbedoResolution ? *largest : *highest;
    verdict.reason = "albedo " + cited.Text() + " lies between " + Significant(cited.lower()) +
                     " and " + Significant(cited.upper()) +
                     " within twice its error estimate, on both sides of 1" +
                     cited.CoverageCaveat();
    return verdict;
  }
  verdict.conservation = Conservation::kConserving;
  if (largest->upper() > 1.0 - kAlbedoResolution) {
    verdict.reason = "the largest albedo, " + largest->Text() +
                     ", is 1 within twice its error estimate and " +
                     Significant(kAlbedoResolution) + ": at the bound";
  } else {
    verdict.reason = "the largest albedo, " + largest->Text() + ", stays below 1 by " +
                     Significant(1.0 - largest->albedo) + ", more than twice its error estimate";
  }
  if (largest_measured_incidence_deg < 90.0) {
    verdict.reason += " over the measured incidences (up to " +
                      Fixed(largest_measured_incidence_deg, 1) + " deg)";
  }
  verdict.reason += largest->CoverageCaveat();
  return verdict;
}

double AlbedoCurve::excess() const { return max_albedo.maxCoeff() - 1.0; }

std::string AlbedoCurve::Summary() const {
  return source + " [" + AlbedoMethodName(method) + "]: max albedo " + Rgb3(max_albedo, 6) +
         " at theta " + Fixed(theta_deg_at_max[0], 1) + " " + Fixed(theta_deg_at_max[1], 1) + " " +
         Fixed(theta_deg_at_max[2], 1) + " deg; " + verdict().Text();
}

std::string AlbedoCurve::Report() const {
  std::ostringstream out;
  out << "directional albedo of " << source << " by " << AlbedoMethodName(method) << " ("
      << (method == AlbedoMethod::kQuadrature ? "error = Gauss-Kronrod estimate"
                                              : "error = one standard error")
      << ")\n";
  for (const std::string& note : notes) out << "note: " << note << "\n";
  out << "theta_deg        r         g         b     err_r     err_g     err_b  coverage\n";
  for (const AlbedoPoint& point : points) {
    out << std::setw(9) << Fixed(point.theta_deg, 2);
    for (int c = 0; c < 3; ++c) out << " " << std::setw(9) << Fixed(point.estimate.albedo[c], 6);
    for (int c = 0; c < 3; ++c) {
      out << " " << std::setw(9) << std::scientific << std::setprecision(1)
          << point.estimate.error[c] << std::defaultfloat;
    }
    out << " " << std::setw(9) << Fixed(point.estimate.coverage, 4) << "\n";
  }
  for (const std::string& warning : warnings) out << "warning: " << warning << "\n";
  for (int c = 0; c < 3; ++c) {
    out << "max " << kChannelNames[c] << " = " << Fixed(max_albedo[c], 6) << " +- "
        << std::scientific << std::setprecision(1) << error_at_max[c] << std::defaultfloat
        << " at theta " << Fixed(theta_deg_at_max[c], 2) << " deg\n";
  }
  out << "BRDF evaluations: " << evaluations << "\n";
  out << "verdict: " << verdict().Text() << "\n";
  return out.str();
}

void FinishAlbedoCurve(AlbedoCurve* curve) {
  curve->max_albedo = Rgb::Constant(-std::numeric_limits<double>::infinity());
  curve->min_coverage = 1.0;
  curve->evaluations = 0;
  double theta_of_min_coverage = 0, first_low_coverage = -1;
  for (const AlbedoPoint& point : curve->points) {
    for (int c = 0; c < 3; ++c) {
      if (point.estimate.albedo[c] > curve->max_albedo[c]) {
        curve->max_albedo[c] = point.estimate.albedo[c];
        curve->error_at_max[c] = point.estimate.error[c];
        curve->theta_deg_at_max[c] = point.theta_deg;
      }
    }
    if (point.estimate.coverage < curve->min_coverage) {
      curve->min_coverage = point.estimate.coverage;
      theta_of_min_coverage = point.theta_deg;
    }
    if (point.estimate.coverage < kCoverageWarning && first_low_coverage < 0) {
      first_low_coverage = point.theta_deg;
    }
    curve->evaluations += point.estimate.evaluations;
  }
  if (curve->points.empty()) curve->max_albedo = Rgb::Zero();
  int worst = 0;
  curve->max_albedo.maxCoeff(&worst);
  for (const AlbedoPoint& point : curve->points) {
    if (point.theta_deg == curve->theta_deg_at_max[worst]) {
      curve->coverage_at_max = point.estimate.coverage;
    }
  }
  if (first_low_coverage >= 0) {
    curve->warnings.push_back(
        "the data cover less than " + Fixed(100 * kCoverageWarning, 0) +
        "% of the cosine-weighted hemisphere from theta = " + Fixed(first_low_coverage, 1) +
        " deg (least: " + Fixed(100 * curve->min_coverage, 1) + "% at " +
        Fixed(theta_of_min_coverage, 1) +
        " deg); values there are extrapolated or zero (see the notes), so the albedo is less "
        "certain than its error estimate says");
  }
}

AlbedoEstimate ModelDirectionalAlbedo(const Model& model, double theta_o,
                                      const AlbedoOptions& options, uint64_t stream) {
  const Vec3 wo = OutgoingAt(theta_o);
  const std::vector<AlbedoTerm> terms = AlbedoTerms(model);
  AlbedoEstimate estimate;
  switch (options.method) {
    case AlbedoMethod::kQuadrature: {
      // Each term gets an equal share of the error budget.
      LobeQuadratureOptions per_term = options.quadrature;
      per_term.tolerance /= static_cast<double>(terms.size());
      for (const AlbedoTerm& term : terms) {
        estimate +=
            IntegrateInLobeCoordinates(ModelBrdf(term.model), wo, term.coordinates, per_term);
      }
      return estimate;
    }
    case AlbedoMethod::kMonteCarlo: {
      Rng random(stream, options.seed);
      return EstimateAlbedoCosine(ModelBrdf(model), wo, options.samples, &random);
    }
    case AlbedoMethod::kImportance: {
      Rng random(stream, options.seed);
      return EstimateAlbedoByMixture(ModelBrdf(model), wo, ImportanceStrategies(terms),
                                     options.samples, &random);
    }
  }
  return estimate;
}

AlbedoEstimate MeasuredDirectionalAlbedo(const MeasuredBrdf& measured, double theta_o,
                                         const AlbedoOptions& options, uint64_t stream) {
  // Measured data need not be reciprocal (RGL-EPFL tables at grazing): the albedo at an
  // incidence integrates f(wi, wo) cos(theta_o) over the outgoing hemisphere with wi held, as the
  // data's reference does. The integrators hold their second argument, so the data are handed
  // to them with the directions swapped; for reciprocal data it is the same integral.
  const Vec3 wi = OutgoingAt(theta_o);
  const BrdfFunction held_light = [&measured](const Vec3& wo, const Vec3& light) {
    return measured.brdf(light, wo);
  };
  switch (options.method) {
    case AlbedoMethod::kQuadrature: {
      LobeQuadratureOptions capped = options.quadrature;
      capped.max_intervals = std::min(capped.max_intervals, options.measured_max_intervals);
      return IntegrateInLobeCoordinates(held_light, wi, measured.coordinates, capped);
    }
    case AlbedoMethod::kMonteCarlo: {
      Rng random(stream, options.seed);
      return EstimateAlbedoCosine(held_light, wi, options.samples, &random);
    }
    case AlbedoMethod::kImportance:
      break;
  }
  throw UsageError(
      "importance sampling draws from a model's lobe; for measured data use the "
      "quadrature or mc method");
}

AlbedoCurve ModelAlbedoCurve(const Model& model, const AlbedoOptions& options, Progress* progress) {
  AlbedoCurve curve =
      ComputeCurve(model.ToString(7), options, progress, [&](double theta_o, uint64_t stream) {
        return ModelDirectionalAlbedo(model, theta_o, options, stream);
      });
  FinishAlbedoCurve(&curve);
  if (options.method == AlbedoMethod::kMonteCarlo) {
    const std::string warning = SparseLobeWarning(model, options);
    if (!warning.empty()) curve.warnings.push_back(warning);
  }
  return curve;
}

AlbedoCurve MeasuredAlbedoCurve(const MeasuredBrdf& measured, const AlbedoOptions& options,
                                Progress* progress) {
  if (options.method == AlbedoMethod::kImportance) {
    MeasuredDirectionalAlbedo(measured, 0.0, options);  // throws the descriptive error
  }
  AlbedoCurve curve =
      ComputeCurve(measured.source, options, progress, [&](double theta_o, uint64_t stream) {
        return MeasuredDirectionalAlbedo(measured, theta_o, options, stream);
      });
  curve.notes = measured.notes;
  curve.largest_measured_incidence_deg = measured.largest_incidence_deg;
  FinishAlbedoCurve(&curve);
  return curve;
}

}  // namespace brdf
