// Atomic outputs (DESIGN §3): a run killed with SIGKILL while it computes or writes leaves the
// previous file untouched or a complete new one — never a half-written file.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <thread>
#include <vector>

#include "test_util.h"

namespace brdf {
namespace {

using testing::ScratchDir;

// Starts `brdf` with `arguments`, kills it with SIGKILL after `delay_ms`, and reaps it.
void RunAndKill(const std::vector<std::string>& arguments, int delay_ms) {
  std::vector<char*> argv;
  std::string binary = BRDFKIT_BINARY;
  argv.push_back(binary.data());
  std::vector<std::string> copies = arguments;
  for (std::string& argument : copies) argv.push_back(argument.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
}

bool IsCompletePng(const std::string& bytes) {
  static const std::string kSignature("\x89PNG\r\n\x1a\n", 8);
  return bytes.size() > 20 && bytes.compare(0, 8, kSignature) == 0 &&
         bytes.find("IEND") == bytes.size() - 8;
}

bool IsCompleteCsv(const std::string& bytes) {
  return bytes.rfind("# brdfkit measurement v1", 0) == 0 && !bytes.empty() && bytes.back() == '\n';
}

TEST(AtomicOutput, KilledRenderLeavesOldOrCompleteFile) {
  ScratchDir dir;
  const std::string out = dir.File("sphere.png");
  for (int delay_ms : {50, 200, 500, 1000}) {
    const std::string previous = "previous contents\n";
    dir.Write("sphere.png", previous);
    RunAndKill({"render", "blinn-phong:rho_s=0.5:m=100", "--env", "uniform:1", "--size", "1024",
                "--spp", "16", "--quiet", "--out", out},
               delay_ms);
    const std::string now = testing::ReadFileText(out);
    EXPECT_TRUE(now == previous || IsCompletePng(now))
        << "killed after " << delay_ms << " ms: " << now.size() << " bytes";
  }
}

TEST(AtomicOutput, KilledMeasureLeavesOldOrCompleteFile) {
  ScratchDir dir;
  const std::string out = dir.File("large.csv");
  for (int delay_ms : {50, 200, 500, 1000}) {
    const std::string previous = "# brdfkit measurement v1\nprevious\n";
    dir.Write("large.csv", previous);
    RunAndKill({"measure", "--sample", "model:phong:n=20", "--schedule",
                "hemisphere:theta_i_step=3:theta_o_step=1:phi_o_step=1", "--quiet", "--out", out},
               delay_ms);
    const std::string now = testing::ReadFileText(out);
    EXPECT_TRUE(now == previous || (IsCompleteCsv(now) && now.size() > 1000000))
        << "killed after " << delay_ms << " ms: " << now.size() << " bytes";
  }
}

}  // namespace
}  // namespace brdf
