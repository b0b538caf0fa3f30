#include "fitters/energy_bound.h"

#include "core/errors.h"
#include "models/registry.h"

namespace brdf::fitters {

LobeKind LobeKindOf(std::string_view model_name) {
  if (model_name == models::Lambert::kName) return LobeKind::kNone;
  if (model_name == models::Phong::kName) return LobeKind::kPhong;
  if (model_name == models::BlinnPhong::kName) return LobeKind::kBlinnPhong;
  if (model_name == models::BlinnPhongExact::kName) return LobeKind::kBlinnPhongExact;
  FindModel(model_name);  // throws the descriptive UsageError
  throw UsageError("model '" + std::string(model_name) + "' cannot be fitted");
}

}  // namespace brdf::fitters
