// The Ceres residual: a small templated functor over raw parameter arrays, so one definition
// serves double and ceres::Jet (automatic differentiation), after Ceres' own examples. Each
// functor holds a batch of samples rather than one: with ~1e6 samples, per-sample overhead
// would dominate, and batches are what ParallelBatchCost (parallel_cost.h) spreads over threads
// (docs/fitting.md measures the batch size).
#pragma once

#include <cmath>

#include "fitters/fit_samples.h"
#include "fitters/parameterization.h"

namespace brdf::fitters {

// The model's value f as the loss compares it with LossTarget (fit_samples.h): f, log(1 + f cos
// theta_i) or f cos theta_i; and its derivative d/df, for the analytic Jacobians.
template <typename T>
T LossPrediction(Loss loss, const T& f, double cos_theta_i) {
  using std::log;
  if (loss == Loss::kLog) return log(T(1) + f * cos_theta_i);
  if (loss == Loss::kCosineL2) return f * cos_theta_i;
  return f;
}
inline double LossPredictionDerivative(Loss loss, double f, double cos_theta_i) {
  if (loss == Loss::kLog) return cos_theta_i / (1.0 + f * cos_theta_i);
  if (loss == Loss::kCosineL2) return cos_theta_i;
  return 1.0;
}

template <typename ModelType>
class BatchResidual {
 public:
  BatchResidual(bool grey_specular, Loss loss, const FitSample* samples, int count)
      : grey_specular_(grey_specular), loss_(loss), samples_(samples), count_(count) {}

  int num_residuals() const { return 3 * count_; }

  // lambert: one parameter block, d[3].
  template <typename T>
  bool operator()(const T* d, T* residuals) const {
    T params[ModelType::kNumParams];
    VariablesToParams<ModelType, T>(grey_specular_, d, nullptr, nullptr, params);
    return Residuals(params, residuals);
  }

  // Lobed models: d[3], s[1 or 3], shape[1] (parameterization.h).
  template <typename T>
  bool operator()(const T* d, const T* s, const T* shape, T* residuals) const {
    T params[ModelType::kNumParams];
    VariablesToParams<ModelType, T>(grey_specular_, d, s, shape, params);
    return Residuals(params, residuals);
  }

 private:
  template <typename T>
  bool Residuals(const T* params, T* residuals) const {
    for (int k = 0; k < count_; ++k) {
      const FitSample& sample = samples_[k];
      // Directions stay plain doubles: only the parameters carry derivatives.
      const RgbT<T> f = ModelType::template Eval<T>(params, sample.wi, sample.wo);
      const double cos_theta_i = sample.cos_theta_i();
      const Rgb target = LossTarget(loss_, sample.value, cos_theta_i);
      for (int c = 0; c < 3; ++c) {
        residuals[3 * k + c] =
            (LossPrediction(loss_, f[c], cos_theta_i) - target[c]) * sample.scale[c];
      }
    }
    return true;
  }

  bool grey_specular_;
  Loss loss_;
  const FitSample* samples_;
  int count_;
};

}  // namespace brdf::fitters
