// libFuzzer target for the fit-report reader (a FIT.json given where a MODEL is expected,
// DESIGN §6). A report that reads must hold a model whose string form parses back to it.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/errors.h"
#include "fuzz_util.h"
#include "models/model_source.h"
#include "models/model_string.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = brdf::fuzz::WriteScratchFile(data, size, ".json");
  try {
    const brdf::Model model = brdf::LoadModel(path);
    if (brdf::ParseModel(model.ToString()).params() != model.params()) std::abort();
  } catch (const brdf::Error&) {
  }
  return 0;
}
