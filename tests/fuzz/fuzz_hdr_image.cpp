// libFuzzer target for HDR image input (DESIGN §8), compiled once per reader: FUZZ_EXR selects
// OpenEXR, otherwise Radiance RGBE. The input goes through ReadHdrImage, which picks the reader
// by signature, as `brdf render --env` and `brdf tonemap` do; an image that reads must have the
// size it claims.
#include <ImfThreading.h>

#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/errors.h"
#include "fuzz_util.h"
#include "hdr/image_files.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
#ifdef FUZZ_EXR
  const std::string& path = brdf::fuzz::WriteScratchFile(data, size, ".exr");
#else
  const std::string& path = brdf::fuzz::WriteScratchFile(data, size, ".hdr");
#endif
  try {
    const brdf::Image image = brdf::ReadHdrImage(path);
    if (image.width <= 0 || image.height <= 0 ||
        image.rgba.size() != static_cast<size_t>(image.pixel_count()) * brdf::Image::kChannels) {
      std::abort();
    }
  } catch (const brdf::Error&) {
  }
#ifdef FUZZ_EXR
  // ReadExr starts OpenEXR's thread pool on its first call; inputs of a few hundred bytes
  // decode faster without it.
  static const bool single_threaded = [] {
    Imf::setGlobalThreadCount(0);
    return true;
  }();
  (void)single_threaded;
#endif
  return 0;
}
