// libFuzzer target for the surface description of the virtual gonioreflectometer
// (gonio/surface_sample.h, data/surfaces/*.json).
#include <cstdint>
#include <string>

#include "core/errors.h"
#include "fuzz_util.h"
#include "gonio/surface_sample.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = brdf::fuzz::WriteScratchFile(data, size, ".json");
  try {
    (void)brdf::gonio::ReadSurfaceSpec(path);
  } catch (const brdf::Error&) {
  }
  return 0;
}
