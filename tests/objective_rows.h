// A fit objective seen by Ceres' test tools: its closed-form rows as a CostFunction (for
// ceres::GradientChecker), and the templated residual with its one parameter block (for
// ceres::DynamicAutoDiffCostFunction, the automatic-differentiation reference). Shared by the
// tests that check the objective's Jacobian of every model, composition and new term.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <cstdint>

#include "fitters/objective.h"
#include "fitters/residual.h"

namespace brdf::testing {

template <typename M>
class ObjectiveRows : public ceres::CostFunction {
 public:
  explicit ObjectiveRows(const fitters::FitObjective<M>& objective) : objective_(objective) {
    mutable_parameter_block_sizes()->push_back(objective.NumVariables());
    set_num_residuals(3 * static_cast<int>(objective.samples().size()));
  }
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    const int n = objective_.NumVariables();
    objective_.ForEachRow(objective_.At(x[0]),
                          [&](int64_t row, const Eigen::VectorXd& jacobian, double residual) {
                            residuals[row] = residual;
                            if (jacobians != nullptr && jacobians[0] != nullptr) {
                              for (int k = 0; k < n; ++k) jacobians[0][row * n + k] = jacobian[k];
                            }
                          });
    return true;
  }

 private:
  const fitters::FitObjective<M>& objective_;
};

template <typename M>
struct DynamicBatchResidual {
  fitters::BatchResidual<M> residual;
  template <typename T>
  bool operator()(T const* const* x, T* residuals) const {
    return residual(x[0], residuals);
  }
};

}  // namespace brdf::testing
