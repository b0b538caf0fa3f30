// Past one machine (DESIGN §11): `brdf measure` and `brdf batch` under mpirun write the same
// bytes for 2 ranks, for 1 rank and without mpirun, and a rank that meets bad input fails the
// job with its rank and file named and no output left behind. The work-split layer itself
// (core/parallel_ranks.h) is checked in-process on one rank.
#include <gtest/gtest.h>

#include <atomic>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/errors.h"
#include "core/parallel_ranks.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::CommandResult;
using testing::DataPath;
using testing::ReadFileText;
using testing::RunBrdf;
using testing::RunCommand;
using testing::ScratchDir;

// mpirun, quoted for the shell ("" in a build without MPI, whose tests skip).
std::string Mpirun() {
#ifdef BRDFKIT_MPIEXEC
  return std::string("'") + BRDFKIT_MPIEXEC + "' --oversubscribe --allow-run-as-root";
#else
  return "";
#endif
}

// `brdf ARGUMENTS` under mpirun with `ranks` processes (as root too, on one core or two).
CommandResult RunUnderMpi(int ranks, const std::string& arguments) {
  return RunCommand(Mpirun() + " -n " + std::to_string(ranks) + " '" + BRDFKIT_BINARY + "' " +
                    arguments);
}

#ifdef BRDFKIT_MPIEXEC
#define SKIP_WITHOUT_MPI()
#else
#define SKIP_WITHOUT_MPI() GTEST_SKIP() << "built without MPI (BRDFKIT_MPI=OFF): nothing to launch"
#endif

// Runs `measure COMMON --out FILE` without mpirun, with 1 rank and with 2, and expects three
// identical, non-trivial files.
void ExpectSameMeasurement(const std::string& common, const std::string& expected_text) {
  ScratchDir dir;
  const CommandResult alone = RunBrdf(common + " --out " + dir.File("alone.csv"));
  ASSERT_EQ(alone.exit_status, 0) << alone.err;
  const CommandResult one = RunUnderMpi(1, common + " --out " + dir.File("one.csv"));
  ASSERT_EQ(one.exit_status, 0) << one.err;
  const CommandResult two = RunUnderMpi(2, common + " --out " + dir.File("two.csv"));
  ASSERT_EQ(two.exit_status, 0) << two.err;
  const std::string bytes = ReadFileText(dir.File("alone.csv"));
  EXPECT_GT(bytes.size(), 2000u);
  EXPECT_NE(bytes.find(expected_text), std::string::npos);
  EXPECT_TRUE(bytes == ReadFileText(dir.File("one.csv"))) << "1 rank differs from no MPI";
  EXPECT_TRUE(bytes == ReadFileText(dir.File("two.csv"))) << "2 ranks differ from no MPI";
  EXPECT_EQ(dir.CountEntries(), 3);  // the three outputs and no temporary left over
}

TEST(Mpi, AnalyticMeasurementIsTheSameForAnyRankCount) {
  SKIP_WITHOUT_MPI();
  ExpectSameMeasurement(
      "measure --quiet --seed 11 --sample model:blinn-phong:rho_s=0.3:m=2000 "
      "--schedule hemisphere:theta_i_step=15:theta_o_step=10:phi_o_step=10",
      "# sample: model:blinn-phong");
}

TEST(Mpi, TracedSurfaceMeasurementIsTheSameForAnyRankCount) {
  SKIP_WITHOUT_MPI();
  ScratchDir dir;
  const std::string surface = dir.Write(
      "rough.json",
      R"({"heightfield": {"kind": "v-grooves", "rms_slope": 0.5, "resolution": 32, "period": 8},
          "base": "lambert:rho_d=0.7", "rays_per_incidence": 20000})");
  ExpectSameMeasurement(
      "measure --quiet --seed 4 --sample surface:" + surface + " --schedule inplane:step=30",
      "ray traced with Embree");
}

TEST(Mpi, SphereMeasurementIsTheSameForAnyRankCount) {
  SKIP_WITHOUT_MPI();
  ScratchDir dir;
  const std::string instrument =
      dir.Write("camera.json", R"({"camera": {"resolution": 48, "sphere_segments": 64}})");
  ExpectSameMeasurement("measure --quiet --seed 9 --sample sphere:phong:n=50 --instrument " +
                            instrument + " --schedule inplane:step=30",
                        "rasterized at 48x48");
}

// A rank whose input is broken (here rank 1 is given a surface file that does not parse, as a
// node whose copy is damaged would be): non-zero exit, the rank and the file named, no output.
TEST(Mpi, RankWithBadInputFailsTheMeasurementCleanly) {
  SKIP_WITHOUT_MPI();
  ScratchDir dir;
  const std::string good = dir.Write(
      "good.json", R"({"heightfield": {"kind": "v-grooves", "resolution": 16, "period": 8},
                      "rays_per_incidence": 2000})");
  const std::string bad = dir.Write("bad.json", R"({"heightfield": {"kind": "fractal"}})");
  const std::string out = dir.File("out.csv");
  const std::string common = " measure --quiet --schedule inplane:step=30 --out " + out;
  // OpenMPI's MPMD form: rank 0 runs the first command line, rank 1 the second.
  const CommandResult result = RunCommand(
      Mpirun() + " -n 1 '" + BRDFKIT_BINARY + "'" + common + " --sample surface:" + good +
      " : -n 1 '" + BRDFKIT_BINARY + "'" + common + " --sample surface:" + bad);
  EXPECT_EQ(result.exit_status, 2) << result.err;
  EXPECT_NE(result.err.find("rank 1: " + bad), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("heightfield.kind"), std::string::npos) << result.err;
  EXPECT_EQ(dir.CountEntries(), 2) << "an output (or a temporary) was left behind";
}

// A computation that fails on one rank while the others work (rank 1's detector is so noisy
// that its reference reading averages below zero for seed 1, caught when its first incidence
// is calibrated): the job exits with status 3 (rank 0's), the rank named once, no output.
TEST(Mpi, RankWhoseComputationFailsStopsTheJob) {
  SKIP_WITHOUT_MPI();
  ScratchDir dir;
  const std::string noisy =
      dir.Write("noisy.json", R"({"detector": {"photons": 1, "read_noise": 1e6}})");
  const std::string out = dir.File("out.csv");
  const std::string common =
      " measure --quiet --seed 1 --sample model:lambert --schedule inplane:step=10 --out " + out;
  // Alone, the noisy instrument fails the same way: the failure is the computation's.
  const CommandResult alone = RunBrdf(common + " --instrument " + noisy);
  ASSERT_EQ(alone.exit_status, 3) << alone.err;
  const CommandResult result =
      RunCommand(Mpirun() + " -n 1 '" + BRDFKIT_BINARY + "'" + common + " : -n 1 '" +
                 BRDFKIT_BINARY + "'" + common + " --instrument " + noisy);
  EXPECT_EQ(result.exit_status, 3) << result.err;
  const std::string line = "rank 1: the reference reading has no signal";
  const size_t first = result.err.find(line);
  EXPECT_NE(first, std::string::npos) << result.err;
  EXPECT_EQ(result.err.find(line, first + 1), std::string::npos) << "reported twice";
  EXPECT_EQ(dir.CountEntries(), 1) << "an output (or a temporary) was left behind";
}

// A table or report without its wall-clock fields ("time_s"), which alone differ between runs.
std::string WithoutTimes(const std::string& text, bool csv) {
  std::istringstream lines(text);
  std::string line, kept;
  int time_column = -1;
  while (std::getline(lines, line)) {
    if (!csv) {
      if (line.find("\"time_s\"") == std::string::npos) kept += line + "\n";
      continue;
    }
    // The table's fields hold no quoted commas before time_s except in params, so split with
    // quoting in mind.
    std::vector<std::string> fields(1);
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      if (c == ',' && !quoted) {
        fields.emplace_back();
      } else {
        fields.back() += c;
      }
    }
    if (time_column < 0) {
      for (size_t k = 0; k < fields.size(); ++k) {
        if (fields[k] == "time_s") time_column = static_cast<int>(k);
      }
    }
    EXPECT_GE(time_column, 0) << "no time_s column";
    if (time_column >= 0 && time_column < static_cast<int>(fields.size())) {
      fields.erase(fields.begin() + time_column);
    }
    for (const std::string& field : fields) kept += field + ",";
    kept += "\n";
  }
  return kept;
}

struct BatchRun {
  CommandResult result;
  std::string table;
  std::vector<std::string> reports;
};

const std::vector<std::string> kReportNames = {"cayman.json", "krylon_blue.json", "mystique.json"};

BatchRun RunBatch(int ranks, const std::string& dir, const std::string& extra = "") {
  const std::string arguments = "batch '" + DataPath("cornell-astm/cayman.astm") + "' '" +
                                DataPath("cornell-astm/krylon_blue.astm") + "' '" +
                                DataPath("cornell-pbrt-v2/mystique.brdf") +
                                "' --model auto --max-samples 2000 --quiet --out '" + dir + "'" +
                                extra;
  BatchRun run;
  run.result = ranks == 0 ? RunBrdf(arguments) : RunUnderMpi(ranks, arguments);
  run.table = ReadFileText(dir + "/table.csv");
  for (const std::string& name : kReportNames)
    run.reports.push_back(ReadFileText(dir + "/" + name));
  return run;
}

TEST(Mpi, BatchTableAndReportsAreTheSameForAnyRankCount) {
  SKIP_WITHOUT_MPI();
  ScratchDir dir;
  const BatchRun alone = RunBatch(0, dir.File("alone"));
  ASSERT_EQ(alone.result.exit_status, 0) << alone.result.err;
  const BatchRun one = RunBatch(1, dir.File("one"));
  ASSERT_EQ(one.result.exit_status, 0) << one.result.err;
  const BatchRun two = RunBatch(2, dir.File("two"));
  ASSERT_EQ(two.result.exit_status, 0) << two.result.err;
  // One file at a time, each fit on every thread: the same numbers again.
  const BatchRun sequential = RunBatch(0, dir.File("sequential"), " --concurrency fit");
  ASSERT_EQ(sequential.result.exit_status, 0) << sequential.result.err;

  // Rows in command-line order, one per file, each with its report and selection.
  EXPECT_EQ(testing::CountLines(alone.table), 4) << alone.table;
  EXPECT_NE(alone.table.find("cayman.astm,cayman.json,ok,"), std::string::npos) << alone.table;
  EXPECT_LT(alone.table.find("cayman.astm"), alone.table.find("krylon_blue.astm"));
  EXPECT_LT(alone.table.find("krylon_blue.astm"), alone.table.find("mystique.brdf"));
  const std::string expected = WithoutTimes(alone.table, true);
  EXPECT_EQ(expected, WithoutTimes(one.table, true));
  EXPECT_EQ(expected, WithoutTimes(two.table, true));
  EXPECT_EQ(expected, WithoutTimes(sequential.table, true));
  for (size_t k = 0; k < kReportNames.size(); ++k) {
    ASSERT_NE(alone.reports[k].find("\"selection\""), std::string::npos) << kReportNames[k];
    const std::string report = WithoutTimes(alone.reports[k], false);
    EXPECT_EQ(report, WithoutTimes(one.reports[k], false)) << kReportNames[k];
    EXPECT_EQ(report, WithoutTimes(two.reports[k], false)) << kReportNames[k];
    EXPECT_EQ(report, WithoutTimes(sequential.reports[k], false)) << kReportNames[k];
  }
}

// A bad file among good ones: its row says why, it gets no report, the good files still get
// theirs, and the job exits 2 naming the file (and, under mpirun, the rank that read it).
TEST(Mpi, BatchWithABadFileReportsItAndExitsTwo) {
  SKIP_WITHOUT_MPI();
  ScratchDir dir;
  const std::string bad = dir.Write("broken.csv", "# brdfkit measurement v1\ntheta_i,phi_i\n1,2\n");
  const std::string out = dir.File("out");
  const CommandResult result =
      RunUnderMpi(2, "batch '" + DataPath("cornell-astm/cayman.astm") + "' '" + bad +
                         "' --model lambert --quiet --out '" + out + "'");
  EXPECT_EQ(result.exit_status, 2) << result.err;
  EXPECT_NE(result.err.find(bad), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("(rank "), std::string::npos) << result.err;
  EXPECT_EQ(ReadFileText(out + "/broken.json"), "");
  EXPECT_NE(ReadFileText(out + "/cayman.json").find("\"model\": \"lambert\""), std::string::npos);
  const std::string table = ReadFileText(out + "/table.csv");
  EXPECT_NE(table.find("broken.csv,,error,"), std::string::npos) << table;
  EXPECT_NE(table.find("cayman.json,ok,lambert,true"), std::string::npos) << table;
}

// Without mpirun: two inputs sharing a stem get their extension in the report name, the JSON
// table is typed, and a missing file is a row of its own and exit status 2.
TEST(BatchCli, NamesReportsByFileAndKeepsGoingPastABadFile) {
  ScratchDir dir;
  const std::string out = dir.File("out");
  const CommandResult result =
      RunBrdf("batch '" + DataPath("cornell-astm/cayman.astm") + "' '" +
              DataPath("cornell-pbrt-v2/cayman.brdf") + "' '" + dir.File("missing.astm") +
              "' --model lambert --quiet --json --out '" + out + "'");
  EXPECT_EQ(result.exit_status, 2) << result.err;
  EXPECT_NE(result.err.find(dir.File("missing.astm")), std::string::npos) << result.err;
  const nlohmann::json table = nlohmann::json::parse(result.out);
  ASSERT_EQ(table.size(), 3u);
  EXPECT_EQ(table[0]["report"], "cayman.astm.json");
  EXPECT_EQ(table[1]["report"], "cayman.brdf.json");
  EXPECT_EQ(table[2]["status"], "error");
  // The ASTM file and its pbrt-v2 copy hold the same numbers: the same fit.
  EXPECT_TRUE(table[0]["converged"].get<bool>());
  EXPECT_EQ(table[0]["params"], table[1]["params"]);
  EXPECT_GT(table[0]["samples"].get<int>(), 1000);
  const nlohmann::json report = nlohmann::json::parse(ReadFileText(out + "/cayman.astm.json"));
  EXPECT_EQ(report["model_string"], table[0]["params"]);
  EXPECT_EQ(ReadFileText(out + "/missing.json"), "");
  // Two inputs with the same name in different directories cannot both be reported.
  const CommandResult clash =
      RunBrdf("batch '" + DataPath("cornell-astm/cayman.astm") + "' '" +
              DataPath("cornell-astm/cayman.astm") + "' --out '" + dir.File("clash") + "'");
  EXPECT_EQ(clash.exit_status, 2);
  EXPECT_NE(clash.err.find("would both write cayman.astm.json"), std::string::npos) << clash.err;
}

// The layer on one rank: every item computed once and collected once, on the calling thread;
// an item's error reaches the caller with its own type (and so its exit status).
TEST(ParallelRanks, OneRankCollectsEveryItemOnceOnTheCallingThread) {
  ASSERT_EQ(ranks::Size(), 1);
  const size_t count = 200;
  std::vector<double> costs;
  for (size_t k = 0; k < count; ++k) costs.push_back(static_cast<double>((k * 37) % 101));
  const ranks::WorkPlan plan = ranks::LargestFirst(costs);
  ASSERT_EQ(plan.order.size(), count);
  for (size_t k = 1; k < count; ++k) EXPECT_GE(costs[plan.order[k - 1]], costs[plan.order[k]]);
  std::atomic<int> prepared{0};
  std::multiset<size_t> seen;
  const std::thread::id caller = std::this_thread::get_id();
  ranks::Distribute(
      plan, [&]() { ++prepared; }, [](size_t item) { return std::to_string(item * item); },
      [&](size_t item, int rank, std::string&& result) {
        EXPECT_EQ(std::this_thread::get_id(), caller);
        EXPECT_EQ(rank, 0);
        EXPECT_EQ(result, std::to_string(item * item));
        seen.insert(item);
      });
  EXPECT_EQ(prepared.load(), 1);
  ASSERT_EQ(seen.size(), count);
  for (size_t k = 0; k < count; ++k) EXPECT_EQ(seen.count(k), 1u) << k;

  EXPECT_THROW(ranks::Distribute(
                   ranks::RoundRobin(50), []() {},
                   [](size_t item) -> std::string {
                     if (item == 17) throw ComputeError("item 17 diverged");
                     return "";
                   },
                   [](size_t, int, std::string&&) {}),
               ComputeError);
  EXPECT_THROW(ranks::Distribute(
                   ranks::RoundRobin(5), []() { throw InputError("x.json", "broken"); },
                   [](size_t) { return std::string(); }, [](size_t, int, std::string&&) {}),
               InputError);
}

}  // namespace
}  // namespace brdf
