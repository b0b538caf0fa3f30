#include "test_util.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/angles.h"
#include "fitters/fit.h"

namespace brdf::testing {

std::string DataPath(const std::string& relative) {
  return std::string(BRDFKIT_DATA_DIR) + "/" + relative;
}
std::string TestPath(const std::string& relative) {
  return std::string(BRDFKIT_TEST_DIR) + "/" + relative;
}

ScratchDir::ScratchDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "brdfkit-test-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) std::abort();
  path_ = pattern;
}

ScratchDir::~ScratchDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::string ScratchDir::Write(const std::string& name, const std::string& bytes) const {
  const std::string file = File(name);
  std::ofstream(file, std::ios::binary) << bytes;
  return file;
}

int ScratchDir::CountEntries() const {
  int count = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(path_)) ++count;
  return count;
}

std::string ReadFileText(const std::string& path) {
  std::ifstream stream(path, std::ios::binary);
  std::stringstream buffer;
  buffer << stream.rdbuf();
  return buffer.str();
}

std::string Lines(const std::string& text, int first, int last) {
  std::string out;
  int line = 1;
  size_t start = 0;
  while (start < text.size() && line <= last) {
    size_t end = text.find('\n', start);
    end = end == std::string::npos ? text.size() : end + 1;
    if (line >= first) out += text.substr(start, end - start);
    start = end;
    ++line;
  }
  return out;
}

int CountLines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

CommandResult RunCommand(const std::string& command) {
  ScratchDir capture;
  const std::string line =
      command + " >'" + capture.File("out") + "' 2>'" + capture.File("err") + "' </dev/null";
  const int status = std::system(line.c_str());
  CommandResult result;
  if (status != -1 && WIFEXITED(status)) result.exit_status = WEXITSTATUS(status);
  result.out = ReadFileText(capture.File("out"));
  result.err = ReadFileText(capture.File("err"));
  return result;
}

CommandResult RunBrdf(const std::string& arguments) {
  return RunCommand(std::string("'") + BRDFKIT_BINARY + "' " + arguments);
}

Measurement ScatteredSamplesOf(const Model& model, double theta_o_step, double phi_o_step) {
  Measurement measurement;
  measurement.format = "native-csv";
  for (double theta_i = 0.0; theta_i < 80.0; theta_i += 10.0) {
    for (double theta_o = 0.0; theta_o < 80.0; theta_o += theta_o_step) {
      for (double phi_o = 0.0; phi_o <= 180.0; phi_o += phi_o_step) {
        Sample sample;
        sample.wi = SphericalDirection(DegToRad(theta_i), kPi);
        sample.wo = SphericalDirection(DegToRad(theta_o), DegToRad(phi_o));
        sample.value = model.Eval(sample.wi, sample.wo);
        measurement.samples.push_back(sample);
      }
    }
  }
  return measurement;
}

std::string ReplaceFirst(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at == std::string::npos) std::abort();
  return text.replace(at, from.size(), to);
}

Vec3 RandomUpperDirection(std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double cos_theta = 1.0 - uniform(*rng);
  const double phi = 2.0 * kPi * uniform(*rng);
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
}

bool HasWarning(const fitters::FitResult& fit, const std::string& prefix) {
  for (const std::string& warning : fit.warnings) {
    if (warning.rfind(prefix, 0) == 0) return true;
  }
  return false;
}

std::string AllWarnings(const fitters::FitResult& fit) {
  std::string text;
  for (const std::string& warning : fit.warnings) text += "\n  " + warning;
  return text;
}

}  // namespace brdf::testing
