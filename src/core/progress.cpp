#include "core/progress.h"

#include <unistd.h>

#include <cstdio>

#include "core/parallel_ranks.h"

namespace brdf {
namespace {

// A terminal to draw on. Under mpirun a rank's stderr is a pipe to mpirun even when mpirun's is
// a terminal; OpenMPI then gives the rank's stdout a pseudo-terminal, so that one tells.
bool OnTerminal() {
  if (::isatty(STDERR_FILENO)) return true;
  return ranks::LaunchedByMpi() && ::isatty(STDOUT_FILENO);
}

}  // namespace

Progress::Progress(std::string label, int64_t total, bool quiet)
    : label_(std::move(label)),
      total_(total),
      enabled_(!quiet && OnTerminal()),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() {
  if (enabled_) std::fprintf(stderr, "\r\033[K");
}

void Progress::Advance(int64_t done) {
  const int64_t now_done = done_.fetch_add(done) + done;
  if (!enabled_) return;
  Draw(now_done);
}

void Progress::Draw(int64_t done) {
  std::unique_lock<std::mutex> lock(draw_mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  const auto now = std::chrono::steady_clock::now();
  if (done < total_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const double seconds = std::chrono::duration<double>(now - start_).count();
  const double fraction = total_ > 0 ? static_cast<double>(done) / total_ : 1.0;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(fraction * kWidth);
  std::fprintf(stderr, "\r%s [%.*s%*s] %3.0f%% %.1fs\033[K", label_.c_str(), filled,
               "##############################", kWidth - filled, "", 100.0 * fraction, seconds);
  std::fflush(stderr);
}

}  // namespace brdf
