// A lobed model's residual batch with a hand-written Jacobian: the cost function a fit of phong,
// blinn-phong, blinn-phong-exact, ggx or beckmann hands Ceres instead of automatic
// differentiation of BatchResidual (residual.h), whose residuals it reproduces bit for bit
// (those Ceres evaluated with derivatives, through Jets, and those without, in doubles).
//
// With Jets every sample carries seven derivatives through the whole model. But a sample's
// value depends on the variables only through the parameters, and the parameters
// (parameterization.h) are the same for every sample of a batch, so the chain rule splits:
//   d r / d v = d r / d params * d params / d v,
// the second factor G once per batch (Jets over VariablesToParams: ParamsAndGradients), the
// first in closed form per sample. For r_c = (P(f_c) - t_c) s_c, with P the loss's prediction
// (LossPrediction), both families are f_c = rho_d_c / pi + (lobe of channel c), so
// d f_c / d rho_d_c = 1 / pi, and:
//   power cosine (EvalPowerCosine): lobe = rho_s_c L, L = N(m) c^m,
//     d f_c / d rho_s_c = L,   d f_c / d m = rho_s_c (N'(m) c^m + L ln c)
//     (c > 0; L = 0 and so its derivative for c <= 0), since d c^m / d m = c^m ln c; N'(m) is
//     per batch (one Jet);
//   microfacet (MicrofacetModel::Eval): lobe = F_c S(alpha), Schlick's F_c = f0_c + (1 - f0_c) w,
//     w = (1 - cos theta_d)^5, S = D G2 / (4 cos theta_i cos theta_o),
//     d f_c / d f0_c = (1 - w) S,   d f_c / d alpha = F_c S'(alpha),
//     S' by a one-variable Jet per sample (Λ and D keep their one definition).
// Below the horizon f = 0 and every derivative vanishes. tests/fit_test.cpp checks the Jacobian
// against automatic differentiation of BatchResidual and against ceres::GradientChecker.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/jet.h>

#include <cmath>

#include "fitters/fit_samples.h"
#include "fitters/parameterization.h"
#include "fitters/residual.h"
#include "models/microfacet.h"

namespace brdf::fitters {

template <typename ModelType>
class AnalyticBatchCost : public ceres::CostFunction {
  static constexpr bool kMicrofacet = ModelType::kFamily == models::ModelFamily::kMicrofacet;
  static_assert(kHasLobe<ModelType>);
  // Both families: rho_d, then the lobe's per-channel slot (rho_s or f0), then its shape.
  static constexpr int kRhoD = ModelType::kRhoD;
  static constexpr int kLobeSlot = 3;
  static constexpr int kShape = ModelType::kShape;
  using Jet1 = ceres::Jet<double, 1>;

 public:
  AnalyticBatchCost(bool grey_specular, Loss loss, const FitSample* samples, int count)
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
    if (jacobians == nullptr) {
      return residual_(parameters[0], parameters[1], parameters[2], residuals);
    }
    const int s_size = SpecularSize();
    constexpr int kMaxVariables = FitVariables::kMaxVariables;
    const int variables = 3 + s_size + 1;
    double params[ModelType::kNumParams];
    double gradients[ModelType::kNumParams * kMaxVariables];
    ParamsAndGradients<ModelType>(grey_specular_, parameters[0], parameters[1], parameters[2],
                                  params, gradients);
    const double shape = params[kShape];
    // Power cosine: N(m) and N'(m); N as the Jets had it (a Jet divides by multiplying with
    // the inverse).
    Jet1 normalization(0.0);
    if constexpr (!kMicrofacet) normalization = ModelType::LobeNormalization(Jet1(shape, 0));
    const double* const g_shape = gradients + kShape * variables;
    for (int k = 0; k < count_; ++k) {
      const FitSample& sample = samples_[k];
      // f and its derivatives by the channel's lobe slot and by the shape; zero below the horizon.
      Rgb f = Rgb::Zero(), df_dlobe = Rgb::Zero(), df_dshape = Rgb::Zero();
      const bool above = models::AboveHorizon(sample.wi, sample.wo);
      if (!above) {
        // f and its derivatives stay zero.
      } else if constexpr (kMicrofacet) {
        const auto angles = ModelType::Angles(sample.wi, sample.wo);
        const Jet1 specular = ModelType::Specular(angles, Jet1(shape, 0));
        const double w = models::SchlickFresnel(angles.cos_theta_d, 0.0);
        for (int c = 0; c < 3; ++c) {
          const double fresnel = models::SchlickFresnel(angles.cos_theta_d, params[kLobeSlot + c]);
          f[c] = params[kRhoD + c] * kInvPi + fresnel * specular.a;
          df_dlobe[c] = (1.0 - w) * specular.a;
          df_dshape[c] = fresnel * specular.v[0];
        }
      } else {
        const double cosine = ModelType::LobeCosine(sample.wi, sample.wo);
        const double power = models::ClampedPow(cosine, shape);
        const double lobe = normalization.a * power;
        const double lobe_slope =
            cosine > 0 ? normalization.v[0] * power + lobe * std::log(cosine) : 0.0;
        f = models::PowerCosineValue(params, lobe);
        df_dlobe.setConstant(lobe);
        for (int c = 0; c < 3; ++c) df_dshape[c] = params[kLobeSlot + c] * lobe_slope;
      }
      const double cos_theta_i = sample.cos_theta_i();
      const Rgb target = LossTarget(loss_, sample.value, cos_theta_i);
      for (int c = 0; c < 3; ++c) {
        const int row = 3 * k + c;
        residuals[row] = (LossPrediction(loss_, f[c], cos_theta_i) - target[c]) * sample.scale[c];
        const double dr_df =
            above ? sample.scale[c] * LossPredictionDerivative(loss_, f[c], cos_theta_i) : 0.0;
        const double dr_drho_d = dr_df * kInvPi;
        const double dr_dlobe = dr_df * df_dlobe[c];
        const double dr_dshape = dr_df * df_dshape[c];
        const double* const g_rho_d = gradients + (kRhoD + c) * variables;
        const double* const g_lobe = gradients + (kLobeSlot + c) * variables;
        double row_gradient[kMaxVariables];
        for (int j = 0; j < variables; ++j) {
          row_gradient[j] = dr_drho_d * g_rho_d[j] + dr_dlobe * g_lobe[j] + dr_dshape * g_shape[j];
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
