// The pieces of one model's fit that depend on the model's type: its variables and their
// blocks, the data-driven starts of the multi-start, building and solving a Ceres problem over
// a set of samples, and the per-sample reweighting of a robust loss. fit.cpp runs them in order
// (multi-start, refine, polish); covariance.h turns the result into standard errors.
#pragma once

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "fitters/analytic_cost.h"
#include "fitters/fit.h"
#include "fitters/parallel_cost.h"
#include "fitters/parameterization.h"
#include "fitters/residual.h"

namespace brdf::fitters {

// Samples per Ceres residual block, each a ParallelBatchCost of BatchResiduals: large enough to
// keep every thread busy inside one block, small enough that Ceres' scratch copy of a block's
// Jacobian stays a few MB.
inline constexpr size_t kSamplesPerSolverBlock = size_t{1} << 16;

// One start of the multi-start: the lobe's width (an exponent or an alpha), for the microfacet
// models whether f0 comes from the data's peak or is a dielectric's 0.04, and where in the
// values' ranks the diffuse floor is read (a lobed model's value is never below rho_d / pi).
struct FitStart {
  double shape = 1.0;
  bool f0_from_peak = true;
  double floor_rank = 0.2;
};

// The floor ranks of the multi-start. A measurement spread over the hemisphere sees a lobe in
// few of its samples, so its lower fifth is the diffuse floor, safe from noise and grazing
// outliers. A designed schedule (`brdf plan`) can put most of its samples on the lobe: there the
// lower fifth is the lobe itself, and a start with rho_d that high settles with rho_d at zero
// (a local minimum). Its off-lobe samples are the lowest few percent.
inline constexpr double kFloorRank = 0.2;
inline constexpr double kLowFloorRank = 0.01;

template <typename ModelType>
class ModelFitter {
 public:
  static constexpr bool kLobed = kHasLobe<ModelType>;
  static constexpr bool kMicrofacet = ModelType::kFamily == models::ModelFamily::kMicrofacet;

  explicit ModelFitter(const FitOptions& options) : options_(options) {}

  int SpecularSize() const { return kLobed ? (options_.grey_specular ? 1 : 3) : 0; }
  int FreeVariables() const { return kLobed ? 3 + SpecularSize() + 1 : 3; }

  std::vector<double> Params(const Variables& v) const {
    std::vector<double> params(ModelType::kNumParams);
    VariablesToParams<ModelType, double>(options_.grey_specular, v.d, v.s, v.shape, params.data());
    return params;
  }

  // The multi-start's starts: exponents for a power-cosine lobe, alphas times two f0 guesses for
  // a microfacet lobe, one start for lambert; for a lobe measured on a `designed` schedule,
  // every start again with the floor read from the lowest values.
  std::vector<FitStart> Starts(bool designed) const {
    std::vector<FitStart> starts;
    if constexpr (!kLobed) {
      starts.push_back({});
    } else if constexpr (kMicrofacet) {
      for (double alpha : options_.start_alphas) {
        starts.push_back({alpha, true});
        starts.push_back({alpha, false});
      }
    } else {
      for (double exponent : options_.start_exponents) starts.push_back({exponent, true});
    }
    if (kLobed && designed) {
      const size_t count = starts.size();
      for (size_t k = 0; k < count; ++k) {
        starts.push_back(starts[k]);
        starts.back().floor_rank = kLowFloorRank;
      }
    }
    return starts;
  }

  // Data-driven start: rho_d from the diffuse floor, the lobe's albedo parameter from the peak
  // height above it, both pulled inside the energy budget.
  Variables InitialGuess(const std::vector<FitSample>& samples, const FitStart& start) const {
    Variables v;
    // The brightest sample (by its largest channel): where the lobe is seen.
    size_t peak_index = 0;
    for (size_t k = 1; k < samples.size(); ++k) {
      if (samples[k].value.maxCoeff() > samples[peak_index].value.maxCoeff()) peak_index = k;
    }
    for (int c = 0; c < 3; ++c) {
      std::vector<double> values;
      values.reserve(samples.size());
      for (const FitSample& sample : samples) values.push_back(sample.value[c]);
      const size_t floor_rank = RankIndex(values.size(), kLobed ? start.floor_rank : 0.5);
      std::nth_element(values.begin(), values.begin() + floor_rank, values.end());
      const double floor_value = std::max(values[floor_rank], 0.0);
      const double peak = *std::max_element(values.begin(), values.end());
      double rho_d = std::clamp(kPi * floor_value, 1e-3, 0.9);
      if constexpr (!kLobed) {
        v.d[c] = Logit(rho_d);
      } else if constexpr (kMicrofacet) {
        v.s[c] = Logit(MicrofacetF0Guess(samples[peak_index], rho_d, c, start));
      } else {
        // The model's own value at the lobe peak (wi = wo = normal) per unit rho_s.
        double unit[models::LobedSlots::kNumParams] = {0, 0, 0, 1, 1, 1, start.shape};
        const Vec3 normal(0, 0, 1);
        const double peak_per_rho_s = ModelType::template Eval<double>(unit, normal, normal)[0];
        const double rho_s = std::max(peak - rho_d / kPi, 1e-6) / peak_per_rho_s;
        const double q = std::clamp(ModelType::NormalLobeAlbedo(start.shape) * rho_s, 1e-6, 0.9);
        rho_d = std::min(rho_d, 0.99 * (1.0 - q));
        v.d[c] = Logit(rho_d / (1.0 - q));
        v.s[c] = Logit(q);
      }
      if constexpr (kMicrofacet) {
        const double f0 = Logistic(v.s[c]);
        const double budget =
            1.0 - AlbedoTableOf<ModelType>().MaxLobeAlbedo(std::log(start.shape), f0);
        rho_d = std::min(rho_d, 0.99 * std::max(budget, 1e-6));
        v.d[c] = Logit(std::clamp(rho_d / std::max(budget, 1e-6), 1e-6, 1 - 1e-6));
      }
    }
    if (options_.grey_specular) v.s[0] = (v.s[0] + v.s[1] + v.s[2]) / 3.0;
    v.shape[0] = std::log(start.shape);
    return v;
  }

  // A least-squares problem over `samples`, which must outlive it. Robust losses act per
  // sample through Reweight, not per (batched) residual block.
  std::unique_ptr<ceres::Problem> BuildProblem(const std::vector<FitSample>& samples,
                                               Variables* v) const {
    auto problem = std::make_unique<ceres::Problem>();
    ceres::LossFunction* const loss = nullptr;
    const size_t block = static_cast<size_t>(options_.samples_per_block);
    const int s_size = SpecularSize();
    const std::vector<int32_t> block_sizes =
        kLobed ? std::vector<int32_t>{3, s_size, 1} : std::vector<int32_t>{3};
    for (size_t solver_start = 0; solver_start < samples.size();
         solver_start += kSamplesPerSolverBlock) {
      const size_t solver_end = std::min(samples.size(), solver_start + kSamplesPerSolverBlock);
      std::vector<std::unique_ptr<ceres::CostFunction>> batches;
      for (size_t start = solver_start; start < solver_end; start += block) {
        const int count = static_cast<int>(std::min(block, solver_end - start));
        batches.emplace_back(MakeCost(samples.data() + start, count));
      }
      auto* cost = new ParallelBatchCost(std::move(batches), block_sizes);
      if constexpr (kLobed) {
        problem->AddResidualBlock(cost, loss, v->d, v->s, v->shape);
      } else {
        problem->AddResidualBlock(cost, loss, v->d);
      }
    }
    SetVariableBounds(problem.get(), v);
    return problem;
  }

  // Bounds `problem`'s parameter blocks, those of `v`, to VariableBounds().
  void SetVariableBounds(ceres::Problem* problem, Variables* v) const {
    const int s_size = SpecularSize();
    const Bounds bounds = VariableBounds();
    for (int k = 0; k < 3; ++k) {
      problem->SetParameterLowerBound(v->d, k, bounds.lower[k]);
      problem->SetParameterUpperBound(v->d, k, bounds.upper[k]);
    }
    if constexpr (kLobed) {
      for (int k = 0; k < s_size; ++k) {
        problem->SetParameterLowerBound(v->s, k, bounds.lower[3 + k]);
        problem->SetParameterUpperBound(v->s, k, bounds.upper[3 + k]);
      }
      problem->SetParameterLowerBound(v->shape, 0, bounds.lower[3 + s_size]);
      problem->SetParameterUpperBound(v->shape, 0, bounds.upper[3 + s_size]);
    }
  }

  // The box of the free variables, in the order d, s, shape (FreeVariables() of each).
  struct Bounds {
    std::vector<double> lower, upper;
  };
  Bounds VariableBounds() const {
    Bounds bounds;
    bounds.lower.assign(FreeVariables(), -FitVariables::kLogisticBound);
    bounds.upper.assign(FreeVariables(), FitVariables::kLogisticBound);
    if constexpr (kLobed) {
      bounds.lower.back() = ShapeLowerBound<ModelType>();
      bounds.upper.back() = ShapeUpperBound<ModelType>();
    }
    return bounds;
  }

  ceres::Solver::Summary Solve(ceres::Problem* problem, int max_iterations) const {
    ceres::Solver::Options solver_options;
    solver_options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    solver_options.max_num_iterations = max_iterations;
    // One solver thread: the residual blocks evaluate themselves in parallel
    // (ParallelBatchCost), so the result does not depend on the thread count.
    solver_options.num_threads = 1;
    solver_options.function_tolerance = 1e-12;
    solver_options.gradient_tolerance = 1e-14;
    solver_options.parameter_tolerance = 1e-12;
    solver_options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, problem, &summary);
    return summary;
  }

  // Squared norm of each sample's (3-channel) weighted residual at `v`, from the same functor
  // Ceres differentiates.
  std::vector<double> SquaredResiduals(const std::vector<FitSample>& samples,
                                       const Variables& v) const {
    std::vector<double> squared(samples.size());
    tbb::parallel_for(size_t{0}, samples.size(), [&](size_t k) {
      const BatchResidual<ModelType> residual(options_.grey_specular, options_.loss, &samples[k],
                                              1);
      double r[3];
      if constexpr (kLobed) {
        residual(v.d, v.s, v.shape, r);
      } else {
        residual(v.d, r);
      }
      squared[k] = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    });
    return squared;
  }

  // Iteratively reweighted least squares for a robust loss rho (Huber or Cauchy, evaluated by
  // Ceres' own loss functions): each sample's residual is scaled by sqrt(rho'(s_i)) at the
  // current fit, s_i its squared residual norm. The loss acts per sample — a blind spot zeroes
  // one sample, not a whole residual block. The scale is 3 x the robust standard deviation
  // (1.4826 x median absolute residual), so inliers stay in the quadratic part.
  std::vector<FitSample> Reweight(const std::vector<FitSample>& samples, const Variables& v,
                                  double* scale) const {
    const std::vector<double> squared = SquaredResiduals(samples, v);
    if (*scale <= 0) {
      std::vector<double> norms(squared.size());
      double mean_square = 0;
      for (size_t k = 0; k < squared.size(); ++k) {
        norms[k] = std::sqrt(squared[k]);
        mean_square += squared[k];
      }
      const size_t middle = norms.size() / 2;
      std::nth_element(norms.begin(), norms.begin() + middle, norms.end());
      mean_square /= std::max<size_t>(1, squared.size());
      *scale =
          std::max(3.0 * 1.4826 * norms[middle], 1e-9 * std::max(std::sqrt(mean_square), 1e-12));
    }
    std::unique_ptr<ceres::LossFunction> loss;
    if (options_.robust == Robust::kHuber) {
      loss = std::make_unique<ceres::HuberLoss>(*scale);
    } else {
      loss = std::make_unique<ceres::CauchyLoss>(*scale);
    }
    std::vector<FitSample> weighted = samples;
    for (size_t k = 0; k < samples.size(); ++k) {
      double rho[3];
      loss->Evaluate(squared[k], rho);
      weighted[k].scale *= std::sqrt(std::max(rho[1], 0.0));
    }
    return weighted;
  }

  const FitOptions& options() const { return options_; }

 private:
  // A lobed model's batches carry their hand-written Jacobian (analytic_cost.h); lambert's are
  // differentiated automatically.
  ceres::CostFunction* MakeCost(const FitSample* samples, int count) const {
    using Residual = BatchResidual<ModelType>;
    if constexpr (kLobed) {
      return new AnalyticBatchCost<ModelType>(options_.grey_specular, options_.loss, samples,
                                              count);
    } else {
      return new ceres::AutoDiffCostFunction<Residual, ceres::DYNAMIC, 3>(
          new Residual(options_.grey_specular, options_.loss, samples, count), 3 * count);
    }
  }

  // f0 of channel c for a microfacet start: from the peak (the model's own value there with
  // f0 = 0 and f0 = 1, Schlick being linear in f0), or a dielectric's 0.04 — the Fresnel rise
  // toward grazing then has to come from the data, which keeps a start from mistaking a
  // grazing peak for a metal.
  static size_t RankIndex(size_t size, double rank) {
    return std::min(size - 1, static_cast<size_t>(rank * static_cast<double>(size)));
  }

  double MicrofacetF0Guess(const FitSample& peak_sample, double rho_d, int c,
                           const FitStart& start) const {
    if (!start.f0_from_peak) return 0.04;
    double unit[ModelType::kNumParams] = {0, 0, 0, 0, 0, 0, start.shape};
    const double at_zero =
        ModelType::template Eval<double>(unit, peak_sample.wi, peak_sample.wo)[0];
    for (int k = 0; k < 3; ++k) unit[ModelType::kF0 + k] = 1.0;
    const double at_one = ModelType::template Eval<double>(unit, peak_sample.wi, peak_sample.wo)[0];
    const double excess = peak_sample.value[c] - rho_d / kPi - at_zero;
    if (!(at_one - at_zero > 1e-12)) return 0.04;
    return std::clamp(excess / (at_one - at_zero), 0.005, 0.95);
  }

  const FitOptions& options_;
};

}  // namespace brdf::fitters
