// Progress of a long run on stderr (DESIGN §3): shown only when stderr is a terminal and the
// user did not ask for --quiet (under mpirun: when mpirun's output is a terminal); redrawn at
// most ten times a second; thread-safe.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace brdf {

class Progress {
 public:
  // `quiet` comes from the command's --quiet flag.
  Progress(std::string label, int64_t total, bool quiet);
  ~Progress();  // clears the line
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Adds `done` finished units (from any thread).
  void Advance(int64_t done = 1);
  bool enabled() const { return enabled_; }

 private:
  void Draw(int64_t done);

  std::string label_;
  int64_t total_;
  bool enabled_;
  std::atomic<int64_t> done_{0};
  std::mutex draw_mutex_;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace brdf
