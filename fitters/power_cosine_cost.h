// The power-cosine models' residual batch with a hand-written Jacobian: the cost function a fit
// of phong, blinn-phong or blinn-phong-exact hands Ceres instead of automatic differentiation of
// BatchResidual (residual.h), whose residuals it reproduces bit for bit (those Ceres evaluated
// with derivatives, through Jets, and those without, in doubles).
//
// With Jets every sample carries seven derivatives through the whole model. But a sample's
// value depends on the variables only through the parameters, and the parameters
// (parameterization.h) are the same for every sample of a batch, so the chain rule splits:
//   d r / d v = d r / d params * d params / d v,
// the second factor G once per batch (Jets over VariablesToParams: ParamsAndGradients), the
// first in closed form per sample. For r_c = (P(f_c) - t_c) s_c, with P the loss's prediction
// (LossPrediction), f_c = rho_d_c / pi + rho_s_c L and L = N(m) c^m (EvalPowerCosine):
//   d f_c / d rho_d_c = 1 / pi,   d f_c / d rho_s_c = L,
//   d f_c / d m = rho_s_c (N'(m) c^m + L ln c)   (c > 0; L = 0 and so its derivative for c <= 0),
// since d c^m / d m = c^m ln c. N'(m) is per batch as well (one Jet). Below the horizon f = 0
// and every derivative vanishes. tests/fit_test.cpp checks the Jacobian against
// ceres::GradientChecker and against automatic differentiation of BatchResidual.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/jet.h>

#include <cmath>

#include "fitters/fit_samples.h"
#include "fitters/parameterization.h"
#include "fitters/residual.h"

namespace brdf::fitters {

template <typename ModelType>
class PowerCosineBatchCost : public ceres::CostFunction {
  static_assert(ModelType::kFamily == models::ModelFamily::kPowerCosine);
  using Slots = models::LobedSlots;

 public:
  PowerCosineBatchCost(bool grey_specular, Loss loss, const FitSample* samples, int count)
      : residual_(grey_specular, loss, samples, count),
        grey_specular_(grey_specular),
        loss_(loss),
        samples_(samples),
        count_(count) {
    *mutable_parameter_block_sizes() = {3, SpecularSize(), 1};
    set_num_residuals(3 * count);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (jacobians == nullptr)
      return residual_(parameters[0], parameters[1], parameters[2], residuals);
    const int s_size = SpecularSize();
    constexpr int kMaxVariables = FitVariables::kMaxVariables;
    const int variables = 3 + s_size + 1;
    double params[Slots::kNumParams];
    double gradients[Slots::kNumParams * kMaxVariables];
    ParamsAndGradients<ModelType>(grey_specular_, parameters[0], parameters[1], parameters[2],
                                  params, gradients);
    const double m = params[Slots::kExponent];
    // N(m) and N'(m); N as the Jets had it (a Jet divides by multiplying with the inverse).
    const ceres::Jet<double, 1> normalization_jet =
        ModelType::LobeNormalization(ceres::Jet<double, 1>(m, 0));
    const double normalization = normalization_jet.a;
    const double normalization_slope = normalization_jet.v[0];
    const double* const g_m = gradients + Slots::kExponent * variables;
    for (int k = 0; k < count_; ++k) {
      const FitSample& sample = samples_[k];
      const bool above = models::AboveHorizon(sample.wi, sample.wo);
      double lobe = 0, lobe_slope = 0;  // L and dL/dm
      if (above) {
        const double cosine = ModelType::LobeCosine(sample.wi, sample.wo);
        const double power = models::ClampedPow(cosine, m);
        lobe = normalization * power;
        if (cosine > 0) lobe_slope = normalization_slope * power + lobe * std::log(cosine);
      }
      const Rgb f = above ? models::PowerCosineValue(params, lobe) : Rgb::Zero().eval();
      const double cos_theta_i = sample.cos_theta_i();
      const Rgb target = LossTarget(loss_, sample.value, cos_theta_i);
      for (int c = 0; c < 3; ++c) {
        const int row = 3 * k + c;
        residuals[row] = (LossPrediction(loss_, f[c], cos_theta_i) - target[c]) * sample.scale[c];
        // d r / d f_c times d f_c / d (rho_d_c, rho_s_c, m); zero below the horizon.
        const double dr_df =
            above ? sample.scale[c] * LossPredictionDerivative(loss_, f[c], cos_theta_i) : 0.0;
        const double dr_drho_d = dr_df * kInvPi;
        const double dr_drho_s = dr_df * lobe;
        const double dr_dm = dr_df * params[Slots::kRhoS + c] * lobe_slope;
        const double* const g_rho_d = gradients + (Slots::kRhoD + c) * variables;
        const double* const g_rho_s = gradients + (Slots::kRhoS + c) * variables;
        double row_gradient[kMaxVariables];
        for (int j = 0; j < variables; ++j) {
          row_gradient[j] = dr_drho_d * g_rho_d[j] + dr_drho_s * g_rho_s[j] + dr_dm * g_m[j];
        }
        if (jacobians[0] != nullptr) {
          for (int j = 0; j < 3; ++j) jacobians[0][3 * row + j] = row_gradient[j];
        }
        if (jacobians[1] != nullptr) {
          for (int j = 0; j < s_size; ++j) jacobians[1][s_size * row + j] = row_gradient[3 + j];
        }
        if (jacobians[2] != nullptr) jacobians[2][row] = row_gradient[3 + s_size];
      }
    }
    return true;
  }

 private:
  int SpecularSize() const { return grey_specular_ ? 1 : 3; }

  BatchResidual<ModelType> residual_;  // the residuals alone, evaluated in doubles
  bool grey_specular_;
  Loss loss_;
  const FitSample* samples_;
  int count_;
};

}  // namespace brdf::fitters
