// How the fitter's free variables map to a model's parameters (DESIGN §6).
//
// Ceres offers box bounds only, but the energy bound (energy_bound.h) couples parameters. So the
// fitter works in variables for which every value is a physically valid, energy-conserving
// material, and Ceres never has to enforce the constraint. The variables are the terms' own
// (models/term.h: each term's Map), in the composition's order: the diffuse term's first, then
// each lobe's. The albedo budget, 1 per channel, flows through the lobes in order, each taking its
// largest albedo over incidence from what is left, and the diffuse term takes a logistic share of
// the rest:
//   power-cosine lobe:  q_c = logistic(s_c) budget_c, rho_s_c = q_c / A(e), e = exp(shape)
//   microfacet lobe:    f0_c = logistic(s_c), alpha = exp(shape); it takes
//                       max_theta E(theta; alpha, f0_c)
//   lambert:            rho_d_c = budget_c logistic(d_c)
// The logistic ("log-odds") variables keep albedos positive as log space would, and bounded as
// the energy budget requires. A second lobe takes its share of what the first left. A microfacet
// lobe's albedo does not fall below its f0 = 0 value (Schlick's F tends to 1 at grazing for any
// f0), so the first lobe leaves the second at least that value at its largest alpha
// (ReserveForLaterLobes), and the second raises its alpha where its f0 = 0 albedo would not fit
// what is left (models/microfacet.h). Every reachable point therefore keeps the sum of the terms'
// largest albedos within 1, the bound `brdf energy` checks (an upper bound of the joint maximum
// over incidence). `grey_specular` gives the first lobe one variable for all channels (one rho_s
// or f0, as for dielectric coatings); a second lobe (a clear coat) always has one.
//
// Everything here is a pure function of the variables; a fit computes the map and its Jacobian
// once per point (FitObjective::At) and hands them to every batch.
#pragma once

#include <ceres/jet.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "fitters/microfacet_bound.h"
#include "models/composition.h"
#include "models/term.h"

namespace brdf::fitters {

using models::Logistic;
using models::Logit;

struct FitVariables {
  static constexpr double kLogisticBound = models::kLogisticBound;
  // The most variables any composition has: d[3], and two lobes of s[3] and shape[1], with room
  // for a term with two shapes (the Jet size of the map's Jacobian).
  static constexpr int kMaxVariables = 16;
};

// The tabulated bound of a lobe term (its Map's `bound`): the largest albedo over incidence of
// the table the term names (AlbedoTableTerm: its own, or another term's, e.g. ggx-aniso's is
// ggx's). Only terms whose bound is tabulated (kTabulatedBound) call it.
template <typename Term>
struct TabulatedBound {
  template <typename T>
  T MaxAlbedo(const T& log_shape, const T& p) const {
    return AlbedoTableOf<typename Term::AlbedoTableTerm>().MaxLobeAlbedo(log_shape, p);
  }
};

// The layout of composition M's variables: the terms' blocks in order.
template <typename M>
struct VariableLayout {
  // Whether lobe `index` (1 or 2) has one variable for all channels.
  static bool Grey(int index, bool grey_specular) { return index == 1 ? grey_specular : true; }
  // The first variable of each term.
  static std::array<int, M::kTerms> Offsets(bool grey_specular) {
    std::array<int, M::kTerms> offsets{};
    int next = 0;
    M::ForEachTerm([&](auto term, auto index) {
      offsets[index] = next;
      next += decltype(term)::NumVariables(Grey(index, grey_specular));
    });
    return offsets;
  }
  static int Count(bool grey_specular) {
    int count = 0;
    M::ForEachTerm([&](auto term, auto index) {
      count += decltype(term)::NumVariables(Grey(index, grey_specular));
    });
    return count;
  }
  // The box of every variable.
  static void Bounds(bool grey_specular, std::vector<double>* lower, std::vector<double>* upper) {
    lower->assign(Count(grey_specular), 0.0);
    upper->assign(Count(grey_specular), 0.0);
    const auto offsets = Offsets(grey_specular);
    M::ForEachTerm([&](auto term, auto index) {
      decltype(term)::VariableBounds(Grey(index, grey_specular), lower->data() + offsets[index],
                                     upper->data() + offsets[index]);
    });
  }
  // Which variables are shapes (log exponent or log alpha: the last variable of a term with a
  // shape parameter); the others are logistic shares.
  static std::vector<bool> Shapes(bool grey_specular) {
    std::vector<bool> shapes(Count(grey_specular), false);
    const auto offsets = Offsets(grey_specular);
    M::ForEachTerm([&](auto term, auto index) {
      using Term = decltype(term);
      if (Term::kShapeSlot >= 0) {
        shapes[offsets[index] + Term::NumVariables(Grey(index, grey_specular)) - 1] = true;
      }
    });
    return shapes;
  }
};

// What each lobe of M must leave the lobes after it (reserve[index], index 1 or 2): the sum of
// their least albedos (models/term.h: LeastAlbedo). A microfacet lobe's albedo never falls below
// its f0 = 0 value, Schlick's grazing rise; with this much left it can always raise its roughness
// until that fits (models/microfacet.h), so the sum of the terms' albedos stays within 1 at every
// point. With one lobe nothing is reserved, and a one-lobe map is what it always was.
template <typename M>
std::array<double, M::kTerms + 1> ReserveForLaterLobes() {
  std::array<double, M::kTerms + 1> least{}, reserve{};
  M::ForEachLobe([&](auto lobe, auto index) {
    using Lobe = decltype(lobe);
    if constexpr (decltype(index)::value > 1) {  // the first lobe's least albedo is never reserved
      static_assert(Lobe::kFitsAnyBudget,
                    "a lobe that follows another must keep within any budget (models/term.h)");
      least[index] = Lobe::LeastAlbedo(TabulatedBound<Lobe>());
    }
  });
  for (int index = M::kTerms - 2; index >= 0; --index) {
    reserve[index] = reserve[index + 1] + least[index + 1];
  }
  return reserve;
}

// The budget a lobe is handed: what is left, less what the later lobes need (never below 0).
template <typename T>
void AvailableBudget(const T* left, double reserve, T* available) {
  for (int c = 0; c < 3; ++c) {
    available[c] = left[c] - T(reserve);
    if (available[c] < T(0)) available[c] = T(0);
  }
}

// Fills M's parameters from the variables `x`.
template <typename M, typename T>
void ComputeParams(bool grey_specular, const T* x, T* params) {
  const auto offsets = VariableLayout<M>::Offsets(grey_specular);
  const auto reserve = ReserveForLaterLobes<M>();
  T budget[3] = {T(1), T(1), T(1)}, available[3], taken[3];
  M::ForEachLobe([&](auto lobe, auto index) {
    using Lobe = decltype(lobe);
    AvailableBudget(budget, reserve[index], available);
    Lobe::Map(x + offsets[index], VariableLayout<M>::Grey(index, grey_specular), available,
              params + M::kOffsets[index], taken, TabulatedBound<Lobe>());
    for (int c = 0; c < 3; ++c) {
      budget[c] = budget[c] - taken[c];
      if (budget[c] < T(0)) budget[c] = T(0);  // a near-perfect mirror leaves nothing
    }
  });
  using Diffuse = typename M::DiffuseTerm;
  Diffuse::Map(x, grey_specular, budget, params, taken, TabulatedBound<Diffuse>());
}

// The map at `x` and its Jacobian d params / d x (row-major, kNumParams rows of Count()
// columns), by automatic differentiation with Jets. The parameters are the Jets' values.
template <typename M>
void ParamsAndGradients(bool grey_specular, const double* x, double* params, double* gradients) {
  using Jet = ceres::Jet<double, FitVariables::kMaxVariables>;
  const int n = VariableLayout<M>::Count(grey_specular);
  Jet x_jet[FitVariables::kMaxVariables];
  for (int k = 0; k < n; ++k) x_jet[k] = Jet(x[k], k);
  Jet params_jet[M::kNumParams];
  ComputeParams<M, Jet>(grey_specular, x_jet, params_jet);
  for (int p = 0; p < M::kNumParams; ++p) {
    params[p] = params_jet[p].a;
    for (int k = 0; k < n; ++k) gradients[p * n + k] = params_jet[p].v[k];
  }
}

// The inverse of ComputeParams (grey_specular off): the variables of M's parameters, each
// logistic variable clamped to the box the fit allows (+-kLogisticBound), so a parameter at its
// bound (rho_d = 0, a used-up budget) maps to a saturated variable that the covariance holds out
// (covariance.h).
template <typename M>
std::vector<double> ParamsToVariables(const double* params) {
  std::vector<double> x(VariableLayout<M>::Count(false));
  const auto offsets = VariableLayout<M>::Offsets(false);
  const auto reserve = ReserveForLaterLobes<M>();
  double budget[3] = {1, 1, 1}, available[3], taken[3];
  M::ForEachLobe([&](auto lobe, auto index) {
    using Lobe = decltype(lobe);
    AvailableBudget(budget, reserve[index], available);
    Lobe::Unmap(params + M::kOffsets[index], VariableLayout<M>::Grey(index, false), available,
                x.data() + offsets[index], taken, TabulatedBound<Lobe>());
    for (int c = 0; c < 3; ++c) budget[c] = std::max(budget[c] - taken[c], 0.0);
  });
  using Diffuse = typename M::DiffuseTerm;
  Diffuse::Unmap(params, false, budget, x.data(), taken, TabulatedBound<Diffuse>());
  return x;
}

}  // namespace brdf::fitters
