// Hostile input through the command line (docs/reliability.md): headers claiming 10^12
// samples, duplicated or contradictory header keys, devices and directories where a file is
// expected, and outputs that cannot be written, for every reader and every writing command.
// Each must exit with status 2 and one line on stderr naming the file (and the line or byte
// where the file itself is at fault), without a giant allocation and without writing anything.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "test_util.h"

namespace brdf {
namespace {

using testing::DataPath;
using testing::RunBrdf;
using testing::ScratchDir;

// The bytes of a little-endian int32, as MERL and OpenEXR store them.
std::string Int32(int32_t value) {
  std::string bytes(4, '\0');
  for (int k = 0; k < 4; ++k) bytes[k] = static_cast<char>((value >> (8 * k)) & 0xff);
  return bytes;
}

// A file the command line must reject: `command` holds {} where the path goes ({out} becomes
// an output path in the scratch directory); `position` is
// "line", "byte" or "" (no position: the path itself is the problem).
struct HostileInputCase {
  std::string name, contents, command, position;
};

void ExpectRejected(const ScratchDir& dir, const std::string& path, const std::string& command,
                    const std::string& position) {
  const int entries_before = dir.CountEntries();
  const testing::CommandResult result = RunBrdf(command);
  EXPECT_EQ(result.exit_status, 2) << command << "\n" << result.err;
  EXPECT_EQ(testing::CountLines(result.err), 1) << command << "\n" << result.err;
  EXPECT_NE(result.err.find(path), std::string::npos) << command << "\n" << result.err;
  if (!position.empty()) {
    EXPECT_NE(result.err.find(position + " "), std::string::npos) << command << "\n" << result.err;
  }
  EXPECT_EQ(dir.CountEntries(), entries_before) << command << ": an output was written";
}

std::string Substitute(std::string command, const std::string& path) {
  const size_t at = command.find("{}");
  return command.replace(at, 2, "'" + path + "'");
}

void RunCases(const std::vector<HostileInputCase>& cases) {
  ScratchDir dir;
  for (const HostileInputCase& c : cases) {
    const std::string path = dir.Write(c.name, c.contents);
    std::string command = c.command;
    const size_t out = command.find("{out}");
    if (out != std::string::npos) command.replace(out, 5, "'" + dir.File("out") + "'");
    ExpectRejected(dir, path, Substitute(command, path), c.position);
  }
}

const char kZemaxHeader[] =
    "Source Measured\nSymmetry PlaneSymmetrical\nSpectralContent Monochrome\nScatterType BRDF\n"
    "SampleRotation 1\n0\n";

TEST(HostileInput, HeadersClaimingTenToTheTwelveSamplesAllocateNothing) {
  // A small OpenEXR file whose data window says 60000 x 16 pixels (one zip line block, so
  // OpenEXR's own offset table fits): the pixels cannot fit in 375 bytes.
  std::string exr = testing::ReadFileText(testing::TestPath("fuzz/seeds/zip-half.exr"));
  const char kDataWindow[] = "dataWindow\0box2i\0";
  const size_t window = exr.find(std::string(kDataWindow, sizeof(kDataWindow) - 1));
  ASSERT_NE(window, std::string::npos);
  exr.replace(window + sizeof(kDataWindow) - 1 + 4, 16,
              Int32(0) + Int32(0) + Int32(59999) + Int32(15));
  RunCases({
      {"huge.astm",
       "NUM_POINTS 1000000000000\nVARS theta_i,phi_i,theta_s,phi_s,400nm\n0.1,0,0.2,0,0.5\n",
       "info {}", "line"},
      {"huge.brdf", "# num wls\n1000000000000\n400\n", "info {}", "line"},
      {"huge.bsdf", std::string(kZemaxHeader) + "AngleOfIncidence 1000000000000\n15\n", "info {}",
       "line"},
      // MERL: 10000^3 cells in a 36-byte file.
      {"huge.binary", Int32(10000) + Int32(10000) + Int32(10000) + std::string(24, '\0'), "info {}",
       "byte"},
      {"huge.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 30000 +X 30000\n\x02\x02\x75\x30",
       "tonemap {} --out {out}.png", "byte"},
      {"huge.exr", exr, "tonemap {} --out {out}.png", "byte"},
  });
}

TEST(HostileInput, DuplicatedOrContradictoryHeaderKeysAreErrors) {
  const std::string astm_tail =
      "NUM_POINTS 1\nVARS theta_i,phi_i,theta_s,phi_s,400nm,500nm\n0.1,0,0.2,0,0.5,0.5\n";
  RunCases({
      {"twice.astm", "SAMPLE_NAME a\nSAMPLE_NAME b\n" + astm_tail, "info {}", "line"},
      {"count-twice.astm", "NUM_POINTS 1\n" + astm_tail, "info {}", "line"},
      {"contradiction.bsdf", "Source Measured\nSymmetry PlaneSymmetrical\nSymmetry Asymmetrical\n",
       "info {}", "line"},
      {"twice.bsdf", std::string(kZemaxHeader) + "ScatterType BRDF\n", "info {}", "line"},
      {"twice.csv",
       "# brdfkit measurement v1\n# sample: a\n# sample: b\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n"
       "1,0,2,0,1,1,1\n",
       "info {}", "line"},
      {"twice.brdf", "# num wls\n2\n# num wls\n400 500\n", "info {}", "line"},
      {"instrument.json", R"({"jitter_deg": 0.1, "jitter_deg": 0.2})",
       "measure --sample model:lambert:rho_d=0.5 --instrument {} --out {out}.csv", "byte"},
      {"surface.json", R"({"heightfield": {"kind": "flat", "kind": "flat"}, "base": "lambert"})",
       "measure --sample surface:{} --out {out}.csv", "byte"},
      {"fit.json", R"({"model": "lambert", "params": {"rho_d": 0.5}, "model": "phong"})",
       "render {} --size 16 --out {out}.png", "byte"},
  });
}

TEST(HostileInput, DevicesAndDirectoriesAreNamedNotRead) {
  ScratchDir dir;
  const std::string out = dir.File("out");
  const std::vector<std::string> commands = {
      "info {}",
      "convert {} '" + out + ".csv'",
      "fit {}",
      "energy {}",
      "render {} --out '" + out + ".png'",
      "render lambert:rho_d=0.5 --env {} --out '" + out + ".png'",
      "tonemap {} --out '" + out + ".png'",
      "measure --sample model:lambert:rho_d=0.5 --instrument {} --out '" + out + ".csv'",
  };
  // /dev/zero never ends: reading it would hang or exhaust memory.
  for (const std::string& path : {std::string("/dev/null"), std::string("/dev/zero"), dir.path()}) {
    for (const std::string& command : commands) {
      ExpectRejected(dir, path, Substitute(command, path), "");
    }
  }
  ExpectRejected(dir, "/dev/zero", "measure --sample surface:/dev/zero --out '" + out + ".csv'",
                 "");
}

TEST(HostileInput, EveryWritingCommandReportsAnUnwritableOutput) {
  ScratchDir dir;
  // Under a regular file no directory can be made, even by root.
  const std::string blocked = dir.Write("file", "") + "/sub";
  const std::string astm = "'" + DataPath("cornell-astm/cayman.astm") + "'";
  const std::vector<std::string> commands = {
      "convert " + astm + " {}",
      "fit " + astm + " --model lambert --out {}",
      "measure --sample model:lambert:rho_d=0.5 --schedule inplane:step=30 --out {}",
      "render lambert:rho_d=0.5 --size 16 --out {}",
      "render lambert:rho_d=0.5 --size 16 --out '" + dir.File("ok.png") + "' --exr {}",
      "tonemap '" + DataPath("hdr/memorial.hdr") + "' --out {}",
      "energy lambert:rho_d=0.5 --theta-steps 4 --out {}",
      "energy lambert:rho_d=0.5 --theta-steps 4 --plot {}",
      "demo --quick --quiet --out {}",
  };
  const char* extensions[] = {".csv", ".json", ".csv", ".png", ".exr", ".png", ".csv", ".png", ""};
  for (size_t k = 0; k < commands.size(); ++k) {
    const std::string target = blocked + "/out" + extensions[k];
    ExpectRejected(dir, target, Substitute(commands[k], target), "");
  }
}

}  // namespace
}  // namespace brdf
