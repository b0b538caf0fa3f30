// Distribute within one process: a failing item stops the run between items, never inside one.
#include "core/parallel_ranks.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/errors.h"

namespace brdf {
namespace {

TEST(Distribute, AFailingItemLetsTheRunningOnesFinishTheirNestedLoops) {
  // Item 0 fails while item 1 is inside a parallel loop of its own. Cancelling TBB's group
  // would cut that loop short and item 1 would carry on with part of its work undone (how a
  // failure on one MPI rank crashed another); an item that has started must finish whole.
  constexpr size_t kIterations = 200;
  std::atomic<bool> inner_started{false};
  std::atomic<int> incomplete{0}, complete{0};
  const auto compute = [&](size_t item) -> std::string {
    if (item == 0) {
      // Fail once item 1 is inside its loop (or after 2 s, when the items run one by one).
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
      while (!inner_started && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::yield();
      }
      throw ComputeError("item 0 fails");
    }
    std::vector<char> written(kIterations, 0);
    tbb::parallel_for(size_t{0}, kIterations, [&](size_t k) {
      inner_started = true;
      std::this_thread::sleep_for(std::chrono::microseconds(500));
      written[k] = 1;
    });
    for (char w : written) {
      if (!w) {
        ++incomplete;
        return "incomplete";
      }
    }
    ++complete;
    return "complete";
  };
  std::vector<std::string> collected;
  try {
    ranks::Distribute(
        ranks::RoundRobin(2), [] {}, compute,
        [&](size_t, int, std::string&& result) { collected.push_back(result); });
    FAIL() << "the failure of item 0 did not reach the caller";
  } catch (const ComputeError& error) {
    EXPECT_NE(std::string(error.what()).find("item 0 fails"), std::string::npos) << error.what();
  }
  EXPECT_EQ(incomplete, 0) << "an item's nested loop was cut short";
  if (inner_started) {
    EXPECT_EQ(complete, 1);  // item 1 started before item 0 failed, and finished whole
  } else {
    EXPECT_EQ(complete, 0);  // the items ran one by one: item 1 was not started after the failure
  }
}

TEST(Distribute, EveryItemIsCollectedOnceWhenNothingFails) {
  constexpr size_t kItems = 64;
  std::vector<int> seen(kItems, 0);
  ranks::Distribute(
      ranks::RoundRobin(kItems), [] {},
      [](size_t item) {
        std::atomic<size_t> sum{0};
        tbb::parallel_for(size_t{0}, item + 1, [&](size_t k) { sum += k; });
        return std::to_string(sum.load());
      },
      [&](size_t item, int rank, std::string&& result) {
        EXPECT_EQ(rank, 0);
        EXPECT_EQ(result, std::to_string(item * (item + 1) / 2));
        ++seen[item];
      });
  for (size_t item = 0; item < kItems; ++item) EXPECT_EQ(seen[item], 1) << item;
}

}  // namespace
}  // namespace brdf
