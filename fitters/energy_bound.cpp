#include "fitters/energy_bound.h"

namespace brdf::fitters {

Rgb EnergyBound(const Model& model) {
  return VisitModelType(model.name(), [&](auto model_type) {
    return EnergyBound<decltype(model_type)>(model.params().data());
  });
}

}  // namespace brdf::fitters
