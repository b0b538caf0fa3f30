// libFuzzer target for one measurement reader, chosen at compile time by FUZZ_FORMAT (a
// FileFormat name). The input becomes a file, as users give it; every outcome but a clean read
// or a brdf::Error (a one-line diagnosis) is a finding: a crash, a sanitizer report, another
// exception type, a hang or a leak.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/errors.h"
#include "fuzz_util.h"
#include "io/formats.h"

namespace {

const brdf::FileFormat& Format() {
  static const brdf::FileFormat* format = [] {
    for (const brdf::FileFormat& candidate : brdf::FileFormats()) {
      if (candidate.name == FUZZ_FORMAT) return &candidate;
    }
    std::abort();
  }();
  return *format;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = brdf::fuzz::WriteScratchFile(data, size, Format().extensions.front());
  try {
    const brdf::Measurement measurement = Format().read(path, brdf::ReadOptions{});
    (void)brdf::Summarize(measurement);  // what `brdf info` does next
  } catch (const brdf::Error&) {
    // A diagnosed bad input: the expected outcome for most mutations.
  }
  return 0;
}
