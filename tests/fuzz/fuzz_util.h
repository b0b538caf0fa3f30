// What the libFuzzer targets share: the input becomes a file, as a user hands it to the tool.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace brdf::fuzz {

// Writes the input to one scratch file per process (in memory where the system offers it) and
// returns its path; `extension` (".exr", ".json", ...) is kept, as some readers dispatch on it.
inline const std::string& WriteScratchFile(const uint8_t* data, size_t size,
                                           const std::string& extension) {
  static const std::string path = [&] {
    const char* directory = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    return std::string(directory) + "/brdfkit-fuzz-" + std::to_string(getpid()) + extension;
  }();
  FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, file) != size) std::abort();
  std::fclose(file);
  return path;
}

}  // namespace brdf::fuzz
