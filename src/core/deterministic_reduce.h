// Parallel reductions whose result does not depend on the number of threads or on how the
// scheduler happened to split the work. tbb::parallel_reduce splits a range where threads steal
// it, so a floating-point sum differs in its last bits from run to run and between thread counts;
// here the range is cut into chunks of a fixed size and the partial results are combined in a
// fixed tree (tbb::parallel_deterministic_reduce with a simple partitioner). The same inputs
// then give the same bits with 1 or 64 threads.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/partitioner.h>

#include <cstdint>
#include <utility>

namespace brdf {

// Reduces [0, count): `chunk(begin, end, partial)` folds one chunk of at most `grain` indices
// into `partial` (it starts from `identity`) and returns it; `combine(left, right)` joins two
// partial results, always left before right.
template <typename Value, typename Chunk, typename Combine>
Value DeterministicReduce(int64_t count, int64_t grain, const Value& identity, const Chunk& chunk,
                          const Combine& combine) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int64_t>(0, count, grain), identity,
      [&](const tbb::blocked_range<int64_t>& range, Value partial) {
        return chunk(range.begin(), range.end(), std::move(partial));
      },
      combine, tbb::simple_partitioner());
}

}  // namespace brdf
