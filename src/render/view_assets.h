// The files embedded into `brdf view`'s page (render/view_assets.cpp).
#pragma once

#include <string_view>

extern "C" {
extern const char brdf_view_template[], brdf_view_template_end[];
extern const char brdf_three_core[], brdf_three_core_end[];
extern const char brdf_three_module[], brdf_three_module_end[];
extern const char brdf_three_license[], brdf_three_license_end[];
}

namespace brdf {

std::string_view ViewTemplate();  // src/render/view/view.html
std::string_view ThreeCore();     // three/build/three.core.js (ES module)
std::string_view ThreeModule();   // three/build/three.module.js (imports ./three.core.js)
std::string_view ThreeLicense();  // three/LICENSE (MIT)

}  // namespace brdf
