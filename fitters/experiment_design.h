// Optimal experimental design for a fit (DESIGN §3, `brdf plan`; docs/planning.md): which
// direction pairs a measurement should visit so that the fitted parameters come out with the
// smallest variance. The Fisher information of a set of readings is sum_i J_i^T W_i J_i, J_i
// the Jacobian of reading i's model value with respect to the fitter's variables
// (parameterization.h; the same Ceres cost functions the fit differentiates, covariance.h) and
// W_i = 1 / sigma_i^2 per channel, sigma_i the noise the instrument will state for the reading.
//
// Criteria (Atkinson & Donev, "Optimum Experimental Designs"):
//   d          maximise log det of the information (the volume of the confidence ellipsoid);
//              invariant to how the parameters are scaled or reparameterized.
//   a          minimise the sum of the free parameters' squared relative standard errors.
//   param:NAME minimise one parameter's squared relative standard error (summed over its
//              channels).
// The design is chosen greedily from a candidate set, one geometry at a time, each adding the
// rank-3 (one row per channel) term U U^T: the determinant lemma gives the gain
// log det(I + U^T M^-1 U) and Woodbury the new M^-1 in O(n^2) per candidate. log det is
// monotone submodular in the chosen set, so "lazy" evaluation (a stale gain is an upper bound)
// returns exactly the greedy design while evaluating few candidates per step. The trace
// criteria are not submodular: the same lazy scheme is a heuristic for them, refreshed with a
// full evaluation every kFullRefresh steps.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "core/measurement.h"
#include "core/vec.h"
#include "gonio/instrument.h"
#include "models/registry.h"

namespace brdf::fitters {

// One candidate reading: nominal directions and the one-sigma noise of its value (sr^-1): the
// sigma the instrument will state (what the information and a fit weigh the reading by), and
// the part of it that is independent from reading to reading (what a fit's scatter follows;
// the rest is common to the run, ExpectedNoise::common_scale_variance).
struct DesignPoint {
  Vec3 wi, wo;
  Rgb sigma = Rgb::Ones();
  Rgb independent_sigma = Rgb::Ones();
};

enum class DesignCriterion { kD, kA, kParam };

struct DesignOptions {
  DesignCriterion criterion = DesignCriterion::kD;
  std::string param;  // the parameter of kParam
  int budget = 0;     // geometries to choose
  // Two chosen geometries must differ by at least this much in incidence or in detector
  // direction (degrees); 0: only distinct geometries.
  double min_separation_deg = 0;
};

// Parses "d", "a" or "param:NAME" for `model`; throws UsageError naming an unknown criterion or
// a parameter the model does not have.
DesignOptions ParseCriterion(const std::string& text, const Model& model);

struct DesignResult {
  std::vector<size_t> chosen;  // candidate indices in the order they were chosen
  double log_det = 0;          // of the chosen set's information on the free variables
};

// What the plan can and cannot inform at `model`: one message per parameter at a bound (its
// fitter variable is saturated and held out, as covariance.h holds it out of a fit).
std::vector<std::string> DesignWarnings(const Model& model);

// Greedy choice of options.budget candidates (see above). Throws UsageError when the budget
// exceeds what the candidates and the separation allow, when the criterion's parameter is at a
// bound, or when a sigma is not positive; deterministic (ties go to the lower index). With an
// `instrument`, every reading is predicted through it as a fit through it will predict it
// (reading_nodes.h): the model averaged over the source and detector apertures.
DesignResult ChooseDesign(const Model& model, const std::vector<DesignPoint>& candidates,
                          const DesignOptions& options,
                          const gonio::Instrument* instrument = nullptr);

// log det of the information of `points` on the free variables (-inf when singular), through
// `instrument` when given.
double InformationLogDet(const Model& model, const std::vector<DesignPoint>& points,
                         const gonio::Instrument* instrument = nullptr);

struct PredictedErrors {
  std::vector<double> stderr_values;  // one per model parameter; NaN when not available
  bool available = false;
  std::string note;  // why not, when they are not
};

// The noise of a run beyond the sigma its readings state.
struct ExpectedNoise {
  // Per sample, the one-sigma noise independent from reading to reading; empty: all of the
  // stated sigma is.
  std::vector<Rgb> independent_sigma;
  // Relative variance of an error shared by every value of the run (the instrument's
  // reference): it moves the fit along the direction a common scale of all values moves it,
  // whatever the geometries.
  double common_scale_variance = 0;
  // Variance (radians², per axis) of the light arm's positioning jitter: it moves the incidence
  // once for all the readings of that incidence (samples of equal wi), which shift together.
  double light_arm_variance = 0;
  // Variance (radians², per axis) of the detector arm's jitter, drawn once per reading and
  // common to its three channels. When > 0, independent_sigma must leave the detector arm out.
  double detector_arm_variance = 0;
};

// The noise of a run at `points`: their independent sigmas, the run's common scale variance and
// the light arm's jitter variance.
ExpectedNoise ExpectedNoiseAt(const std::vector<DesignPoint>& points, double common_scale_variance,
                              double light_arm_variance = 0, double detector_arm_variance = 0);

// The standard errors `brdf fit` (L2 loss, its default) will report for a measurement of
// `model` at the geometries of `measurement`, whose `sigma` is the sigma its readings will
// state: the fit's own sample weights (PrepareSamples: solid angle, the file's weights,
// sigma) and the sandwich covariance with the expected squared residuals (from `noise`) in
// place of measured ones. `measurement`'s values must be the model's (noise-free). A
// measurement that records its instrument (fit_samples.h: kInstrumentKey) is predicted through
// it, as the fit will read it.
PredictedErrors PredictErrors(const Model& model, const Measurement& measurement,
                              const ExpectedNoise& noise = {});

}  // namespace brdf::fitters
