// The files the page of `brdf view` is made of, linked into the binary at build time
// (src/CMakeLists.txt names them: the page's template from src/render/view/, three.js and its
// licence from the pinned npm install in the build tree). Each is a byte range
// [NAME, NAME_end); none is NUL-terminated.
#include "render/view_assets.h"

#define BRDF_EMBED(name, file)        \
  asm(".section .rodata\n"            \
      ".global " #name                \
      "\n"                            \
      ".hidden " #name                \
      "\n"                            \
      ".balign 16\n" #name            \
      ":\n"                           \
      ".incbin \"" file               \
      "\"\n"                          \
      ".global " #name                \
      "_end\n"                        \
      ".hidden " #name "_end\n" #name \
      "_end:\n"                       \
      ".byte 0\n"                     \
      ".previous\n")

BRDF_EMBED(brdf_view_template, BRDF_VIEW_TEMPLATE_FILE);
BRDF_EMBED(brdf_three_core, BRDF_THREE_CORE_FILE);
BRDF_EMBED(brdf_three_module, BRDF_THREE_MODULE_FILE);
BRDF_EMBED(brdf_three_license, BRDF_THREE_LICENSE_FILE);

namespace brdf {

std::string_view ViewTemplate() {
  return {brdf_view_template, static_cast<size_t>(brdf_view_template_end - brdf_view_template)};
}
std::string_view ThreeCore() {
  return {brdf_three_core, static_cast<size_t>(brdf_three_core_end - brdf_three_core)};
}
std::string_view ThreeModule() {
  return {brdf_three_module, static_cast<size_t>(brdf_three_module_end - brdf_three_module)};
}
std::string_view ThreeLicense() {
  return {brdf_three_license, static_cast<size_t>(brdf_three_license_end - brdf_three_license)};
}

}  // namespace brdf
