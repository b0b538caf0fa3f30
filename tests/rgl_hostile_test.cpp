// Hostile RGL-EPFL tensor files through the command line: the real paper_white file with one
// table entry or value broken at a time (offsets from the hex dump in rgl_test.cpp). Each must
// exit with status 2 and one printable line naming the file and the byte, allocating nothing
// large and writing nothing. Also: detection by magic, not by extension.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "test_util.h"

namespace brdf {
namespace {

using testing::DataPath;
using testing::RunBrdf;
using testing::ScratchDir;

// Table entries of paper_white_rgb.bsdf (entry offset, then: u16 name length, name, u16 ndim,
// u8 dtype, u64 data offset, ndim x u64 shape).
constexpr size_t kVndfEntry = 198, kRgbEntry = 301;
constexpr size_t kVndfDtype = kVndfEntry + 2 + 4 + 2;          // 206
constexpr size_t kVndfShape = kVndfEntry + 2 + 4 + 2 + 1 + 8;  // 217
constexpr size_t kRgbOffset = kRgbEntry + 2 + 3 + 2 + 1;       // 309
constexpr size_t kRgbShape = kRgbOffset + 8;                   // 317
constexpr size_t kRgbData = 0x889e8;

std::string Paper() { return testing::ReadFileText(DataPath("rgl-bsdf/paper_white_rgb.bsdf")); }

template <typename T>
void Put(std::string* bytes, size_t offset, T value) {
  std::memcpy(bytes->data() + offset, &value, sizeof(T));
}

bool Printable(const std::string& text) {
  for (unsigned char c : text) {
    if (c != '\n' && (c < 0x20 || c >= 0x7f)) return false;
  }
  return true;
}

void ExpectRejectedAtByte(const std::string& name, const std::string& bytes, int64_t byte,
                          const std::string& says) {
  ScratchDir dir;
  const std::string path = dir.Write(name, bytes);
  for (const std::string command : {"info", "energy"}) {
    const testing::CommandResult result = RunBrdf(command + " '" + path + "'");
    EXPECT_EQ(result.exit_status, 2) << name << " " << command << "\n" << result.err;
    EXPECT_EQ(testing::CountLines(result.err), 1) << result.err;
    EXPECT_NE(result.err.find(path + ": byte " + std::to_string(byte) + ":"), std::string::npos)
        << name << "\n"
        << result.err;
    EXPECT_NE(result.err.find(says), std::string::npos) << name << "\n" << result.err;
    EXPECT_TRUE(Printable(result.err)) << result.err;
  }
  EXPECT_EQ(dir.CountEntries(), 1);
}

TEST(RglHostile, TruncatedInsideTheFieldTable) {
  // The first entry, "version", points at byte 416, past a 300-byte cut: its offset (byte 30).
  ExpectRejectedAtByte("truncated.bsdf", Paper().substr(0, 300), 30, "runs past the end");
  ExpectRejectedAtByte("cut.bsdf", Paper().substr(0, 16), 14, "file ends inside the field table");
}

TEST(RglHostile, FieldOffsetPastTheEnd) {
  std::string bytes = Paper();
  Put<uint64_t>(&bytes, kRgbOffset, uint64_t{1} << 40);
  ExpectRejectedAtByte("offset.bsdf", bytes, kRgbOffset, "runs past the end");
}

TEST(RglHostile, ShapeWhoseProductOverflowsOrExceedsTheFile) {
  std::string overflow = Paper();
  for (int d = 0; d < 4; ++d) Put<uint64_t>(&overflow, kVndfShape + 8 * d, uint64_t{1} << 40);
  ExpectRejectedAtByte("overflow.bsdf", overflow, kVndfShape, "larger than the");
  std::string wraps = Paper();  // 2^62 x 4 bytes wraps a uint64 to 0 if unchecked
  Put<uint64_t>(&wraps, kVndfShape, uint64_t{1} << 62);
  ExpectRejectedAtByte("wraps.bsdf", wraps, kVndfShape, "larger than the");
  std::string big = Paper();
  Put<uint64_t>(&big, kRgbShape, 1000);  // 1000 phi_i slices: 98 MB of floats
  // 4 x 1000 x 8 x 3 x 32 bytes passes the file size at the fourth extent.
  ExpectRejectedAtByte("big.bsdf", big, kRgbShape + 8 * 3, "larger than the");
}

TEST(RglHostile, UnknownDtype) {
  std::string bytes = Paper();
  bytes[kVndfDtype] = 12;
  ExpectRejectedAtByte("dtype.bsdf", bytes, kVndfDtype, "unknown dtype code 12");
}

TEST(RglHostile, NanCell) {
  std::string bytes = Paper();
  Put<float>(&bytes, kRgbData + 4 * 77, std::numeric_limits<float>::quiet_NaN());
  ExpectRejectedAtByte("nan.bsdf", bytes, kRgbData + 4 * 77, "NaN or infinite");
}

TEST(RglHostile, MissingRequiredField) {
  std::string bytes = Paper();
  bytes[kVndfEntry + 2 + 3] = 'X';  // "vndf" -> "vndX"
  ExpectRejectedAtByte("missing.bsdf", bytes, 412, "no 'vndf' field");
}

TEST(RglHostile, DetectionIsByMagicNotByExtension) {
  ScratchDir dir;
  // An RGL file named .csv is still RGL.
  const std::string renamed = dir.Write("paper.csv", Paper());
  testing::CommandResult result = RunBrdf("info --json '" + renamed + "'");
  EXPECT_EQ(result.exit_status, 0) << result.err;
  EXPECT_NE(result.out.find("\"format\": \"rgl-bsdf\""), std::string::npos) << result.out;
  // The Zemax file in data/ is named .bsdf and is still Zemax.
  result = RunBrdf("info --json '" + DataPath("zemax-bsdf/test_13_planesymmetric_brdf_zemax.bsdf") +
                   "'");
  EXPECT_EQ(result.exit_status, 0) << result.err;
  EXPECT_NE(result.out.find("\"format\": \"zemax\""), std::string::npos) << result.out;
  // Binary that is neither, named .bsdf: one printable line, no raw bytes.
  std::string garbage = Paper().substr(12, 4000);
  const std::string path = dir.Write("garbage.bsdf", garbage);
  result = RunBrdf("info '" + path + "'");
  EXPECT_EQ(result.exit_status, 2);
  EXPECT_EQ(testing::CountLines(result.err), 1) << result.err;
  EXPECT_NE(result.err.find(path), std::string::npos) << result.err;
  EXPECT_TRUE(Printable(result.err)) << result.err;
}

}  // namespace
}  // namespace brdf
