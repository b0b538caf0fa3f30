#include "core/parallel_ranks.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <mutex>
#include <new>
#include <thread>
#include <utility>

#ifdef BRDFKIT_HAVE_MPI
#include <mpi.h>
#endif

namespace brdf::ranks {
namespace {

int g_rank = 0;
int g_size = 1;
[[maybe_unused]] bool g_active = false;  // MPI_Init was called (only read in an MPI build)
bool g_failed_in_protocol = false;       // the last Distribute failed after every rank agreed

// Message tags; results go to rank 0, stop and outcome come from it.
enum Tag : int { kResult = 1, kDone = 2, kFailed = 3, kStop = 4, kOutcome = 5 };

// A rank's own items, computed on a thread of their own (and TBB's workers under it) while the
// main thread talks to the other ranks. Finished results wait in a queue for the main thread.
//
// A run stops between items, never inside one: cancelling TBB's group would reach the parallel
// loops nested in an item's computation, which then return with part of their work undone, and
// the item would go on with what they never wrote (a failure on another rank crashed this rank
// that way). So an item that has started finishes; the ones not started are skipped; and an
// item's exception is kept here rather than let through TBB, which would cancel the group.
class LocalRun {
 public:
  LocalRun(std::vector<size_t> items, const std::function<std::string(size_t)>& compute,
           bool in_parallel)
      : items_(std::move(items)), compute_(compute) {
    thread_ = std::thread([this, in_parallel]() { Run(in_parallel); });
  }
  ~LocalRun() {
    Cancel();
    thread_.join();
  }
  LocalRun(const LocalRun&) = delete;
  LocalRun& operator=(const LocalRun&) = delete;

  // Moves the finished results into `results`, waiting up to `wait` when there are none yet.
  // Returns true once every item is done (or the run stopped) and nothing is left queued.
  bool Take(std::deque<std::pair<size_t, std::string>>* results, std::chrono::milliseconds wait) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (queue_.empty() && !finished_) {
      ready_.wait_for(lock, wait, [this]() { return !queue_.empty() || finished_; });
    }
    while (!queue_.empty()) {
      results->push_back(std::move(queue_.front()));
      queue_.pop_front();
    }
    return finished_;
  }
  void Cancel() { stop_ = true; }
  // The first exception of an item, once Take returned true.
  std::exception_ptr error() const { return error_; }

 private:
  // Computes one item unless the run has stopped; the first exception stops the run.
  void Finish(size_t item) noexcept {
    if (stop_) return;
    try {
      std::string result = compute_(item);
      if (g_size > 1 && result.size() > static_cast<size_t>(INT_MAX) - sizeof(uint64_t)) {
        throw ComputeError("the result of work item " + std::to_string(item) + " is " +
                           std::to_string(result.size()) +
                           " bytes, above the 2 GiB an MPI message holds; split the work finer");
      }
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.emplace_back(item, std::move(result));
      ready_.notify_one();
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
      stop_ = true;
    }
  }

  void Run(bool in_parallel) {
    if (in_parallel) {
      tbb::parallel_for(
          tbb::blocked_range<size_t>(0, items_.size(), 1),
          [this](const tbb::blocked_range<size_t>& range) {
            for (size_t k = range.begin(); k != range.end(); ++k) Finish(items_[k]);
          },
          tbb::simple_partitioner());
    } else {
      for (size_t item : items_) Finish(item);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    finished_ = true;
    ready_.notify_one();
  }

  const std::vector<size_t> items_;
  const std::function<std::string(size_t)>& compute_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::pair<size_t, std::string>> queue_;
  bool finished_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

std::vector<size_t> ItemsOf(const WorkPlan& plan, int rank) {
  std::vector<size_t> items;
  for (size_t item : plan.order) {
    if (plan.owner[item] == rank) items.push_back(item);
  }
  return items;
}

#ifdef BRDFKIT_HAVE_MPI
// Sends and waits for the send to complete, sleeping rather than spinning (see WaitForMessage):
// a large result waits for rank 0, which looks for messages every few milliseconds.
void Send(int destination, Tag tag, const std::string& bytes) {
  MPI_Request request;
  MPI_Isend(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, destination, tag,
            MPI_COMM_WORLD, &request);
  int complete = 0;
  while (true) {
    MPI_Test(&request, &complete, MPI_STATUS_IGNORE);
    if (complete) return;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}

// Receives the message `status` announced (from MPI_Probe or MPI_Iprobe).
std::string Receive(const MPI_Status& status) {
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  std::string bytes(static_cast<size_t>(count), '\0');
  MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  return bytes;
}

// Waits for the next message from `source` without spinning: OpenMPI's blocking probe polls
// a core at full speed, which on a node shared with the working threads (or an oversubscribed
// one) takes their time. A millisecond's sleep between looks costs nothing by comparison.
MPI_Status WaitForMessage(int source) {
  MPI_Status status;
  int flag = 0;
  while (true) {
    MPI_Iprobe(source, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
    if (flag) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// A status and a message in one buffer: 4 bytes of status, then the text.
std::string PackStatus(int32_t status, const std::string& message) {
  std::string bytes(sizeof(status), '\0');
  std::memcpy(bytes.data(), &status, sizeof(status));
  return bytes + message;
}
int32_t UnpackStatus(const std::string& bytes, std::string* message) {
  int32_t status = 1;
  if (bytes.size() >= sizeof(status)) std::memcpy(&status, bytes.data(), sizeof(status));
  *message = bytes.size() > sizeof(status) ? bytes.substr(sizeof(status)) : "";
  return status;
}

// Every rank takes rank 0's plan, so that a cost that reads differently elsewhere (a file seen
// through another node's file system) cannot leave an item to nobody.
void SharePlan(WorkPlan* plan) {
  uint64_t count = plan->order.size();
  MPI_Bcast(&count, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  std::vector<uint64_t> order(plan->order.begin(), plan->order.end());
  std::vector<int> owner = plan->owner;
  order.resize(count);
  owner.resize(count);
  MPI_Bcast(order.data(), static_cast<int>(count), MPI_UINT64_T, 0, MPI_COMM_WORLD);
  MPI_Bcast(owner.data(), static_cast<int>(count), MPI_INT, 0, MPI_COMM_WORLD);
  plan->order.assign(order.begin(), order.end());
  plan->owner = owner;
}

// Ranks other than 0: compute, send each result as it finishes, report done or failed, then
// wait for the job's outcome from rank 0.
void RunWorker(const WorkPlan& plan, const std::function<void()>& prepare,
               const std::function<std::string(size_t)>& compute, bool in_parallel) {
  std::exception_ptr error;
  try {
    prepare();
  } catch (...) {
    error = std::current_exception();
  }
  if (!error) {
    LocalRun local(ItemsOf(plan, g_rank), compute, in_parallel);
    std::deque<std::pair<size_t, std::string>> results;
    bool finished = false, stopped = false;
    while (!finished) {
      finished = local.Take(&results, std::chrono::milliseconds(2));
      for (std::pair<size_t, std::string>& result : results) {
        if (stopped) continue;
        const uint64_t item = result.first;
        std::string message(sizeof(item), '\0');
        std::memcpy(message.data(), &item, sizeof(item));
        message += result.second;
        std::string().swap(result.second);
        Send(0, kResult, message);
      }
      results.clear();
      int flag = 0;
      MPI_Iprobe(0, kStop, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
      if (flag && !stopped) {
        stopped = true;
        local.Cancel();
      }
    }
    error = local.error();
  }
  if (error) {
    std::string message;
    const int status = ExitStatus(error, &message);
    Send(0, kFailed, PackStatus(status, message));
  } else {
    Send(0, kDone, "");
  }
  while (true) {
    const MPI_Status probe = WaitForMessage(0);
    const std::string bytes = Receive(probe);
    if (probe.MPI_TAG != kOutcome) continue;  // a stop that crossed our report
    std::string message;
    const int status = UnpackStatus(bytes, &message);
    if (status != 0) {
      g_failed_in_protocol = true;
      throw RankFailure(message, status);
    }
    return;
  }
}
#endif

// Rank 0 (and a run without MPI): computes its own items, collects everyone's results, and
// tells the other ranks the outcome.
void RunRoot(const WorkPlan& plan, const std::function<void()>& prepare,
             const std::function<std::string(size_t)>& compute,
             const std::function<void(size_t, int, std::string&&)>& collect, bool in_parallel) {
  struct Failure {
    bool failed = false;
    int rank = 0;
    int status = 0;
    std::string message;
    std::exception_ptr original;
  } failure;
  std::vector<char> done(g_size, 0);
  done[0] = 1;
  int remaining = g_size - 1;
  std::unique_ptr<LocalRun> local;

  auto fail = [&](int rank, int status, const std::string& message, std::exception_ptr original) {
    if (failure.failed) return;
    failure = {true, rank, status, message, std::move(original)};
    if (local) local->Cancel();
#ifdef BRDFKIT_HAVE_MPI
    for (int r = 1; r < g_size; ++r) {
      if (!done[r]) Send(r, kStop, "");
    }
#endif
  };
  auto fail_here = [&](std::exception_ptr error) {
    std::string message;
    const int status = ExitStatus(error, &message);
    fail(0, status, message, error);
  };
  auto deliver = [&](size_t item, int rank, std::string&& result) {
    if (failure.failed) return;
    try {
      collect(item, rank, std::move(result));
    } catch (...) {
      fail_here(std::current_exception());
    }
  };

  try {
    prepare();
  } catch (...) {
    fail_here(std::current_exception());
  }
  if (!failure.failed) local = std::make_unique<LocalRun>(ItemsOf(plan, 0), compute, in_parallel);
  bool local_finished = local == nullptr;
  std::deque<std::pair<size_t, std::string>> results;

#ifdef BRDFKIT_HAVE_MPI
  auto handle = [&](const MPI_Status& status) {
    std::string bytes = Receive(status);
    const int source = status.MPI_SOURCE;
    if (status.MPI_TAG == kResult) {
      uint64_t item = 0;
      std::memcpy(&item, bytes.data(), sizeof(item));
      deliver(static_cast<size_t>(item), source, bytes.substr(sizeof(item)));
      return;
    }
    if (!done[source]) {
      done[source] = 1;
      --remaining;
    }
    if (status.MPI_TAG == kFailed) {
      std::string message;
      const int exit_status = UnpackStatus(bytes, &message);
      fail(source, exit_status, message, nullptr);
    }
  };
#endif

  while (!local_finished || remaining > 0) {
    if (!local_finished) {
      // With other ranks to listen to, look up every 2 ms; alone, sleep until a result is ready.
      const auto wait = std::chrono::milliseconds(remaining > 0 ? 2 : 1000);
      local_finished = local->Take(&results, wait);
      for (std::pair<size_t, std::string>& result : results) {
        deliver(result.first, 0, std::move(result.second));
      }
      results.clear();
      if (local_finished && local->error()) fail_here(local->error());
    }
#ifdef BRDFKIT_HAVE_MPI
    while (remaining > 0) {
      MPI_Status status;
      if (local_finished) {
        status = WaitForMessage(MPI_ANY_SOURCE);
      } else {
        int flag = 0;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
        if (!flag) break;
      }
      handle(status);
    }
#endif
  }
  local.reset();

  std::string message = failure.message;
  if (failure.failed && g_size > 1)
    message = "rank " + std::to_string(failure.rank) + ": " + message;
#ifdef BRDFKIT_HAVE_MPI
  for (int r = 1; r < g_size; ++r) {
    Send(r, kOutcome, PackStatus(failure.failed ? failure.status : 0, message));
  }
#endif
  if (!failure.failed) return;
  g_failed_in_protocol = true;
  if (g_size == 1 && failure.original) std::rethrow_exception(failure.original);
  throw RankFailure(message, failure.status);
}

}  // namespace

Session::Session(int* argc, char*** argv) {
#ifdef BRDFKIT_HAVE_MPI
  if (!LaunchedByMpi()) return;
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  g_active = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
#else
  (void)argc;
  (void)argv;
#endif
}

Session::~Session() {
#ifdef BRDFKIT_HAVE_MPI
  if (g_active) MPI_Finalize();
#endif
}

void Abort(int exit_status) {
#ifdef BRDFKIT_HAVE_MPI
  if (g_active) MPI_Abort(MPI_COMM_WORLD, exit_status);
#endif
  std::exit(exit_status);
}

bool BuiltWithMpi() {
#ifdef BRDFKIT_HAVE_MPI
  return true;
#else
  return false;
#endif
}

bool LaunchedByMpi() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"}) {
    if (std::getenv(variable) != nullptr) return true;
  }
  return false;
}

int Rank() { return g_rank; }
int Size() { return g_size; }
bool FailedInStep() { return g_failed_in_protocol; }

WorkPlan RoundRobin(size_t count) {
  WorkPlan plan;
  for (size_t item = 0; item < count; ++item) {
    plan.order.push_back(item);
    plan.owner.push_back(static_cast<int>(item % static_cast<size_t>(g_size)));
  }
  return plan;
}

WorkPlan LargestFirst(const std::vector<double>& costs) {
  WorkPlan plan;
  plan.owner.assign(costs.size(), 0);
  for (size_t item = 0; item < costs.size(); ++item) plan.order.push_back(item);
  std::stable_sort(plan.order.begin(), plan.order.end(),
                   [&](size_t a, size_t b) { return costs[a] > costs[b]; });
  std::vector<double> load(g_size, 0.0);
  for (size_t item : plan.order) {
    const int rank = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    plan.owner[item] = rank;
    load[rank] += costs[item];
  }
  return plan;
}

void Distribute(const WorkPlan& plan, const std::function<void()>& prepare,
                const std::function<std::string(size_t)>& compute,
                const std::function<void(size_t, int, std::string&&)>& collect,
                const DistributeOptions& options) {
  g_failed_in_protocol = false;
#ifdef BRDFKIT_HAVE_MPI
  if (g_size > 1) {
    WorkPlan shared = plan;
    SharePlan(&shared);
    if (g_rank != 0) {
      RunWorker(shared, prepare, compute, options.items_in_parallel);
    } else {
      RunRoot(shared, prepare, compute, collect, options.items_in_parallel);
    }
    return;
  }
#endif
  RunRoot(plan, prepare, compute, collect, options.items_in_parallel);
}

}  // namespace brdf::ranks
