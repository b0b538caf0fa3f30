// Model strings on the command line (DESIGN §2): NAME[:key=value]..., an RGB value given as
// three comma-separated numbers or one number for grey, e.g.
//   blinn-phong:rho_d=0.5,0.1,0.1:rho_s=0.04:m=200
// Parameters not named take the registry's defaults.
#pragma once

#include <string>
#include <string_view>

#include "models/registry.h"

namespace brdf {

// Throws UsageError naming the string, the offending part and what was expected.
Model ParseModel(std::string_view text);

}  // namespace brdf
