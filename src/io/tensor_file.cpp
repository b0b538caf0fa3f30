#include "io/tensor_file.h"

#include <cmath>
#include <cstring>

#include "core/enum_names.h"
#include "core/errors.h"
#include "core/text.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the tensor_file reader copies little-endian bytes directly");

namespace brdf {
namespace {

constexpr EnumName<TensorDtype> kTensorDtypeNames[] = {
    {TensorDtype::kU8, "u8"},   {TensorDtype::kI8, "i8"},   {TensorDtype::kU16, "u16"},
    {TensorDtype::kI16, "i16"}, {TensorDtype::kU32, "u32"}, {TensorDtype::kI32, "i32"},
    {TensorDtype::kU64, "u64"}, {TensorDtype::kI64, "i64"}, {TensorDtype::kF16, "f16"},
    {TensorDtype::kF32, "f32"}, {TensorDtype::kF64, "f64"},
};

// More dimensions than any tensor in the material database uses (vndf and rgb have 4 and 5).
constexpr uint16_t kMaxDimensions = 16;

// Reads little-endian values from the table, failing with the byte offset of what is missing.
class TableCursor {
 public:
  TableCursor(const std::string& path, const std::string& bytes) : path_(path), bytes_(bytes) {}

  template <typename T>
  T Next(const char* what) {
    if (position_ + sizeof(T) > bytes_.size()) {
      throw ByteError(path_, static_cast<int64_t>(position_),
                      std::string("file ends inside the field table, expected ") + what);
    }
    T value;
    std::memcpy(&value, bytes_.data() + position_, sizeof(T));
    position_ += sizeof(T);
    return value;
  }
  std::string NextText(size_t length, const char* what) {
    if (length > bytes_.size() - position_) {
      throw ByteError(path_, static_cast<int64_t>(position_),
                      std::string("file ends inside the field table, expected ") + what + " of " +
                          std::to_string(length) + " bytes");
    }
    std::string text = bytes_.substr(position_, length);
    position_ += length;
    return text;
  }
  int64_t position() const { return static_cast<int64_t>(position_); }

 private:
  const std::string& path_;
  const std::string& bytes_;
  size_t position_ = 0;
};

// IEEE 754 binary16 -> double.
double HalfToDouble(uint16_t half) {
  const int sign = half >> 15, exponent = (half >> 10) & 0x1f, mantissa = half & 0x3ff;
  double magnitude;
  if (exponent == 0) {
    magnitude = std::ldexp(mantissa, -24);  // subnormal
  } else if (exponent == 31) {
    magnitude = mantissa == 0 ? INFINITY : NAN;
  } else {
    magnitude = std::ldexp(mantissa + 1024, exponent - 25);
  }
  return sign ? -magnitude : magnitude;
}

template <typename T>
double Load(const char* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return static_cast<double>(value);
}

}  // namespace

const char* TensorDtypeName(TensorDtype dtype) { return NameOf(kTensorDtypeNames, dtype); }

int TensorDtypeBytes(TensorDtype dtype) {
  switch (dtype) {
    case TensorDtype::kU8:
    case TensorDtype::kI8:
      return 1;
    case TensorDtype::kU16:
    case TensorDtype::kI16:
    case TensorDtype::kF16:
      return 2;
    case TensorDtype::kU32:
    case TensorDtype::kI32:
    case TensorDtype::kF32:
      return 4;
    case TensorDtype::kU64:
    case TensorDtype::kI64:
    case TensorDtype::kF64:
      return 8;
  }
  return 0;
}

uint64_t TensorField::count() const {
  uint64_t product = 1;
  for (uint64_t extent : shape) product *= extent;  // checked against overflow when parsed
  return product;
}

std::string TensorField::ShapeText() const {
  std::string text = "[";
  for (size_t k = 0; k < shape.size(); ++k) {
    text += (k ? ", " : "") + std::to_string(shape[k]);
  }
  return text + "]";
}

bool IsTensorFile(std::string_view head) {
  return head.size() >= TensorFile::kMagic.size() &&
         head.substr(0, TensorFile::kMagic.size()) == TensorFile::kMagic;
}

TensorFile TensorFile::Read(const std::string& path) {
  return Parse(path, ReadFileBytes(path, kMaxBytes));
}

TensorFile TensorFile::Parse(const std::string& path, std::string bytes) {
  TensorFile file;
  file.path_ = path;
  file.bytes_ = std::move(bytes);
  const std::string& data = file.bytes_;
  if (!IsTensorFile(data)) {
    throw ByteError(path, 0, "expected the 12-byte magic \"tensor_file\\0\"");
  }
  TableCursor cursor(path, data);
  cursor.NextText(kMagic.size(), "the magic");
  file.version_[0] = cursor.Next<uint8_t>("the version (major)");
  file.version_[1] = cursor.Next<uint8_t>("the version (minor)");
  if (file.version_[0] != 1 || file.version_[1] != 0) {
    throw ByteError(path, 12,
                    "tensor_file version " + std::to_string(file.version_[0]) + "." +
                        std::to_string(file.version_[1]) + ", expected 1.0");
  }
  const uint32_t field_count = cursor.Next<uint32_t>("the field count (uint32)");
  // The smallest entry (empty name, ndim 0) takes 13 bytes: a larger count cannot fit.
  if (field_count > (data.size() - kHeaderBytes) / 13) {
    throw ByteError(path, 14,
                    "field count " + std::to_string(field_count) + " cannot fit in a file of " +
                        std::to_string(data.size()) + " bytes");
  }
  const uint64_t file_size = data.size();
  for (uint32_t index = 0; index < field_count; ++index) {
    TensorField field;
    field.entry_offset = cursor.position();
    const uint16_t name_length = cursor.Next<uint16_t>("a field name length (uint16)");
    field.name = cursor.NextText(name_length, "a field name");
    const std::string shown = PrintableText(field.name);
    const int64_t ndim_offset = cursor.position();
    const uint16_t ndim = cursor.Next<uint16_t>("a field's ndim (uint16)");
    if (ndim > kMaxDimensions) {
      throw ByteError(path, ndim_offset,
                      "field '" + shown + "' has " + std::to_string(ndim) +
                          " dimensions, expected at most " + std::to_string(kMaxDimensions));
    }
    const int64_t dtype_offset = cursor.position();
    const uint8_t dtype = cursor.Next<uint8_t>("a field's dtype (uint8)");
    if (dtype < 1 || dtype > 11) {
      throw ByteError(path, dtype_offset,
                      "field '" + shown + "' has unknown dtype code " + std::to_string(dtype) +
                          ", expected 1..11 (u8 i8 u16 i16 u32 i32 u64 i64 f16 f32 f64)");
    }
    field.dtype = static_cast<TensorDtype>(dtype);
    const int64_t data_offset_offset = cursor.position();
    field.data_offset = cursor.Next<uint64_t>("a field's data offset (uint64)");
    uint64_t field_bytes = static_cast<uint64_t>(TensorDtypeBytes(field.dtype));
    for (uint16_t d = 0; d < ndim; ++d) {
      const int64_t extent_offset = cursor.position();
      const uint64_t extent = cursor.Next<uint64_t>("a field's shape (uint64)");
      field.shape.push_back(extent);
      if (__builtin_mul_overflow(field_bytes, extent, &field_bytes) || field_bytes > file_size) {
        throw ByteError(path, extent_offset,
                        "field '" + shown + "' shape extent " + std::to_string(extent) +
                            " makes it larger than the " + std::to_string(file_size) +
                            "-byte file");
      }
    }
    uint64_t data_end = 0;
    if (__builtin_add_overflow(field.data_offset, field_bytes, &data_end) || data_end > file_size) {
      throw ByteError(path, data_offset_offset,
                      "field '" + shown + "' data at offset " + std::to_string(field.data_offset) +
                          " (" + std::to_string(field_bytes) + " bytes) runs past the end of the " +
                          std::to_string(file_size) + "-byte file");
    }
    if (file.Find(field.name) != nullptr) {
      throw ByteError(path, field.entry_offset, "second field named '" + shown + "'");
    }
    file.fields_.push_back(std::move(field));
  }
  file.table_end_ = cursor.position();
  return file;
}

const TensorField* TensorFile::Find(std::string_view name) const {
  for (const TensorField& field : fields_) {
    if (field.name == name) return &field;
  }
  return nullptr;
}

const TensorField& TensorFile::Require(std::string_view name, size_t ndim) const {
  const TensorField* field = Find(name);
  if (field == nullptr) {
    throw ByteError(path_, table_end_,
                    "the field table has no '" + std::string(name) + "' field (required)");
  }
  if (field->shape.size() != ndim) {
    throw ByteError(path_, field->entry_offset,
                    "field '" + field->name + "' has " + std::to_string(field->shape.size()) +
                        " dimensions " + field->ShapeText() + ", expected " + std::to_string(ndim));
  }
  return *field;
}

int64_t TensorFile::ElementOffset(const TensorField& field, uint64_t index) {
  return static_cast<int64_t>(field.data_offset + index * TensorDtypeBytes(field.dtype));
}

std::vector<double> TensorFile::Values(const TensorField& field) const {
  const uint64_t count = field.count();
  std::vector<double> values(count);
  const int stride = TensorDtypeBytes(field.dtype);
  const char* base = bytes_.data() + field.data_offset;
  for (uint64_t k = 0; k < count; ++k) {
    const char* element = base + k * stride;
    switch (field.dtype) {
      case TensorDtype::kU8:
        values[k] = Load<uint8_t>(element);
        break;
      case TensorDtype::kI8:
        values[k] = Load<int8_t>(element);
        break;
      case TensorDtype::kU16:
        values[k] = Load<uint16_t>(element);
        break;
      case TensorDtype::kI16:
        values[k] = Load<int16_t>(element);
        break;
      case TensorDtype::kU32:
        values[k] = Load<uint32_t>(element);
        break;
      case TensorDtype::kI32:
        values[k] = Load<int32_t>(element);
        break;
      case TensorDtype::kU64:
        values[k] = Load<uint64_t>(element);
        break;
      case TensorDtype::kI64:
        values[k] = Load<int64_t>(element);
        break;
      case TensorDtype::kF16: {
        uint16_t half;
        std::memcpy(&half, element, 2);
        values[k] = HalfToDouble(half);
        break;
      }
      case TensorDtype::kF32:
        values[k] = Load<float>(element);
        break;
      case TensorDtype::kF64:
        values[k] = Load<double>(element);
        break;
    }
  }
  return values;
}

std::string TensorFile::Text(const TensorField& field) const {
  std::string text =
      bytes_.substr(field.data_offset, field.count() * TensorDtypeBytes(field.dtype));
  while (!text.empty() && text.back() == '\0') text.pop_back();
  return text;
}

}  // namespace brdf
