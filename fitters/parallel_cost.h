// A Ceres cost function over many samples whose evaluation is parallel and yet bit-for-bit
// independent of the thread count. Ceres' own multi-threaded evaluation adds each residual
// block's cost and gradient into per-thread sums and adds those up at the end, so which thread
// took which block changes the last bits of every iterate (about 1e-11 relative in the fitted
// parameters between 1 and 2 threads). Here Ceres runs on one thread and this function
// evaluates its batches (BatchResidual, residual.h) in parallel, each batch writing only its own
// rows of residuals and Jacobian: nothing is summed across threads, and Ceres' sums over rows run
// in a fixed order.
#pragma once

#include <ceres/cost_function.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <memory>
#include <vector>

namespace brdf::fitters {

class ParallelBatchCost : public ceres::CostFunction {
 public:
  // `batches` share the parameter blocks `parameter_block_sizes`; their residuals are stacked
  // in order.
  ParallelBatchCost(std::vector<std::unique_ptr<ceres::CostFunction>> batches,
                    const std::vector<int32_t>& parameter_block_sizes)
      : batches_(std::move(batches)) {
    *mutable_parameter_block_sizes() = parameter_block_sizes;
    int rows = 0;
    for (const auto& batch : batches_) {
      first_rows_.push_back(rows);
      rows += batch->num_residuals();
    }
    set_num_residuals(rows);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const std::vector<int32_t>& sizes = parameter_block_sizes();
    std::atomic<bool> ok{true};
    tbb::parallel_for(size_t{0}, batches_.size(), [&](size_t b) {
      // Ceres' Jacobians are row-major (residuals x block size): a batch's rows are contiguous.
      std::vector<double*> batch_jacobians(sizes.size(), nullptr);
      if (jacobians != nullptr) {
        for (size_t k = 0; k < sizes.size(); ++k) {
          if (jacobians[k] != nullptr) {
            batch_jacobians[k] = jacobians[k] + static_cast<size_t>(first_rows_[b]) * sizes[k];
          }
        }
      }
      if (!batches_[b]->Evaluate(parameters, residuals + first_rows_[b],
                                 jacobians != nullptr ? batch_jacobians.data() : nullptr)) {
        ok = false;
      }
    });
    return ok;
  }

  // The batches, for sums that visit them one at a time (ReduceOverBatches, covariance.h): a
  // batch's residuals and Jacobian are a few tens of kB, a whole block's tens of MB.
  size_t batch_count() const { return batches_.size(); }
  const ceres::CostFunction& batch(size_t b) const { return *batches_[b]; }
  // The batch's first row among this function's residuals.
  int first_row(size_t b) const { return first_rows_[b]; }

 private:
  std::vector<std::unique_ptr<ceres::CostFunction>> batches_;
  std::vector<int> first_rows_;
};

}  // namespace brdf::fitters
