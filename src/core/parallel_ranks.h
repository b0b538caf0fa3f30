// Work split across MPI ranks (DESIGN §11). Under `mpirun` (OpenMPI) or `srun` the process is
// one rank of a job; started any other way it is rank 0 of 1 and never touches MPI, so the same
// binary runs alone and `brdf --help` pays nothing for the MPI build.
//
//   ranks::Session session(&argc, &argv);            // in main(), once
//   ranks::Distribute(ranks::RoundRobin(count), prepare, compute, collect);
//
// Distribute runs numbered work items: every rank runs `prepare` (reads its inputs, builds what
// the items share), then `compute` for the items it owns, on its worker threads; each result is
// a byte string handed to rank 0, which calls `collect` on its main thread, one item at a time.
// Rank 0 holds one item in flight per message, never a copy of another rank's share, so the
// results it keeps are the output itself. Nothing in a result may depend on which rank or
// thread computed it: that is what makes the output bytes identical for any rank count.
//
// Failure: an exception in `prepare` or `compute` on any rank (or in `collect` on rank 0) fails
// the job. The other ranks are told to stop, every rank leaves Distribute by throwing, and the
// job's exit status is that of the first error (core/errors.h). Rank 0 throws it with the
// failing rank named ("rank 1: surface.json: ..."); the other ranks throw RankFailure, which
// main() does not print (rank 0 already did). Without MPI the original exception propagates.
#pragma once

#include <cstddef>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "core/errors.h"

namespace brdf::ranks {

// Starts MPI (thread level "funneled": only the main thread calls MPI) when the environment
// says a launcher started this process, and finalizes it on destruction.
class Session {
 public:
  Session(int* argc, char*** argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

bool BuiltWithMpi();
// True when the process was started by mpirun or srun (OMPI_COMM_WORLD_SIZE, PMIX_RANK or
// PMI_RANK is set); does not need MPI to be initialised.
bool LaunchedByMpi();
int Rank();  // 0 when alone
int Size();  // 1 when alone
inline bool IsRoot() { return Rank() == 0; }

// Ends every rank of the job at once with `exit_status` (MPI_Abort), or just this process when
// alone. For an error outside Distribute, where the other ranks may be waiting for this one.
[[noreturn]] void Abort(int exit_status);
// True when the last Distribute failed with every rank informed (the job can end normally).
bool FailedInStep();

// A job that failed in a distributed step, thrown on every rank once all know of it (rank 0
// prints it, the others print nothing for it); exit_status() is the status the whole job exits
// with (core/errors.h, ExitStatus).
class RankFailure : public Error {
 public:
  RankFailure(const std::string& what, int exit_status) : Error(what), exit_status_(exit_status) {}
  int exit_status() const override { return exit_status_; }

 private:
  int exit_status_;
};

// Who runs what: `owner[item]` is the rank of each item; each rank starts its items in the order
// they appear in `order`.
struct WorkPlan {
  std::vector<size_t> order;
  std::vector<int> owner;
};
// Items 0..count-1 dealt in turn (item k to rank k mod Size()): neighbouring items, which cost
// about the same in a schedule (same theta_i band), land on different ranks.
WorkPlan RoundRobin(size_t count);
// Largest first (Graham's LPT rule): items in decreasing cost, each to the rank with the least
// cost dealt so far (ties: lowest rank). Deterministic for given costs and rank count.
WorkPlan LargestFirst(const std::vector<double>& costs);

struct DistributeOptions {
  // Run a rank's items concurrently on its threads (true) or one after the other, each then free
  // to use every thread itself (false).
  bool items_in_parallel = true;
};

void Distribute(const WorkPlan& plan, const std::function<void()>& prepare,
                const std::function<std::string(size_t item)>& compute,
                const std::function<void(size_t item, int rank, std::string&& result)>& collect,
                const DistributeOptions& options = {});

// Raw bytes of trivially copyable values, for packing results.
template <typename T>
void AppendBytes(std::string* bytes, const T* values, size_t count) {
  bytes->append(reinterpret_cast<const char*>(values), count * sizeof(T));
}

// The values AppendBytes packed: as many whole T as `bytes` holds (none from an empty result,
// without handing memcpy a null pointer).
template <typename T>
std::vector<T> ReadValues(const std::string& bytes) {
  std::vector<T> values(bytes.size() / sizeof(T));
  if (!values.empty()) std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

}  // namespace brdf::ranks
