// Helpers shared by the tests: paths to bundled data, scratch directories, and running the
// `brdf` binary as a user would.
#pragma once

#include <random>
#include <string>

#include "core/angles.h"
#include "core/measurement.h"
#include "models/registry.h"

namespace brdf::fitters {
struct FitResult;
}

namespace brdf::testing {

// Path of a file under data/ (the bundled real measurements).
std::string DataPath(const std::string& relative);
// Path of a file under tests/ (fixtures and hostile inputs).
std::string TestPath(const std::string& relative);

// A fresh empty directory, removed with its contents when the object dies.
class ScratchDir {
 public:
  ScratchDir();
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::string& path() const { return path_; }
  std::string File(const std::string& name) const { return path_ + "/" + name; }
  // Writes `bytes` to a file in the directory and returns its path.
  std::string Write(const std::string& name, const std::string& bytes) const;
  // Number of entries in the directory (to check that nothing was left behind).
  int CountEntries() const;

 private:
  std::string path_;
};

// Whole file as bytes ("" when it cannot be read).
std::string ReadFileText(const std::string& path);
// Lines `first`..`last` (1-based, inclusive) of `text`, each with its original line end.
std::string Lines(const std::string& text, int first, int last);
// Number of '\n' in `text`.
int CountLines(const std::string& text);
// `text` with the first occurrence of `from` replaced by `to`; aborts when there is none (a
// broken test, not a broken reader).
std::string ReplaceFirst(std::string text, const std::string& from, const std::string& to);

// Uniform direction on the upper hemisphere (z = cos(theta) uniform in (0, 1]: never exactly on
// the horizon).
Vec3 RandomUpperDirection(std::mt19937* rng);

// Whether one of the fit's warnings begins with `prefix`.
bool HasWarning(const fitters::FitResult& fit, const std::string& prefix);
// The fit's warnings, each on a line of its own, for a failed assertion's message.
std::string AllWarnings(const fitters::FitResult& fit);

struct CommandResult {
  int exit_status = -1;  // -1 when killed by a signal
  std::string out;       // stdout
  std::string err;       // stderr
};
// Runs a shell command line, no stdin, capturing stdout and stderr.
CommandResult RunCommand(const std::string& command);
// Runs the brdf binary with `arguments` (a shell-quoted string), no stdin.
CommandResult RunBrdf(const std::string& arguments);

// Scattered samples of `model` (native CSV): wi at theta_i = 0, 10, ..., 70 deg in the plane
// phi = 180 deg, wo on the grid of theta_o in [0, 80) deg and phi_o in [0, 180] deg with the
// steps given (in degrees).
Measurement ScatteredSamplesOf(const Model& model, double theta_o_step = 5.0,
                               double phi_o_step = 10.0);

}  // namespace brdf::testing
