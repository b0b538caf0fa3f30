#include "fitters/fit.h"

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "core/deterministic_reduce.h"
#include "core/enum_names.h"
#include "core/errors.h"
#include "core/text.h"
#include "fitters/diagnostics.h"
#include "fitters/energy_check.h"
#include "fitters/fit_composition.h"
#include "fitters/reading_nodes.h"

namespace brdf::fitters {

bool Converged(const ceres::Solver::Summary& summary) {
  return summary.termination_type == ceres::CONVERGENCE ||
         summary.termination_type == ceres::USER_SUCCESS;
}

constexpr EnumName<Robust> kRobustNames[] = {
    {Robust::kNone, "none"},
    {Robust::kHuber, "huber"},
    {Robust::kCauchy, "cauchy"},
};

Robust ParseRobust(const std::string& name) { return ParseEnum(kRobustNames, name, "robust loss"); }

const char* RobustName(Robust robust) { return NameOf(kRobustNames, robust); }

void FitOptions::Validate() const {
  if (max_iterations < 1) throw UsageError("the iteration limit of a fit must be at least 1");
  if (samples_per_block < 1)
    throw UsageError("the samples per evaluation block must be at least 1");
  if (max_samples != 0 && max_samples < 100) {
    throw UsageError("the subsample size (max samples) must be 0 (all) or at least 100");
  }
  if (threads < 0) throw UsageError("the thread count must not be negative");
  if (start_exponents.empty()) throw UsageError("at least one start exponent is needed");
  for (double exponent : start_exponents) {
    if (!(exponent >= models::kMinFitExponent && exponent <= models::kMaxFitExponent)) {
      throw UsageError("start exponents must lie in [1, 1e6]");
    }
  }
  if (start_alphas.empty()) throw UsageError("at least one start alpha is needed");
  for (double alpha : start_alphas) {
    if (!(alpha >= models::kMinFitRoughness && alpha <= models::kMaxFitRoughness)) {
      throw UsageError("start alphas must lie in [0.001, 1.5]");
    }
  }
}

std::string FitResult::Summary() const {
  std::ostringstream line;
  line << model.ToString(kShownDigits) << "  rmse " << metrics.rmse << " sr^-1, "
       << (converged ? "converged" : "NOT converged") << ", " << samples << " samples, " << time_s
       << " s";
  return line.str();
}

FitResult FitPreparedSamples(const PreparedSamples& prepared, const std::string& model_name,
                             const FitOptions& options, SubsampleOptimum* optimum) {
  options.Validate();
  if (options.loss == Loss::kAuto) {
    throw ComputeError("a fit of prepared samples needs a resolved loss (ResolveLoss)");
  }
  // Ceres reports rank deficiency through glog warnings; the fit report says it in words.
  static const bool quiet_ceres = [] {
    FLAGS_minloglevel = google::GLOG_ERROR;
    return true;
  }();
  (void)quiet_ceres;
  const auto start = std::chrono::steady_clock::now();
  const ModelInfo& info = FindModel(model_name);
  FitResult result = InFitArena(options.threads, [&] {
    return VisitModelType(model_name, [&](auto model_type) {
      return FitComposition<decltype(model_type)>(info, prepared, options, optimum);
    });
  });
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

void FinishFit(const PreparedSamples& prepared, const FitOptions& options, FitResult* result,
               const FitResult* diffuse_only) {
  const auto start = std::chrono::steady_clock::now();
  CheckFitEnergy(result);
  const ModelInfo& info = result->model.info();
  std::optional<FitResult> fitted;
  if (info.has_lobe() && diffuse_only == nullptr) {
    diffuse_only = &fitted.emplace(FitPreparedSamples(prepared, info.diffuse, options));
  }
  AppendFitDiagnostics(prepared, result, info.has_lobe() ? diffuse_only : nullptr);  // stability.md
  if (prepared.instrument != nullptr) {
    const std::string blur = ApertureBlurWarning(*prepared.instrument, result->model);
    if (!blur.empty()) result->warnings.push_back(blur);
  }
  result->time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

FitResult FitModel(const Measurement& measurement, const std::string& model_name,
                   const FitOptions& options) {
  options.Validate();
  FindModel(model_name);  // an unknown name is a usage error before any work
  const auto start = std::chrono::steady_clock::now();
  FitOptions resolved = options;
  resolved.loss = ResolveLoss(options.loss, measurement);
  PreparedSamples prepared = PrepareSamples(measurement, resolved.loss);
  FitResult result = FitPreparedSamples(prepared, model_name, resolved);
  FinishFit(prepared, resolved, &result);
  Release(&prepared);
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace brdf::fitters
