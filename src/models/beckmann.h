// beckmann: the lobe F(wi·h) D(h) G2(wi, wo) / (4 cos theta_i cos theta_o), the microfacet lobe
// of microfacet.h with the Beckmann distribution (Beckmann & Spizzichino 1963; Walter et
// al., EGSR 2007, eqs. 25-27):
//   D(h) = exp(−tan²theta_h / α²) / (π α² cos⁴theta_h),
//   Λ(w) = (erf(a) − 1)/2 + exp(−a²)/(2a√π),  a = 1/(α tan theta).
// D is the slope distribution of a Gaussian random surface: for a height field of rms slope s
// over both axes, sqrt(⟨|∇h|²⟩) = s, Beckmann's α equals s (DESIGN §2; the virtual
// gonioreflectometer's validation, docs/gonio.md).
//
// The model `beckmann` is lambert+beckmann: f = rho_d/π + the lobe.
// Parameters: f0 (RGB in [0, 1], default 0.04), alpha (default 0.1); the model adds rho_d.
// Example: `beckmann:rho_d=0:f0=0.9,0.6,0.3:alpha=0.3`.
#pragma once

#include <type_traits>

#include "models/microfacet.h"

namespace brdf::models {

struct BeckmannLobe : MicrofacetLobe<BeckmannLobe> {
  static constexpr const char* kName = "beckmann";
  static constexpr const char* kFormula =
      "F D G2 / (4 cos_i cos_o); D = exp(-tan^2 h/a^2)/(pi a^2 cos^4 h), Schlick F, "
      "height-correlated Smith G2";

  template <typename T, typename Dir>
  static T D(const Dir& cos_theta_h, const T& alpha) {
    using std::exp;
    const T alpha2 = alpha * alpha;
    const Dir cos2 = cos_theta_h * cos_theta_h;
    return exp(-T(TanSquared(cos_theta_h)) / alpha2) / (T(kPi) * alpha2 * T(cos2 * cos2));
  }

  // Written with erfc, (exp(−a²)/(a√π) − erfc(a))/2, which loses no digits for large a where
  // erf(a) − 1 would cancel. Beyond a = 26 both terms are below 1e-295: Λ = 0 (the normal).
  template <typename T, typename Dir>
  static T Lambda(const Dir& cos_theta, const T& alpha) {
    using std::erfc;
    using std::exp;
    using std::sqrt;
    const Dir tan2 = TanSquared(cos_theta);
    if (!(tan2 > Dir(0))) return T(0);
    const T a = T(1) / (alpha * T(sqrt(tan2)));
    if (a > T(26)) return T(0);
    const T gauss = exp(-a * a);
    return (gauss / (a * T(std::sqrt(kPi))) - ErfcBeside(a, gauss)) * T(0.5);
  }

  // erfc(a) beside gauss = exp(−a²), which its derivative −2 exp(−a²)/√π needs: a Jet's erfc
  // evaluates that exp again. For a Jet (value .a, derivatives .v) this is Ceres' erfc(Jet),
  // the same expression, with the exp taken from gauss (the same argument, so the same bits):
  // the fitter evaluates Λ twice a sample (a Beckmann fit of an RGL file: 6 % fewer instructions).
  template <typename T>
  static T ErfcBeside(const T& a, const T& gauss) {
    if constexpr (std::is_floating_point_v<T>) {
      return std::erfc(a);
    } else {
      return T(std::erfc(a.a), -a.v * gauss.a * (1.0 / std::sqrt(std::atan(1.0))));
    }
  }

  // The half-vector density D cos(theta_h): mass beyond theta_h is exp(−tan²theta_h / α²).
  static double MassBeyond(double cos_h, double alpha) {
    if (!(cos_h > 0.0)) return 0.0;
    return std::exp(-TanSquared(cos_h) / (alpha * alpha));
  }
  static double CosAt(double u, double alpha) {
    if (!(u > 0.0)) return 0.0;
    return 1.0 / std::sqrt(1.0 - alpha * alpha * std::log(u));
  }
  static double Density(double cos_h, double alpha) { return D(cos_h, alpha) * cos_h; }
  // The samplers draw h from D cos(theta_h) (Walter et al. 2007, eqs. 28-29, inverted above).
  static constexpr LobeDistribution kLobeDistribution = {"beckmann", MassBeyond, CosAt,
                                                         Density,    nullptr,    nullptr};

  // exp(−tan²theta/α²) ≈ exp(−theta²/α²) = cos^e(theta) near the peak for e = 2/α².
  static double AlphaEquivalentExponent(double alpha) { return 2.0 / (alpha * alpha); }
};

}  // namespace brdf::models
