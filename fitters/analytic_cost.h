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

#include <Eigen/Core>
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
    const ChainRule chain = Chain(parameters);
    VisitRows(chain, [&](int row, double residual, const double* dr_dparams) {
      residuals[row] = residual;
      const int c = row % 3;
      double row_gradient[FitVariables::kMaxVariables];
      for (int j = 0; j < chain.variables; ++j) {
        row_gradient[j] = dr_dparams[0] * chain.g_rho_d[c][j] + dr_dparams[1] * chain.g_lobe[c][j] +
                          dr_dparams[2] * chain.g_shape[j];
      }
      if (jacobians[0] != nullptr) {
        for (int j = 0; j < 3; ++j) jacobians[0][3 * row + j] = row_gradient[j];
      }
      if (jacobians[1] != nullptr) {
        for (int j = 0; j < s_size; ++j) jacobians[1][s_size * row + j] = row_gradient[3 + j];
      }
      if (jacobians[2] != nullptr) jacobians[2][row] = row_gradient[3 + s_size];
    });
    return true;
  }

  // The batch's terms of the normal equations at `parameters`, added to the lower triangles of
  // a = J^T J and b = J^T diag(e) J (e the squared residual, or `expected_squared[row]` when
  // given), to g = J^T r, and 1/2 |r|^2 to cost, without forming J. Each row is
  // J_row = u^T G_c, u = d r / d (rho_d_c, lobe_c, shape), G_c the rows of d params / d
  // variables for channel c (the same for the whole batch), so J^T J = sum_c G_c^T (sum u u^T)
  // G_c: six products a row instead of one per pair of variables.
  void AddNormalSums(double const* const* parameters, const double* expected_squared,
                     Eigen::MatrixXd* a, Eigen::MatrixXd* b, Eigen::VectorXd* g,
                     double* cost) const {
    const ChainRule chain = Chain(parameters);
    double moments[3][6] = {}, weighted[3][6] = {}, gradient[3][3] = {};
    double residuals[3 * kMaxBatch];
    const bool whole_batch = count_ <= kMaxBatch;
    double half_squared = 0;
    VisitRows(chain, [&](int row, double residual, const double* u) {
      const int c = row % 3;
      const double e = expected_squared != nullptr ? expected_squared[row] : residual * residual;
      int slot = 0;
      for (int p = 0; p < 3; ++p) {
        for (int q = 0; q <= p; ++q, ++slot) {
          const double product = u[p] * u[q];
          moments[c][slot] += product;
          weighted[c][slot] += e * product;
        }
        gradient[c][p] += residual * u[p];
      }
      if (whole_batch) {
        residuals[row] = residual;
      } else {
        half_squared += 0.5 * residual * residual;
      }
    });
    // The cost as HalfSquaredSum (covariance.h) adds it up from a batch's residuals.
    *cost += whole_batch
                 ? 0.5 * Eigen::Map<const Eigen::VectorXd>(residuals, 3 * count_).squaredNorm()
                 : half_squared;
    const int n = chain.variables;
    for (int c = 0; c < 3; ++c) {
      const double* rows[3] = {chain.g_rho_d[c], chain.g_lobe[c], chain.g_shape};
      int slot = 0;
      double m[3][3], w[3][3];
      for (int p = 0; p < 3; ++p) {
        for (int q = 0; q <= p; ++q, ++slot) {
          m[p][q] = m[q][p] = moments[c][slot];
          w[p][q] = w[q][p] = weighted[c][slot];
        }
      }
      for (int i = 0; i < n; ++i) {
        for (int p = 0; p < 3; ++p) (*g)[i] += rows[p][i] * gradient[c][p];
        for (int j = 0; j <= i; ++j) {
          double sum_a = 0, sum_b = 0;
          for (int p = 0; p < 3; ++p) {
            for (int q = 0; q < 3; ++q) {
              const double gg = rows[p][i] * rows[q][j];
              sum_a += gg * m[p][q];
              sum_b += gg * w[p][q];
            }
          }
          (*a)(i, j) += sum_a;
          (*b)(i, j) += sum_b;
        }
      }
    }
  }

 private:
  int SpecularSize() const { return grey_specular_ ? 1 : 3; }

  // Batches up to this size keep their residuals on the stack for the cost (AddNormalSums).
  static constexpr int kMaxBatch = 1024;

  // The batch's parameters and d params / d variables (ParamsAndGradients), the rows of the
  // latter each channel's residuals depend on, and the lobe's normalization.
  struct ChainRule {
    double params[ModelType::kNumParams];
    double gradients[ModelType::kNumParams * FitVariables::kMaxVariables];
    int variables = 0;
    const double* g_rho_d[3];
    const double* g_lobe[3];
    const double* g_shape;
    Jet1 normalization{0.0};
  };
  ChainRule Chain(double const* const* parameters) const {
    ChainRule chain;
    chain.variables = 3 + SpecularSize() + 1;
    ParamsAndGradients<ModelType>(grey_specular_, parameters[0], parameters[1], parameters[2],
                                  chain.params, chain.gradients);
    for (int c = 0; c < 3; ++c) {
      chain.g_rho_d[c] = chain.gradients + (kRhoD + c) * chain.variables;
      chain.g_lobe[c] = chain.gradients + (kLobeSlot + c) * chain.variables;
    }
    chain.g_shape = chain.gradients + kShape * chain.variables;
    // Power cosine: N(m) and N'(m); N as the Jets had it (a Jet divides by multiplying with
    // the inverse).
    if constexpr (!kMicrofacet) {
      chain.normalization = ModelType::LobeNormalization(Jet1(chain.params[kShape], 0));
    }
    return chain;
  }

  // Calls visit(row, residual, u) for each residual row of the batch, with u = d residual /
  // d (rho_d_c, lobe slot c, shape) for the row's channel c.
  template <typename Visit>
  void VisitRows(const ChainRule& chain, Visit&& visit) const {
    const double* params = chain.params;
    const double shape = params[kShape];
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
        const double lobe = chain.normalization.a * power;
        const double lobe_slope =
            cosine > 0 ? chain.normalization.v[0] * power + lobe * std::log(cosine) : 0.0;
        f = models::PowerCosineValue(params, lobe);
        df_dlobe.setConstant(lobe);
        for (int c = 0; c < 3; ++c) df_dshape[c] = params[kLobeSlot + c] * lobe_slope;
      }
      const double cos_theta_i = sample.cos_theta_i();
      const Rgb target = LossTarget(loss_, sample.value, cos_theta_i);
      for (int c = 0; c < 3; ++c) {
        const double residual =
            (LossPrediction(loss_, f[c], cos_theta_i) - target[c]) * sample.scale[c];
        const double dr_df =
            above ? sample.scale[c] * LossPredictionDerivative(loss_, f[c], cos_theta_i) : 0.0;
        const double u[3] = {dr_df * kInvPi, dr_df * df_dlobe[c], dr_df * df_dshape[c]};
        visit(3 * k + c, residual, u);
      }
    }
  }

  BatchResidual<ModelType> residual_;  // the residuals alone, evaluated in doubles
  bool grey_specular_;
  Loss loss_;
  const FitSample* samples_;
  int count_;
};

}  // namespace brdf::fitters
