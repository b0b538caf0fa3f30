#include "fitters/energy_bound.h"

namespace brdf::fitters {

Rgb EnergyBound(const Model& model) {
  return VisitModelType(model.name(), [&](auto model_type) {
    return EnergyBound<decltype(model_type)>(model.params().data());
  });
}

const char* EnergyBoundFormula(models::ModelFamily family) {
  switch (family) {
    case models::ModelFamily::kDiffuse:
      return "rho_d";
    case models::ModelFamily::kPowerCosine:
      return "rho_d + A(m) rho_s";
    case models::ModelFamily::kMicrofacet:
      return "rho_d + max over theta of E(theta; alpha, f0)";
  }
  return "?";
}

}  // namespace brdf::fitters
