// libFuzzer target for the instrument description (gonio/instrument.h). An instrument that
// reads must survive the round trip through its own JSON (the measurement metadata).
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/errors.h"
#include "gonio/instrument.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const brdf::gonio::Instrument instrument = brdf::gonio::ParseInstrument(text, "fuzz.json");
    instrument.Validate();
    const std::string json = instrument.ToJson();
    if (brdf::gonio::ParseInstrument(json, "round trip").ToJson() != json) std::abort();
  } catch (const brdf::Error&) {
  }
  return 0;
}
