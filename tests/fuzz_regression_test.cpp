// Every input that once broke a fuzz target (tests/fuzz/regressions/<target>/) goes through the
// same reader again: it must read, or be rejected as a diagnosed bad input naming the file —
// never crash or escape as another exception. Under scripts/sanitize the same replay fails on
// any ASan or UBSan report, which is how the undefined behaviour the inputs once caused shows.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include "core/errors.h"
#include "gonio/instrument.h"
#include "gonio/surface_sample.h"
#include "hdr/image_files.h"
#include "io/formats.h"
#include "models/model_source.h"
#include "models/model_string.h"
#include "test_util.h"

namespace brdf {
namespace {

// What each target reads, given the path of a saved input.
std::function<void(const std::string&)> ReaderOf(const std::string& target) {
  for (const FileFormat& format : FileFormats()) {
    std::string name = "fuzz_" + format.name;
    for (char& c : name) c = c == '-' ? '_' : c;
    if (name == target) return [&format](const std::string& path) { format.read(path, {}); };
  }
  const std::map<std::string, std::function<void(const std::string&)>> readers = {
      {"fuzz_model_string",
       [](const std::string& path) { ParseModel(testing::ReadFileText(path)); }},
      {"fuzz_fit_report", [](const std::string& path) { LoadModel(path); }},
      {"fuzz_exr", [](const std::string& path) { ReadHdrImage(path); }},
      {"fuzz_radiance", [](const std::string& path) { ReadHdrImage(path); }},
      {"fuzz_instrument", [](const std::string& path) { gonio::ReadInstrument(path); }},
      {"fuzz_surface", [](const std::string& path) { gonio::ReadSurfaceSpec(path); }},
  };
  const auto reader = readers.find(target);
  return reader == readers.end() ? nullptr : reader->second;
}

TEST(FuzzRegressions, EverySavedInputReadsOrIsADiagnosedError) {
  const std::filesystem::path root = testing::TestPath("fuzz/regressions");
  int inputs = 0;
  for (const auto& target : std::filesystem::directory_iterator(root)) {
    const auto read = ReaderOf(target.path().filename().string());
    ASSERT_TRUE(read) << "no reader for " << target.path();
    for (const auto& input : std::filesystem::directory_iterator(target.path())) {
      const std::string path = input.path().string();
      ++inputs;
      try {
        read(path);
      } catch (const Error& error) {
        // A model string is text, not a file: its errors quote the text instead.
        if (target.path().filename() != "fuzz_model_string") {
          EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
        }
      }
    }
  }
  EXPECT_GT(inputs, 0);
}

}  // namespace
}  // namespace brdf
