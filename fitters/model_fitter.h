// The pieces of one model's fit that depend on the model's type: its variables and their box,
// the data-driven starts of the multi-start, and the per-sample reweighting of a robust loss.
// fit.cpp runs them in order (multi-start, refine, polish) through the solver of solve.h;
// covariance.h turns the result into standard errors. The model is a composition
// (models/composition.h): every term answers for its own variables, starts and guess.
#pragma once

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "fitters/fit.h"
#include "fitters/objective.h"
#include "fitters/parameterization.h"

namespace brdf::fitters {

// One start of the multi-start: each lobe's start (its width and whether its per-channel
// parameter is read from the data's peak), and where in the values' ranks the diffuse floor is
// read (a lobed model's value is never below rho_d / pi).
struct FitStart {
  std::vector<models::TermStart> lobes;
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
  static constexpr bool kLobed = ModelType::kLobes > 0;

  explicit ModelFitter(const FitOptions& options) : options_(options) {
    VariableLayout<ModelType>::Bounds(options.grey_specular, &lower_, &upper_);
  }

  int FreeVariables() const { return VariableLayout<ModelType>::Count(options_.grey_specular); }
  const std::vector<double>& lower() const { return lower_; }
  const std::vector<double>& upper() const { return upper_; }

  std::vector<double> Params(const std::vector<double>& x) const {
    std::vector<double> params(ModelType::kNumParams);
    ComputeParams<ModelType, double>(options_.grey_specular, x.data(), params.data());
    return params;
  }

  // The multi-start's starts: every combination of the lobes' own starts (models/term.h:
  // Starts), one start without a lobe; for a lobe measured on a `designed` schedule, every start
  // again with the floor read from the lowest values.
  std::vector<FitStart> Starts(bool designed) const {
    const models::StartShapes shapes{options_.start_exponents, options_.start_alphas};
    std::vector<FitStart> starts(1);
    ModelType::ForEachLobe([&](auto lobe, auto) {
      std::vector<FitStart> combined;
      for (const FitStart& start : starts) {
        for (const models::TermStart& term_start : decltype(lobe)::Starts(shapes)) {
          combined.push_back(start);
          combined.back().lobes.push_back(term_start);
        }
      }
      starts = std::move(combined);
    });
    if (kLobed && designed) {
      const size_t count = starts.size();
      for (size_t k = 0; k < count; ++k) {
        starts.push_back(starts[k]);
        starts.back().floor_rank = kLowFloorRank;
      }
    }
    return starts;
  }

  // Data-driven start: rho_d from the diffuse floor, each lobe from the peak's height above it,
  // all inside the energy budget.
  std::vector<double> InitialGuess(const std::vector<FitSample>& samples,
                                   const FitStart& start) const {
    models::PeakSample peak;
    // The brightest sample in radiance, f cos theta_i (by its largest channel): where the lobe
    // is seen. By f alone, a table's brightest sample is often at grazing incidence, where
    // Fresnel lifts a broad tail above the highlight.
    size_t peak_index = 0;
    const auto radiance = [&](size_t k) {
      return samples[k].value.maxCoeff() * samples[k].cos_theta_i();
    };
    for (size_t k = 1; k < samples.size(); ++k) {
      if (radiance(k) > radiance(peak_index)) peak_index = k;
    }
    peak.wi = samples[peak_index].wi;
    peak.wo = samples[peak_index].wo;
    peak.value = samples[peak_index].value;
    Rgb rho_d;
    for (int c = 0; c < 3; ++c) {
      std::vector<double> values;
      values.reserve(samples.size());
      for (const FitSample& sample : samples) values.push_back(sample.value[c]);
      const size_t floor_rank = RankIndex(values.size(), kLobed ? start.floor_rank : 0.5);
      std::nth_element(values.begin(), values.begin() + floor_rank, values.end());
      const double floor_value = std::max(values[floor_rank], 0.0);
      peak.channel_max[c] = *std::max_element(values.begin(), values.end());
      rho_d[c] = std::clamp(kPi * floor_value, 1e-3, 0.9);
      peak.diffuse[c] = rho_d[c] / kPi;
    }
    std::vector<double> x(FreeVariables());
    const auto offsets = VariableLayout<ModelType>::Offsets(options_.grey_specular);
    const auto reserve = ReserveForLaterLobes<ModelType>();
    double budget[3] = {1, 1, 1};
    ModelType::ForEachLobe([&](auto lobe, auto index) {
      using Lobe = decltype(lobe);
      // The lobe's variables in their three-channel layout (models/term.h: Guess).
      double variables[FitVariables::kMaxVariables], taken[3], available[3];
      AvailableBudget(budget, reserve[index], available);
      Lobe::Guess(peak, start.lobes[index - 1], available, TabulatedBound<Lobe>(), variables,
                  taken);
      for (int c = 0; c < 3; ++c) budget[c] = std::max(budget[c] - taken[c], 0.0);
      const bool grey = VariableLayout<ModelType>::Grey(index, options_.grey_specular);
      models::PackVariables(variables, Lobe::NumVariables(false), grey, x.data() + offsets[index]);
    });
    ModelType::DiffuseTerm::Guess(rho_d, budget, x.data());
    return x;
  }

  // Iteratively reweighted least squares for a robust loss rho (Huber or Cauchy, evaluated by
  // Ceres' own loss functions): each sample's residual is scaled by sqrt(rho'(s_i)) at the
  // current fit, s_i its squared residual norm. The loss acts per sample — a blind spot zeroes
  // one sample, not a whole batch. The scale is 3 x the robust standard deviation (1.4826 x
  // median absolute residual), so inliers stay in the quadratic part.
  std::vector<FitSample> Reweight(const std::vector<FitSample>& samples,
                                  const std::vector<double>& x, double* scale) const {
    const FitObjective<ModelType> objective(samples, options_.loss, options_.grey_specular);
    const std::vector<double> squared = objective.SquaredResiduals(objective.At(x.data()));
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
  static size_t RankIndex(size_t size, double rank) {
    return std::min(size - 1, static_cast<size_t>(rank * static_cast<double>(size)));
  }

  const FitOptions& options_;
  std::vector<double> lower_, upper_;
};

}  // namespace brdf::fitters
