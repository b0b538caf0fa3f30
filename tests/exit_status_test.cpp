// core/errors.h: ExitStatus is the one map from an error to the process's exit status
// (DESIGN §3), used by main() and by the ranks of a distributed step alike.
#include <gtest/gtest.h>

#include <exception>
#include <new>
#include <stdexcept>
#include <string>

#include "core/errors.h"
#include "core/parallel_ranks.h"

namespace brdf {
namespace {

template <typename E>
int StatusOf(const E& error, std::string* message) {
  return ExitStatus(std::make_exception_ptr(error), message);
}

TEST(ExitStatus, BadUsageAndBadInputAreTwo) {
  std::string message;
  EXPECT_EQ(StatusOf(UsageError("unknown model 'x'"), &message), 2);
  EXPECT_EQ(message, "unknown model 'x'");
  EXPECT_EQ(StatusOf(ParseError("a.astm", 7, "not a number"), &message), 2);
  EXPECT_EQ(message, "a.astm: line 7: not a number");
  EXPECT_EQ(StatusOf(ByteError("a.binary", 12, "truncated"), &message), 2);
  EXPECT_EQ(message, "a.binary: byte 12: truncated");
  EXPECT_EQ(StatusOf(OutputError("out/x.png", "cannot write"), &message), 2);
}

TEST(ExitStatus, AFailedComputationIsThree) {
  std::string message;
  EXPECT_EQ(StatusOf(ComputeError("the fit did not converge"), &message), 3);
  EXPECT_EQ(message, "the fit did not converge");
}

TEST(ExitStatus, AnotherRanksFailureKeepsItsStatus) {
  std::string message;
  EXPECT_EQ(StatusOf(ranks::RankFailure("rank 1: did not converge", 3), &message), 3);
  EXPECT_EQ(message, "rank 1: did not converge");
  EXPECT_EQ(StatusOf(ranks::RankFailure("rank 1: internal error: x", 1), &message), 1);
}

TEST(ExitStatus, AnythingElseIsAnInternalErrorOne) {
  std::string message;
  EXPECT_EQ(StatusOf(std::bad_alloc(), &message), 1);
  EXPECT_EQ(message, "out of memory");
  EXPECT_EQ(StatusOf(std::out_of_range("vector::at"), &message), 1);
  EXPECT_EQ(message, "internal error: vector::at");
  EXPECT_EQ(StatusOf(42, &message), 1);
  EXPECT_EQ(message, "internal error: unknown exception");
}

}  // namespace
}  // namespace brdf
