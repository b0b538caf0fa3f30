// Fitting a reflectance model to a measurement with Ceres (DESIGN §6).
//
//   FitOptions options;            // defaults: L2 loss, no robust loss, multi-start
//   options.Validate();
//   FitResult fit = FitModel(measurement, "blinn-phong", options);
//   std::cout << fit.Summary() << "\n";
#pragma once

#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/measurement.h"
#include "energy/verdict.h"
#include "fitters/fit_samples.h"
#include "models/registry.h"

namespace brdf::fitters {

enum class Robust { kNone, kHuber, kCauchy };
Robust ParseRobust(const std::string& name);
const char* RobustName(Robust robust);

struct FitOptions {
  Loss loss = Loss::kL2;
  Robust robust = Robust::kNone;
  bool grey_specular = false;  // one rho_s for all channels
  size_t max_samples = 20000;  // stratified subsample for the starts; 0 = use every sample
  uint64_t seed = 1;           // of the subsample draw
  int threads = 0;             // 0 = all cores; the result does not depend on it
  int max_iterations = 200;
  int samples_per_block = 256;  // samples per batch of the objective's sums (objective.h)
  // Multi-start: exponents tried from the data-driven guess of rho_d and rho_s; log-spaced
  // over the range real materials span (~1 to ~1e5).
  std::vector<double> start_exponents = {2, 8, 32, 128, 512, 2048, 8192, 32768};
  // Microfacet models: alphas tried, each with f0 from the data's peak and with f0 = 0.04 (a
  // dielectric coat); log-spaced from a near-mirror (alpha 2e-3: a polished coat's or a metal's
  // highlight, which a start of 0.02 misses, settling on a broad lobe) to a matte-like roughness.
  std::vector<double> start_alphas = {0.002, 0.006, 0.02, 0.05, 0.12, 0.3, 0.7};
  int start_iterations = 30;  // iterations per start (at most max_iterations)

  // Throws UsageError naming the bad field.
  void Validate() const;
};

struct FitMetrics {
  // Solid-angle-weighted means over all fitted samples and channels.
  double rmse = 0;       // of f, sr^-1
  double log_rmse = 0;   // of log(1 + f cos theta_i)
  double cosine_l2 = 0;  // of f cos theta_i (Ngan et al. 2005)
};

// The fitted material's directional albedo, integrated by the energy library (DESIGN §7),
// next to the closed-form bound the fit enforced.
struct EnergyCheck {
  Rgb max_albedo = Rgb::Zero();    // over incidence angles, per channel
  Rgb albedo_error = Rgb::Zero();  // the integrator's error estimate at the maximum
  std::array<double, 3> theta_deg_at_max = {0, 0, 0};
  Rgb bound = Rgb::Zero();  // rho_d + the lobe's largest albedo (energy_bound.h), <= 1
  EnergyVerdict verdict;    // the albedo curve's (energy/albedo.h)
  std::string method;
};

// Significant digits of the parameters printed for a person (the report's table, Summary): as
// many as a person reads, enough that the printed model string reproduces the fit to them. JSON
// reports keep full precision.
inline constexpr int kShownDigits = 7;

struct FitResult {
  Model model;
  std::vector<double> stderr_values;  // one per model parameter; NaN when not available
  bool stderr_available = false;
  std::string stderr_note;  // why not, when they are not
  FitMetrics metrics;
  Loss loss = Loss::kL2;
  Robust robust = Robust::kNone;
  size_t samples = 0;  // samples fitted
  size_t skipped = 0;  // missing or invalid samples left out
  std::string weighting;
  bool converged = false;
  int iterations = 0;
  double time_s = 0;
  double final_cost = 0;
  double bic = 0;  // Bayesian information criterion of the fit
  int free_variables = 0;
  EnergyCheck energy;
  std::string termination;  // Ceres' one-line report of the final solve
  std::vector<std::string> warnings;

  explicit FitResult(Model fitted) : model(std::move(fitted)) {}
  // One line for a person: model, parameters (kShownDigits significant digits), rmse, converged,
  // time.
  std::string Summary() const;
};

// A fit's optimum on its stratified subsample (steps 1 and 2 of FitPreparedSamples: the
// multi-start and the refinement), and the solver iterations spent reaching it. It depends only
// on the model, the options and Subsample(samples, max_samples, seed), so `--model auto`, whose
// candidates compete on that very subsample, hands the winner's to its fit on every sample
// instead of finding it a second time.
struct SubsampleOptimum {
  bool found = false;
  std::vector<double> variables;  // the fitter's (parameterization.h)
  int iterations = 0;
};

// `work()` with every parallel loop in an arena of `threads` workers (0: as many as cores); no
// fit's result depends on their number. A caller already in such an arena keeps it: work in an
// arena of its own could not use the caller's workers (`auto` fits its candidates side by side in
// one, and a candidate in an arena of its own, the last to finish, ran on one core of two).
template <typename Work>
auto InFitArena(int threads, Work&& work) {
  const int workers = threads > 0 ? threads : tbb::info::default_concurrency();
  if (tbb::this_task_arena::max_concurrency() == workers) return work();
  tbb::task_arena arena(workers);
  return arena.execute(work);
}

// The whole fit: PrepareSamples, FitPreparedSamples, FinishFit on the same samples, which are
// then released.
FitResult FitModel(const Measurement& measurement, const std::string& model_name,
                   const FitOptions& options);
// The fit alone, on PrepareSamples(measurement): parameters, standard errors,
// metrics and BIC, without the energy check and the diagnostics. `optimum`, when given and
// found, is where the polish starts (it must come from a fit of the same model and options
// whose samples had the same Subsample); when given and not found, it receives this fit's.
FitResult FitPreparedSamples(const PreparedSamples& prepared, const std::string& model_name,
                             const FitOptions& options, SubsampleOptimum* optimum = nullptr);
// The energy check (energy_check.h) and the warnings (diagnostics.h) of a fit of `prepared`
// under `options`; a model with a lobe is compared with its diffuse term fitted alone to the same
// samples under the same options (is the lobe more than noise?): `diffuse_only` when the caller
// has that fit, else it is made here.
void FinishFit(const PreparedSamples& prepared, const FitOptions& options, FitResult* result,
               const FitResult* diffuse_only = nullptr);

}  // namespace brdf::fitters
