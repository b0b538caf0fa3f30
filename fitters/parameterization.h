// How the fitter's free variables map to model parameters (DESIGN §6).
//
// Ceres offers box bounds only, but the energy bound (energy_bound.h) couples parameters. So the
// fitter works in variables for which every value is a physically valid, energy-conserving
// material, and Ceres never has to enforce the constraint. Three parameter blocks: d[3], s[1 or
// 3] and shape[1].
//
// Power-cosine models (rho_d + A(m) rho_s <= 1):
//   q_c   = logistic(s_c)         fraction of the albedo budget taken by the lobe, (0, 1)
//   rho_s = q_c / A(m)            so A(m) rho_s = q_c < 1
//   rho_d = (1 - q_c) logistic(d_c)   so rho_d + A(m) rho_s < 1
//   m     = exp(shape)            the exponent in log space, bounded to [1, 1e6]
// Microfacet models (rho_d + max_theta E(theta; alpha, f0) <= 1):
//   f0    = logistic(s_c)         in (0, 1), as Fresnel reflectance must be
//   alpha = exp(shape)            bounded to the tabulated range [1e-3, 1.5]
//   rho_d = (1 - E_max(alpha, f0_c)) logistic(d_c)   the budget the lobe leaves
// The logistic ("log-odds") variables keep albedos positive as log space would, and bounded as
// the energy budget requires. For lambert only rho_d_c = logistic(d_c) remains. `grey_specular`
// shares one s for all channels (one rho_s or f0, as for dielectric coatings).
#pragma once

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "fitters/energy_bound.h"
#include "models/common.h"

namespace brdf::fitters {

struct FitVariables {
  static constexpr double kLogisticBound = 40.0;  // logistic(-40) = 4e-18: "zero" is reachable
  static constexpr double kMinExponent = 1.0;
  static constexpr double kMaxExponent = 1e6;
  static constexpr double kMinAlpha = MicrofacetAlbedoTable::kMinAlpha;
  static constexpr double kMaxAlpha = MicrofacetAlbedoTable::kMaxAlpha;
  // d[3] + s[3] + shape[1]: the most variables any model has (the Jet size of the covariance).
  static constexpr int kMaxVariables = 7;
};

template <typename M>
constexpr bool kHasLobe = M::kFamily != models::ModelFamily::kDiffuse;

// The box of the shape variable (log exponent or log alpha).
template <typename M>
double ShapeLowerBound() {
  return M::kFamily == models::ModelFamily::kMicrofacet ? std::log(FitVariables::kMinAlpha)
                                                        : std::log(FitVariables::kMinExponent);
}
template <typename M>
double ShapeUpperBound() {
  return M::kFamily == models::ModelFamily::kMicrofacet ? std::log(FitVariables::kMaxAlpha)
                                                        : std::log(FitVariables::kMaxExponent);
}

template <typename T>
T Logistic(const T& x) {
  using std::exp;
  return T(1) / (T(1) + exp(-x));
}

inline double Logit(double p) { return std::log(p / (1.0 - p)); }

// The last call of a pure function of the fitter's variables, remembered (Find, Keep): the
// inputs compared bit for bit, so a hit hands out exactly what the function returned. A fit
// evaluates at one point of the variables many times over: every residual batch of a pass asks
// for the same parameters (VariablesToParams, ParamsAndGradients: for a microfacet model a
// search of the albedo table per channel, through Jets), and Ceres asks for the same Jacobian
// twice (GramCost, gram_solve.h).
template <int kOutputs>
class LastCallOfVariables {
 public:
  // Model M's variables as one key: d[3], then for a lobed model s[1 or 3] and shape[1].
  template <typename M>
  void SetKey(bool grey_specular, const double* d, const double* s, const double* shape) {
    grey_ = grey_specular;
    size_ = 0;
    for (int c = 0; c < 3; ++c) key_[size_++] = d[c];
    if constexpr (kHasLobe<M>) {
      for (int c = 0; c < (grey_specular ? 1 : 3); ++c) key_[size_++] = s[c];
      key_[size_++] = shape[0];
    }
  }
  // True, with the outputs copied to out[0, count), if the last kept call had this key.
  bool Find(const LastCallOfVariables& key, double* out, int count) const {
    if (!valid_ || key.grey_ != grey_ || key.size_ != size_ ||
        std::memcmp(key.key_, key_, sizeof(double) * size_) != 0) {
      return false;
    }
    std::copy(out_, out_ + count, out);
    return true;
  }
  void Keep(const LastCallOfVariables& key, const double* out, int count) {
    *this = key;
    std::copy(out, out + count, out_);
    valid_ = true;
  }

 private:
  bool valid_ = false, grey_ = false;
  int size_ = 0;
  double key_[FitVariables::kMaxVariables];
  double out_[kOutputs];
};

// VariablesToParams without the memory of its last call.
template <typename M, typename T>
void ComputeParams(bool grey_specular, const T* d, const T* s, const T* shape, T* params) {
  using models::ModelFamily;
  using std::exp;
  if constexpr (M::kFamily == ModelFamily::kDiffuse) {
    for (int c = 0; c < 3; ++c) params[M::kRhoD + c] = Logistic(d[c]);
  } else if constexpr (M::kFamily == ModelFamily::kPowerCosine) {
    const T exponent = exp(shape[0]);
    const T lobe_albedo = M::NormalLobeAlbedo(exponent);
    for (int c = 0; c < 3; ++c) {
      const T q = Logistic(s[grey_specular ? 0 : c]);
      params[M::kRhoS + c] = q / lobe_albedo;
      params[M::kRhoD + c] = (T(1) - q) * Logistic(d[c]);
    }
    params[M::kExponent] = exponent;
  } else {
    const MicrofacetAlbedoTable& table = AlbedoTableOf<M>();
    for (int c = 0; c < 3; ++c) {
      const T f0 = Logistic(s[grey_specular ? 0 : c]);
      T budget = T(1) - table.MaxLobeAlbedo(shape[0], f0);
      if (budget < T(0)) budget = T(0);  // a near-perfect mirror leaves nothing for rho_d
      params[M::kF0 + c] = f0;
      params[M::kRhoD + c] = budget * Logistic(d[c]);
    }
    params[M::kAlpha] = exp(shape[0]);
  }
}

// Fills model M's params from the fitter's variables (s and shape unused for lambert).
template <typename M, typename T>
void VariablesToParams(bool grey_specular, const T* d, const T* s, const T* shape, T* params) {
  if constexpr (std::is_same_v<T, double>) {
    // Per thread: the batches of a pass run on every core.
    thread_local LastCallOfVariables<M::kNumParams> last;
    LastCallOfVariables<M::kNumParams> key;
    key.template SetKey<M>(grey_specular, d, s, shape);
    if (last.Find(key, params, M::kNumParams)) return;
    ComputeParams<M, T>(grey_specular, d, s, shape, params);
    last.Keep(key, params, M::kNumParams);
  } else {
    ComputeParams<M, T>(grey_specular, d, s, shape, params);
  }
}

// VariablesToParams and its Jacobian, d params / d variables (row-major, kNumParams rows of
// `variables` columns: d[3], then s[1 or 3] and shape[1] for a lobed model), by automatic
// differentiation with Jets. The parameters are the Jets' values, which can differ from
// VariablesToParams<M, double>'s in the last bit: a Jet divides by multiplying with the inverse.
template <typename M>
void ParamsAndGradients(bool grey_specular, const double* d, const double* s, const double* shape,
                        double* params, double* gradients) {
  using Jet = ceres::Jet<double, FitVariables::kMaxVariables>;
  constexpr bool kLobed = kHasLobe<M>;
  const int s_size = kLobed ? (grey_specular ? 1 : 3) : 0;
  const int variables = 3 + s_size + (kLobed ? 1 : 0);
  // Remembered as params, then gradients.
  constexpr int kOutputs = M::kNumParams * (1 + FitVariables::kMaxVariables);
  thread_local LastCallOfVariables<kOutputs> last;
  LastCallOfVariables<kOutputs> key;
  key.template SetKey<M>(grey_specular, d, s, shape);
  const int outputs = M::kNumParams * (1 + variables);
  double kept[kOutputs];
  if (last.Find(key, kept, outputs)) {
    std::copy(kept, kept + M::kNumParams, params);
    std::copy(kept + M::kNumParams, kept + outputs, gradients);
    return;
  }
  Jet d_jet[3], s_jet[3], shape_jet[1];
  int slot = 0;
  for (int c = 0; c < 3; ++c) d_jet[c] = Jet(d[c], slot++);
  for (int c = 0; c < s_size; ++c) s_jet[c] = Jet(s[c], slot++);
  if (kLobed) shape_jet[0] = Jet(shape[0], slot++);
  Jet params_jet[M::kNumParams];
  VariablesToParams<M, Jet>(grey_specular, d_jet, s_jet, shape_jet, params_jet);
  for (int p = 0; p < M::kNumParams; ++p) {
    params[p] = params_jet[p].a;
    for (int k = 0; k < variables; ++k) gradients[p * variables + k] = params_jet[p].v[k];
  }
  std::copy(params, params + M::kNumParams, kept);
  std::copy(gradients, gradients + M::kNumParams * variables, kept + M::kNumParams);
  last.Keep(key, kept, outputs);
}

// The inverse of VariablesToParams (grey_specular off): the fitter's variables of a model's
// parameters, each logistic variable clamped to the box the fit allows (+-kLogisticBound), so a
// parameter at its bound (rho_d = 0, a used-up budget) maps to a saturated variable that the
// covariance holds out (covariance.h).
template <typename M>
void ParamsToVariables(const double* params, double* d, double* s, double* shape) {
  using models::ModelFamily;
  const auto logit = [](double p) {
    const double bound = FitVariables::kLogisticBound;
    if (!(p > 0)) return -bound;
    if (!(p < 1)) return bound;
    return std::clamp(Logit(p), -bound, bound);
  };
  if constexpr (M::kFamily == ModelFamily::kDiffuse) {
    for (int c = 0; c < 3; ++c) d[c] = logit(params[M::kRhoD + c]);
  } else if constexpr (M::kFamily == ModelFamily::kPowerCosine) {
    const double exponent = params[M::kExponent];
    shape[0] = std::clamp(std::log(exponent), ShapeLowerBound<M>(), ShapeUpperBound<M>());
    const double lobe_albedo = M::NormalLobeAlbedo(std::exp(shape[0]));
    for (int c = 0; c < 3; ++c) {
      const double q = lobe_albedo * params[M::kRhoS + c];
      s[c] = logit(q);
      d[c] = logit(q < 1 ? params[M::kRhoD + c] / (1.0 - q) : 1.0);
    }
  } else {
    shape[0] = std::clamp(std::log(params[M::kAlpha]), ShapeLowerBound<M>(), ShapeUpperBound<M>());
    const MicrofacetAlbedoTable& table = AlbedoTableOf<M>();
    for (int c = 0; c < 3; ++c) {
      const double f0 = params[M::kF0 + c];
      s[c] = logit(f0);
      const double budget = 1.0 - table.MaxLobeAlbedo(shape[0], Logistic(s[c]));
      d[c] = logit(budget > 0 ? params[M::kRhoD + c] / budget : 1.0);
    }
  }
}

}  // namespace brdf::fitters
