// A fit's residual as a small templated functor over raw parameter arrays, so one definition
// serves double and ceres::Jet (automatic differentiation), after Ceres' own examples.
#pragma once

#include <cmath>

#include "fitters/fit_samples.h"
#include "fitters/parameterization.h"
#include "fitters/reading_nodes.h"

namespace brdf::fitters {

// The model's value f as the loss compares it with LossTarget (fit_samples.h): f, log(1 + f cos
// theta_i), f cos theta_i or sqrt(f cos theta_i + e); and its derivative d/df, for the analytic
// Jacobians.
//
// Why sqrt: a render shows the radiance L = f cos theta_i E, and an image error is an L1 sum of
// |L_fit - L_data| (fitters/image_error.h). At a relative error eps, a sample of radiance L adds
// eps L to that sum; to a least-squares loss it adds eps^2 L^2 on f cos theta_i (the highlight
// outweighs everything), about eps^2 for L >> 1 under log (the highlight counts no more than the
// dim tails) and (sqrt(L + eps L) - sqrt(L))^2 ~ eps^2 L / 4 under sqrt: in proportion to L, as
// in the image. (The Hellinger distance, or the variance-stabilising transform of counts.)
template <typename T>
T LossPrediction(Loss loss, const T& f, double cos_theta_i) {
  using std::log;
  using std::sqrt;
  if (loss == Loss::kLog) return log(T(1) + f * cos_theta_i);
  if (loss == Loss::kCosineL2) return f * cos_theta_i;
  if (loss == Loss::kSqrt || loss == Loss::kImage) return sqrt(f * cos_theta_i + kSqrtLossFloor);
  return f;
}
// LossPrediction in doubles, with its derivative in f in `*derivative`: the square root (or the
// logarithm's argument) taken once for both.
inline double LossPredictionAndDerivative(Loss loss, double f, double cos_theta_i,
                                          double* derivative) {
  if (loss == Loss::kLog) {
    const double argument = 1.0 + f * cos_theta_i;
    *derivative = cos_theta_i / argument;
    return std::log(argument);
  }
  if (loss == Loss::kCosineL2) {
    *derivative = cos_theta_i;
    return f * cos_theta_i;
  }
  if (loss == Loss::kSqrt || loss == Loss::kImage) {
    const double root = std::sqrt(f * cos_theta_i + kSqrtLossFloor);
    *derivative = 0.5 * cos_theta_i / root;
    return root;
  }
  *derivative = 1.0;
  return f;
}

// The residuals of a batch of samples as a function of the fitter's variables x (one parameter
// block, parameterization.h), for automatic differentiation: the reference the analytic
// derivatives of FitObjective (objective.h) are tested against. With `nodes` (of the samples
// from which `samples` is taken, the first being sample `first`), each reading is predicted
// through its quadrature nodes as the objective predicts it.
template <typename ModelType>
class BatchResidual {
 public:
  BatchResidual(bool grey_specular, Loss loss, const FitSample* samples, int count,
                const SampleNodes* nodes = nullptr, size_t first = 0)
      : grey_specular_(grey_specular),
        loss_(loss),
        samples_(samples),
        count_(count),
        nodes_(nodes),
        first_(first) {}

  int num_residuals() const { return 3 * count_; }

  template <typename T>
  bool operator()(const T* x, T* residuals) const {
    T params[ModelType::kNumParams];
    ComputeParams<ModelType, T>(grey_specular_, x, params);
    for (int k = 0; k < count_; ++k) {
      const FitSample& sample = samples_[k];
      // Directions stay plain doubles: only the parameters carry derivatives.
      RgbT<T> f;
      if (nodes_ == nullptr) {
        f = ModelType::template Eval<T>(params, sample.wi, sample.wo);
      } else {
        f = RgbT<T>::Constant(T(0));
        for (size_t n = nodes_->first[first_ + k]; n < nodes_->first[first_ + k + 1]; ++n) {
          const gonio::ReadingNode& node = nodes_->nodes[n];
          f += ModelType::template Eval<T>(params, node.wi, node.wo) * T(node.weight);
        }
      }
      const double cos_theta_i = sample.cos_theta_i();
      const Rgb target = LossTarget(loss_, sample.value, cos_theta_i);
      for (int c = 0; c < 3; ++c) {
        residuals[3 * k + c] =
            (LossPrediction(loss_, f[c], cos_theta_i) - target[c]) * sample.scale[c];
      }
    }
    return true;
  }

 private:
  bool grey_specular_;
  Loss loss_;
  const FitSample* samples_;
  int count_;
  const SampleNodes* nodes_;
  size_t first_;
};

}  // namespace brdf::fitters
