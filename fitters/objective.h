// The one evaluation core of a fit (DESIGN §6): a model's least squares over prepared samples,
// evaluated at a point of the fitter's variables as the cost, the gradient and the sums of the
// normal equations, in one parallel pass over fixed batches.
//
// A sample's residual depends on the variables only through the model's parameters, which are
// the same for every sample, so the chain rule splits:
//   d r / d x = d r / d params * d params / d x.
// The second factor G (parameterization.h, Jets) is computed once per point (At) and handed to
// every batch; the first comes per sample from each term's ValueAndGradient (models/term.h) in
// closed form, from what the term takes of the sample's directions (its Geometry), computed once
// when the objective is made. For r_c = (P(f_c) - t_c) s_c, with P the loss's prediction
// (LossPrediction),
//   d r_c / d params = s_c P'(f_c) d f_c / d params,
// and f_c depends only on the parameters of channel c (an RGB parameter's channel c, and the
// shapes): u_c, one entry per row of the model's parameter table. Each batch adds up u_c u_c^T per
// channel (K x K, K the table's rows) and only then multiplies by G_c, the rows of G for channel
// c's parameters: J^T J = sum_c G_c^T (sum u_c u_c^T) G_c, a few products a row instead of one per
// pair of variables. Nothing is stored per row, and nothing is remembered between calls: the
// solver asks for a point once (solve.h, through ceres::EvaluationCallback).
//
// Through an instrument (reading_nodes.h) a sample's value is a weighted sum over its quadrature
// nodes, f = sum_n w_n f(wi_n, wo_n), and so is d f / d params: the terms' geometry is kept per
// node, and a sample without an instrument is one node (its own directions, weight 1).
//
// The batches are summed in a fixed tree (DeterministicReduce), so the result does not depend on
// the thread count. The autodiff functor of residual.h evaluates the same residuals and is the
// tests' reference for these derivatives.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <vector>

#include "core/deterministic_reduce.h"
#include "fitters/fit_samples.h"
#include "fitters/parameterization.h"
#include "fitters/reading_nodes.h"
#include "fitters/residual.h"

namespace brdf::fitters {

// The sums of the normal equations over the residual rows i at a point: A = sum J_i^T J_i,
// B = sum J_i^T J_i e_i (e_i the squared residual, or its expectation when given), g = J^T r and
// cost = 1/2 |r|^2. A and B are lower triangles until Symmetric() fills them in.
struct NormalSums {
  Eigen::MatrixXd a, b;
  Eigen::VectorXd g;
  double cost = 0;

  void Symmetric() {
    a = a.selfadjointView<Eigen::Lower>();
    b = b.selfadjointView<Eigen::Lower>();
  }
};

template <typename M>
class FitObjective {
 public:
  // Entries of a channel's d f / d params: one per row of M's parameter table.
  static constexpr int kRows = M::kGradientSize;
  // Samples per batch of the sums: a batch's rows stay in the core's cache.
  static constexpr int kDefaultBatch = 256;

  // The least squares over `samples` (which must outlive this object) under `loss`, each
  // sample's reading predicted through its `nodes` (InstrumentNodes of these samples; null: at
  // its nominal directions). `nodes` must outlive this object too.
  FitObjective(const std::vector<FitSample>& samples, Loss loss, bool grey_specular,
               int batch_size = kDefaultBatch, const SampleNodes* nodes = nullptr)
      : samples_(samples),
        loss_(loss),
        grey_specular_(grey_specular),
        batch_(std::max(batch_size, 1)),
        n_(VariableLayout<M>::Count(grey_specular)),
        nodes_(nodes),
        geometry_(nodes != nullptr ? nodes->nodes.size() : samples.size()),
        above_(geometry_.size()) {
    // What each term takes of a node's directions, once (models/term.h: GeometryOf).
    DeterministicReduce(
        static_cast<int64_t>(geometry_.size()), 4096, 0,
        [&](int64_t begin, int64_t end, int) {
          for (int64_t n = begin; n < end; ++n) {
            const Vec3& wi = nodes != nullptr ? nodes->nodes[n].wi : samples[n].wi;
            const Vec3& wo = nodes != nullptr ? nodes->nodes[n].wo : samples[n].wo;
            above_[n] = models::AboveHorizon(wi, wo);
            M::ForEachTerm([&](auto term, auto index) {
              std::get<decltype(index)::value>(geometry_[n]) = decltype(term)::GeometryOf(wi, wo);
            });
          }
          return 0;
        },
        [](int, int) { return 0; });
    const std::vector<ParamInfo> table = M::Params();
    for (int c = 0; c < 3; ++c) {
      for (int row = 0; row < kRows; ++row) {
        const ParamInfo& param = table[row];
        channel_slots_[c][row] = param.slot + (param.channels == 3 ? c : 0);
      }
    }
  }

  int NumVariables() const { return n_; }
  bool grey_specular() const { return grey_specular_; }
  Loss loss() const { return loss_; }
  const std::vector<FitSample>& samples() const { return samples_; }
  const SampleNodes* nodes() const { return nodes_; }

  // The parameters at a point and d params / d x there (row-major, kNumParams x n).
  struct Point {
    std::array<double, M::kNumParams> params{};
    std::vector<double> gradients;
  };
  Point At(const double* x) const {
    Point at;
    at.gradients.assign(static_cast<size_t>(M::kNumParams) * n_, 0.0);
    ParamsAndGradients<M>(grey_specular_, x, at.params.data(), at.gradients.data());
    return at;
  }

  // The squared residual norm (over the channels) of every sample at `at`.
  std::vector<double> SquaredResiduals(const Point& at) const {
    std::vector<double> squared(samples_.size());
    DeterministicReduce(
        static_cast<int64_t>(samples_.size()), 4096, 0,
        [&](int64_t begin, int64_t end, int) {
          const Prepared prepared = Prepare(at);
          for (int64_t k = begin; k < end; ++k) {
            double r[3];
            Residuals(at, prepared, k, r);
            squared[k] = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
          }
          return 0;
        },
        [](int, int) { return 0; });
    return squared;
  }

  // The normal-equation sums at `at`; e_i of B is the squared residual, or expected_squared[i]
  // (one per row: sample k's channel c is row 3 k + c) when given.
  NormalSums Sums(const Point& at, const std::vector<double>* expected_squared = nullptr) const {
    const NormalSums zero{Eigen::MatrixXd::Zero(n_, n_), Eigen::MatrixXd::Zero(n_, n_),
                          Eigen::VectorXd::Zero(n_), 0.0};
    return DeterministicReduce(
        BatchCount(), kBatchesPerChunk, zero,
        [&](int64_t begin, int64_t end, NormalSums partial) {
          for (int64_t b = begin; b < end; ++b) {
            const size_t first = static_cast<size_t>(b) * batch_;
            AddBatch(at, first, BatchSize(b),
                     expected_squared != nullptr ? expected_squared->data() + 3 * first : nullptr,
                     &partial);
          }
          return partial;
        },
        [](NormalSums x, const NormalSums& y) {
          x.a += y.a;
          x.b += y.b;
          x.g += y.g;
          x.cost += y.cost;
          return x;
        });
  }

  // What every sample's evaluation of each term shares at a point (models/term.h: Prepare).
  using Prepared = typename M::Prepared;
  static Prepared Prepare(const Point& at) {
    Prepared prepared;
    M::ForEachTerm([&](auto term, auto index) {
      std::get<decltype(index)::value>(prepared) =
          decltype(term)::Prepare(at.params.data() + M::kOffsets[index]);
    });
    return prepared;
  }

  // The model's prediction f of sample k's reading, from the terms' values at `at`.
  Rgb Value(const Point& at, const Prepared& prepared, size_t k) const {
    Rgb f = Rgb::Zero();
    for (size_t n = NodeBegin(k); n < NodeEnd(k); ++n) {
      if (!above_[n]) continue;
      Rgb node_f = Rgb::Zero();
      M::ForEachTerm([&](auto term, auto index) {
        constexpr int kIndex = decltype(index)::value;
        node_f += decltype(term)::Value(at.params.data() + M::kOffsets[index],
                                        std::get<kIndex>(prepared), std::get<kIndex>(geometry_[n]));
      });
      f += NodeWeight(n) * node_f;
    }
    return f;
  }

  // Calls visit(row, jacobian_row, residual) for every residual row at `at`, in order (sample
  // k's channel c is row 3 k + c); jacobian_row holds n values.
  template <typename Visit>
  void ForEachRow(const Point& at, Visit&& visit) const {
    Eigen::VectorXd row(n_);
    const Prepared prepared = Prepare(at);
    for (size_t k = 0; k < samples_.size(); ++k) {
      VisitSample(at, prepared, k, [&](int c, double residual, const double* u) {
        for (int i = 0; i < n_; ++i) {
          double sum = 0;
          for (int p = 0; p < kRows; ++p) sum += u[p] * G(at, c, p)[i];
          row[i] = sum;
        }
        visit(static_cast<int64_t>(3 * k + c), row, residual);
      });
    }
  }

 private:
  static constexpr int64_t kBatchesPerChunk = 16;
  static constexpr int kMaxStackBatch = 1024;
  static constexpr int kTriangle = kRows * (kRows + 1) / 2;

  int64_t BatchCount() const {
    return static_cast<int64_t>((samples_.size() + batch_ - 1) / batch_);
  }
  int BatchSize(int64_t b) const {
    return static_cast<int>(
        std::min<size_t>(batch_, samples_.size() - static_cast<size_t>(b) * batch_));
  }
  // Sample k's nodes: geometry_[NodeBegin(k), NodeEnd(k)).
  size_t NodeBegin(size_t k) const { return nodes_ != nullptr ? nodes_->first[k] : k; }
  size_t NodeEnd(size_t k) const { return nodes_ != nullptr ? nodes_->first[k + 1] : k + 1; }
  double NodeWeight(size_t n) const { return nodes_ != nullptr ? nodes_->nodes[n].weight : 1.0; }

  // The row of G for channel c's parameter `p` (of the table's rows).
  const double* G(const Point& at, int c, int p) const {
    return at.gradients.data() + static_cast<size_t>(channel_slots_[c][p]) * n_;
  }

  // The residual of each channel of sample k at `at`, from the terms' values.
  void Residuals(const Point& at, const Prepared& prepared, size_t k, double* r) const {
    const FitSample& sample = samples_[k];
    const Rgb f = Value(at, prepared, k);
    const double cos_theta_i = sample.cos_theta_i();
    const Rgb target = LossTarget(loss_, sample.value, cos_theta_i);
    for (int c = 0; c < 3; ++c) {
      r[c] = (LossPrediction(loss_, f[c], cos_theta_i) - target[c]) * sample.scale[c];
    }
  }

  // Calls visit(c, residual, u) for each channel of `sample`, u = d residual / d (the table's
  // parameters of channel c).
  template <typename Visit>
  void VisitSample(const Point& at, const Prepared& prepared, size_t sample_index,
                   Visit&& visit) const {
    const FitSample& sample = samples_[sample_index];
    Rgb f = Rgb::Zero();
    double df[3][kRows] = {};
    bool above = false;
    for (size_t n = NodeBegin(sample_index); n < NodeEnd(sample_index); ++n) {
      if (!above_[n]) continue;
      above = true;
      const double weight = NodeWeight(n);
      int column = 0;
      M::ForEachTerm([&](auto term, auto index) {
        using Term = decltype(term);
        const double* p = at.params.data() + M::kOffsets[index];
        Rgb term_f;
        double term_gradient[3][Term::kGradientSize];
        constexpr int kIndex = decltype(index)::value;
        Term::ValueAndGradient(p, std::get<kIndex>(prepared), std::get<kIndex>(geometry_[n]),
                               &term_f, term_gradient);
        f += weight * term_f;
        for (int c = 0; c < 3; ++c) {
          for (int k = 0; k < Term::kGradientSize; ++k) {
            df[c][column + k] += weight * term_gradient[c][k];
          }
        }
        column += Term::kGradientSize;
      });
    }
    const double cos_theta_i = sample.cos_theta_i();
    const Rgb target = LossTarget(loss_, sample.value, cos_theta_i);
    for (int c = 0; c < 3; ++c) {
      double derivative;
      const double prediction = LossPredictionAndDerivative(loss_, f[c], cos_theta_i, &derivative);
      const double residual = (prediction - target[c]) * sample.scale[c];
      const double dr_df = above ? sample.scale[c] * derivative : 0.0;
      double u[kRows];
      for (int p = 0; p < kRows; ++p) u[p] = dr_df * df[c][p];
      visit(c, residual, u);
    }
  }

  // A batch's terms of the normal equations, added to `sums` (see the header).
  void AddBatch(const Point& at, size_t first, int count, const double* expected,
                NormalSums* sums) const {
    double moments[3][kTriangle] = {}, weighted[3][kTriangle] = {}, gradient[3][kRows] = {};
    double residuals[3 * kMaxStackBatch];
    const bool whole_batch = count <= kMaxStackBatch;
    if (whole_batch) std::fill_n(residuals, 3 * count, 0.0);  // every row is written below
    double half_squared = 0;
    const Prepared prepared = Prepare(at);
    for (int k = 0; k < count; ++k) {
      VisitSample(at, prepared, first + k, [&](int c, double residual, const double* u) {
        const int row = 3 * k + c;
        const double e = expected != nullptr ? expected[row] : residual * residual;
        int slot = 0;
        for (int p = 0; p < kRows; ++p) {
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
    }
    sums->cost += whole_batch
                      ? 0.5 * Eigen::Map<const Eigen::VectorXd>(residuals, 3 * count).squaredNorm()
                      : half_squared;
    for (int c = 0; c < 3; ++c) {
      const double* rows[kRows];
      for (int p = 0; p < kRows; ++p) rows[p] = G(at, c, p);
      double m[kRows][kRows], w[kRows][kRows];
      int slot = 0;
      for (int p = 0; p < kRows; ++p) {
        for (int q = 0; q <= p; ++q, ++slot) {
          m[p][q] = m[q][p] = moments[c][slot];
          w[p][q] = w[q][p] = weighted[c][slot];
        }
      }
      for (int i = 0; i < n_; ++i) {
        for (int p = 0; p < kRows; ++p) sums->g[i] += rows[p][i] * gradient[c][p];
        for (int j = 0; j <= i; ++j) {
          double sum_a = 0, sum_b = 0;
          for (int p = 0; p < kRows; ++p) {
            for (int q = 0; q < kRows; ++q) {
              const double gg = rows[p][i] * rows[q][j];
              sum_a += gg * m[p][q];
              sum_b += gg * w[p][q];
            }
          }
          sums->a(i, j) += sum_a;
          sums->b(i, j) += sum_b;
        }
      }
    }
  }

  const std::vector<FitSample>& samples_;
  Loss loss_;
  bool grey_specular_;
  size_t batch_;
  int n_;
  const SampleNodes* nodes_;
  std::vector<typename M::Geometry> geometry_;  // one per node
  std::vector<char> above_;                     // per node: both directions above the horizon
  int channel_slots_[3][kRows];
};

}  // namespace brdf::fitters
