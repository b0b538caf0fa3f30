// libFuzzer target for the model-string parser and the fit-report reader (everything a user
// may pass where a MODEL is expected).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/errors.h"
#include "models/model_source.h"
#include "models/model_string.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const brdf::Model model = brdf::ParseModel(text);
    // A parsed model must print back to itself.
    if (brdf::ParseModel(model.ToString()).params() != model.params()) std::abort();
  } catch (const brdf::Error&) {
  }
  // The same bytes as a fit report.
  static const std::string path = "/tmp/brdfkit-fuzz-" + std::to_string(getpid()) + ".json";
  FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, file) != size) std::abort();
  std::fclose(file);
  try {
    brdf::ReadFitReportModel(path);
  } catch (const brdf::Error&) {
  }
  return 0;
}
