// The demo report as a user meets it: opened in a real browser (headless Chromium), every image
// it shows must load and decode. Chromium comes from Debian (scripts/setup installs it);
// $BRDFKIT_CHROMIUM names another binary. The quick demo's own test (cli_test.cpp) calls
// ExpectReportLoadsInBrowser on its report, so the demo runs once.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "browser_check.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::ReadFileText;
using testing::RunCommand;
using testing::ScratchDir;
using testing::TestPath;

std::string ChromiumBinary() {
  const char* named = std::getenv("BRDFKIT_CHROMIUM");
  if (named != nullptr && *named != '\0') return named;
  for (const char* candidate : {"/usr/bin/chromium", "/usr/bin/chromium-browser"}) {
    if (std::filesystem::exists(candidate)) return candidate;
  }
  return "";
}

// Loads `page` headless and returns the DOM after its load event. Flags: no sandbox (tests run
// as root in CI), and no background networking, which a closed network refuses.
std::string DumpDom(const std::string& chromium, const std::string& page,
                    const std::string& profile) {
  const testing::CommandResult result = RunCommand(
      "'" + chromium + "' --headless --no-sandbox --disable-gpu --disable-quic --no-first-run " +
      "--disable-background-networking --disable-component-update --disable-sync " +
      "--allow-file-access-from-files --user-data-dir='" + profile + "' --dump-dom 'file://" +
      page + "'");
  EXPECT_EQ(result.exit_status, 0) << result.err;
  return result.out;
}

// The verdict image_check.html writes: "title=...;images=N;broken=K;src,src".
std::string Verdict(const std::string& dom) {
  const std::string open = "<pre id=\"verdict\">";
  const size_t start = dom.find(open);
  if (start == std::string::npos) return "";
  const size_t end = dom.find("</pre>", start);
  return dom.substr(start + open.size(), end - start - open.size());
}

}  // namespace

void ExpectReportLoadsInBrowser(const std::string& report_dir) {
  const std::string chromium = ChromiumBinary();
  ASSERT_FALSE(chromium.empty()) << "Chromium is missing: scripts/setup installs Debian's "
                                    "chromium package (or set BRDFKIT_CHROMIUM)";
  ScratchDir profile;
  const std::string check = report_dir + "/image_check.html";
  std::filesystem::copy_file(TestPath("browser/image_check.html"), check);
  const std::string verdict = Verdict(DumpDom(chromium, check, profile.File("profile")));
  std::filesystem::remove(check);
  ASSERT_FALSE(verdict.empty()) << "the check page wrote no verdict";
  EXPECT_EQ(verdict.find("error="), std::string::npos) << verdict;
  EXPECT_NE(verdict.find("title=brdfkit demo report;"), std::string::npos) << verdict;
  EXPECT_NE(verdict.find(";broken=0;"), std::string::npos) << verdict;
  const size_t count = verdict.find("images=");
  ASSERT_NE(count, std::string::npos) << verdict;
  // Five datasets in --quick, each with an albedo chart and preview sheets.
  EXPECT_GE(std::atoi(verdict.c_str() + count + 7), 10) << verdict;

  // Self-contained: nothing is fetched from the network.
  const std::string html = ReadFileText(report_dir + "/report.html");
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
}

namespace {

// The check itself must be able to fail: a report whose image is missing is caught.
TEST(ReportInBrowser, AMissingImageIsReportedBroken) {
  const std::string chromium = ChromiumBinary();
  ASSERT_FALSE(chromium.empty()) << "Chromium is missing (scripts/setup installs it)";
  ScratchDir dir;
  dir.Write("report.html",
            "<!DOCTYPE html><html><head><title>t</title></head><body>"
            "<img src=\"present.png\"><img src=\"absent.png\"></body></html>");
  // A 1x1 PNG (the smallest valid image: signature, IHDR, IDAT, IEND).
  static const unsigned char kPng[] = {
      0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
      0x44, 0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x06, 0x00, 0x00,
      0x00, 0x1f, 0x15, 0xc4, 0x89, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x44, 0x41, 0x54, 0x78,
      0x9c, 0x63, 0x60, 0x60, 0x60, 0xf8, 0x0f, 0x00, 0x01, 0x04, 0x01, 0x00, 0x5f, 0xd9,
      0x7d, 0x9b, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  dir.Write("present.png", std::string(reinterpret_cast<const char*>(kPng), sizeof(kPng)));
  std::filesystem::copy_file(TestPath("browser/image_check.html"), dir.File("image_check.html"));
  const std::string verdict =
      Verdict(DumpDom(chromium, dir.File("image_check.html"), dir.File("profile")));
  EXPECT_EQ(verdict, "title=t;images=2;broken=1;absent.png");
}

}  // namespace
}  // namespace brdf
