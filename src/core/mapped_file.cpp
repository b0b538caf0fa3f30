#include "core/mapped_file.h"

#if defined(__linux__) || defined(__APPLE__)
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#endif

namespace brdf {

std::shared_ptr<const MappedFile> MappedFile::Open(const std::string& path) {
#if defined(__linux__) || defined(__APPLE__)
  const int descriptor = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (descriptor < 0) return nullptr;
  struct stat status {};
  void* address = MAP_FAILED;
  size_t size = 0;
  if (fstat(descriptor, &status) == 0 && S_ISREG(status.st_mode) && status.st_size > 0) {
    size = static_cast<size_t>(status.st_size);
    int flags = MAP_PRIVATE;
#if defined(MAP_POPULATE)
    flags |= MAP_POPULATE;  // every page mapped in one call rather than a fault at a time
#endif
    address = mmap(nullptr, size, PROT_READ, flags, descriptor, 0);
  }
  close(descriptor);  // the mapping keeps the file
  if (address == MAP_FAILED) return nullptr;
  return std::shared_ptr<const MappedFile>(
      new MappedFile(static_cast<const unsigned char*>(address), size));
#else
  (void)path;
  return nullptr;
#endif
}

MappedFile::~MappedFile() {
#if defined(__linux__) || defined(__APPLE__)
  munmap(const_cast<unsigned char*>(data_), size_);
#endif
}

}  // namespace brdf
