// The "tensor_file" container of the RGL-EPFL material database (Dupuy & Jakob, "An Adaptive
// Parameterization for Efficient Material Acquisition and Rendering", TOG 37(6), 2018), also
// read by Mitsuba 3 (src/core/tensor.cpp). Little-endian:
//   12 bytes   "tensor_file\0"
//   2 bytes    version major, minor (1, 0)
//   uint32     field count
//   per field: uint16 name length, the name (no NUL), uint16 ndim, uint8 dtype,
//              uint64 absolute offset of the data, ndim x uint64 shape (C order, last fastest)
// dtype codes: 1 u8, 2 i8, 3 u16, 4 i16, 5 u32, 6 i32, 7 u64, 8 i64, 9 f16, 10 f32, 11 f64.
//
// Every offset and shape is checked against the file size (and against overflow) while the
// table is parsed, so a hostile file never drives an allocation; errors are ByteErrors naming
// the byte where the table says the wrong thing.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace brdf {

enum class TensorDtype : uint8_t {
  kU8 = 1,
  kI8,
  kU16,
  kI16,
  kU32,
  kI32,
  kU64,
  kI64,
  kF16,
  kF32,
  kF64,
};
const char* TensorDtypeName(TensorDtype dtype);
int TensorDtypeBytes(TensorDtype dtype);

struct TensorField {
  std::string name;
  TensorDtype dtype = TensorDtype::kU8;
  uint64_t data_offset = 0;     // absolute, in the file
  std::vector<uint64_t> shape;  // C order
  int64_t entry_offset = 0;     // where this field's table entry starts (for errors)

  uint64_t count() const;         // product of the shape (1 for ndim 0)
  std::string ShapeText() const;  // "[1, 8, 3, 32, 32]"
};

// True when `head` starts with the 12-byte magic.
bool IsTensorFile(std::string_view head);

class TensorFile {
 public:
  static constexpr std::string_view kMagic{"tensor_file\0", 12};
  static constexpr int64_t kHeaderBytes = 12 + 2 + 4;
  // Far larger than any material file (the seven real ones are 0.6-1.1 MB).
  static constexpr int64_t kMaxBytes = int64_t{1} << 30;

  // Reads and validates a file. Throws InputError / ByteError.
  static TensorFile Read(const std::string& path);
  // Validates bytes already in memory (`path` names them in errors).
  static TensorFile Parse(const std::string& path, std::string bytes);

  const std::string& path() const { return path_; }
  int64_t size() const { return static_cast<int64_t>(bytes_.size()); }
  int version_major() const { return version_[0]; }
  int version_minor() const { return version_[1]; }
  const std::vector<TensorField>& fields() const { return fields_; }
  // The named field, or nullptr.
  const TensorField* Find(std::string_view name) const;
  // The named field with `ndim` dimensions; throws ByteError at the end of the field table
  // when it is missing, at its entry when the rank differs.
  const TensorField& Require(std::string_view name, size_t ndim) const;

  // Every element converted to double (f16 included), in C order.
  std::vector<double> Values(const TensorField& field) const;
  // A u8 field as text (e.g. "description"), NULs trimmed at the end.
  std::string Text(const TensorField& field) const;
  // Byte offset of element `index` of `field`, for error messages.
  static int64_t ElementOffset(const TensorField& field, uint64_t index);
  // Offset just past the field table.
  int64_t table_end() const { return table_end_; }

 private:
  std::string path_;
  std::string bytes_;
  int version_[2] = {0, 0};
  std::vector<TensorField> fields_;
  int64_t table_end_ = 0;
};

}  // namespace brdf
