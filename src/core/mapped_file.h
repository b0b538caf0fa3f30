// A regular file's bytes mapped read-only into memory, for large binary tables read as they lie
// on disk (the MERL reader). The pages are the system's file cache: nothing is copied, and no
// fresh memory is faulted in (docs/reading.md: on a machine where fresh pages are dear, reading a
// 35 MB MERL file into a new buffer took 136-142 ms, mapping it 4.5 ms).
#pragma once

#include <cstddef>
#include <memory>
#include <string>

namespace brdf {

class MappedFile {
 public:
  // The whole file mapped, or nullptr where it cannot be (no such system call, an empty file, a
  // file system without mappings): the caller then reads the file instead. The size is the
  // file's when mapped; a caller checks it against what it expects before reading the bytes.
  static std::shared_ptr<const MappedFile> Open(const std::string& path);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  const unsigned char* data() const { return data_; }
  size_t size() const { return size_; }

 private:
  MappedFile(const unsigned char* data, size_t size) : data_(data), size_(size) {}
  const unsigned char* data_;
  size_t size_;
};

}  // namespace brdf
