#include "core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "core/errors.h"

namespace brdf {
namespace {

std::string DirectoryOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// Creates a unique temporary file next to `path` (same file system, so rename is atomic).
std::string MakeTemporary(const std::string& path) {
  std::string pattern = path + ".tmp.XXXXXX";
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0) {
    throw OutputError(path, std::string("cannot create a file in '") + DirectoryOf(path) +
                                "': " + std::strerror(errno));
  }
  ::fchmod(fd, 0644);
  ::close(fd);
  return pattern;
}

void FlushToDisk(const std::string& temporary) {
  const int fd = ::open(temporary.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

}  // namespace

void WriteFileAtomicallyByName(const std::string& path,
                               const std::function<void(const std::string& temporary)>& write_to) {
  struct stat info;
  if (::stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) {
    throw OutputError(path, "is a directory, expected a file name to write");
  }
  const std::string temporary = MakeTemporary(path);
  try {
    write_to(temporary);
    FlushToDisk(temporary);
    if (std::rename(temporary.c_str(), path.c_str()) != 0) {
      throw OutputError(
          path, std::string("cannot rename the finished file into place: ") + std::strerror(errno));
    }
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
}

void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                         bool binary) {
  WriteFileAtomicallyByName(path, [&](const std::string& temporary) {
    std::ofstream stream(temporary, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
    if (!stream) throw OutputError(path, "cannot open a temporary file for writing");
    write(stream);
    stream.flush();
    if (!stream) throw OutputError(path, "write failed (disk full?)");
  });
}

}  // namespace brdf
