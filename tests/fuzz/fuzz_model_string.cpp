// libFuzzer target for the model-string parser (`phong:rho_d=0.5:...`, DESIGN §2). A string
// that parses must print back to the same parameters.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/errors.h"
#include "models/model_string.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const brdf::Model model = brdf::ParseModel(text);
    if (brdf::ParseModel(model.ToString()).params() != model.params()) std::abort();
  } catch (const brdf::Error&) {
  }
  return 0;
}
