// `brdf view` (DESIGN §3): the page's numbers are the sources' (closed forms of a Lambertian),
// and the page as a user opens it (headless Chromium, from disk, no flag that widens file
// access) runs its script without error and paints every canvas, the three.js lobe included.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/errors.h"
#include "render/view_page.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::DataPath;
using testing::ReadFileText;
using testing::RunBrdf;
using testing::RunCommand;
using testing::ScratchDir;

nlohmann::json PageData(const std::string& page) {
  const std::string open = "id=\"brdf-data\">";
  const size_t start = page.find(open) + open.size();
  const size_t end = page.find("</script>", start);
  return nlohmann::json::parse(page.substr(start, end - start));
}

std::vector<float> DecodeFloats(const std::string& base64) {
  std::string bytes;
  uint32_t word = 0;
  int bits = 0;
  for (char c : base64) {
    const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char* at = std::strchr(alphabet, c);
    if (c == '=' || at == nullptr) break;
    word = (word << 6) | static_cast<uint32_t>(at - alphabet);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      bytes += static_cast<char>((word >> bits) & 0xff);
    }
  }
  std::vector<float> values(bytes.size() / 4);
  std::memcpy(values.data(), bytes.data(), values.size() * 4);
  return values;
}

TEST(ViewPage, CarriesALambertiansClosedForms) {
  ViewGrid grid;
  grid.albedo_steps = 10;
  const nlohmann::json data = PageData(ViewPageHtml({"lambert:rho_d=0.5,0.25,0.125"}, grid));
  ASSERT_EQ(data["sources"].size(), 1u);
  const nlohmann::json& source = data["sources"][0];
  EXPECT_FALSE(source["measured"].get<bool>());
  const double rho[3] = {0.5, 0.25, 0.125};
  const std::vector<float> plane = DecodeFloats(source["plane"]["rgb"]);
  ASSERT_EQ(plane.size(),
            3 * source["plane"]["incidence_deg"].size() * source["plane"]["outgoing_deg"].size());
  for (size_t i = 0; i < plane.size(); ++i) EXPECT_NEAR(plane[i], rho[i % 3] / M_PI, 1e-7);
  const std::vector<float> table = DecodeFloats(source["table"]["rgb"]);
  ASSERT_EQ(table.size(), 3u * grid.theta_h_cells * grid.theta_d_cells * grid.phi_d_cells);
  int above = 0;
  for (size_t i = 0; i < table.size(); i += 3) {
    // Cells whose directions lie below the horizon hold zero; the others f = rho / pi.
    if (table[i] == 0) continue;
    ++above;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(table[i + c], rho[c] / M_PI, 1e-7);
  }
  EXPECT_GT(above, static_cast<int>(table.size() / 3 / 2));
  const std::vector<float> albedo = DecodeFloats(source["albedo"]["rgb"]);
  ASSERT_EQ(albedo.size(), 3u * grid.albedo_steps);
  for (size_t i = 0; i < albedo.size(); ++i) EXPECT_NEAR(albedo[i], rho[i % 3], 1e-6);
  EXPECT_TRUE(source["albedo"]["conserving"].get<bool>());
}

TEST(ViewCommand, AMissingSourceIsAnInputErrorAndWritesNothing) {
  ScratchDir dir;
  const testing::CommandResult result =
      RunBrdf("view '" + dir.File("absent.astm") + "' --out '" + dir.File("view.html") + "'");
  EXPECT_EQ(result.exit_status, 2) << result.err;
  EXPECT_NE(result.err.find("absent.astm"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir.File("view.html")));
}

std::string Chromium() {
  const char* named = std::getenv("BRDFKIT_CHROMIUM");
  if (named != nullptr && *named != '\0') return named;
  for (const char* candidate : {"/usr/bin/chromium", "/usr/bin/chromium-browser"}) {
    if (std::filesystem::exists(candidate)) return candidate;
  }
  return "";
}

// The status line the page writes once drawn: "canvases=N;painted=K;lobe=0|1;errors=E[;...]".
std::string PageStatus(const std::string& page, const std::string& profile) {
  const std::string chromium = Chromium();
  EXPECT_FALSE(chromium.empty()) << "Chromium is missing: scripts/setup installs Debian's "
                                    "chromium package (or set BRDFKIT_CHROMIUM)";
  if (chromium.empty()) return "";
  // Virtual time lets the page's asynchronous import of three.js finish before the dump.
  const testing::CommandResult result = RunCommand(
      "'" + chromium + "' --headless --no-sandbox --disable-gpu --disable-quic --no-first-run " +
      "--disable-background-networking --disable-component-update --disable-sync " +
      "--virtual-time-budget=20000 --user-data-dir='" + profile + "' --dump-dom 'file://" + page +
      "'");
  EXPECT_EQ(result.exit_status, 0) << result.err;
  const std::string open = "<pre id=\"status\">";
  const size_t start = result.out.find(open);
  if (start == std::string::npos) return "";
  const size_t end = result.out.find("</pre>", start);
  return result.out.substr(start + open.size(), end - start - open.size());
}

TEST(ViewInBrowser, LoadsWithoutErrorAndPaintsEveryCanvas) {
  ScratchDir dir;
  const std::string page = dir.File("view.html");
  const testing::CommandResult result = RunBrdf(
      "view '" + DataPath("cornell-astm/garnet_red.astm") +
      "' 'ggx:rho_d=0.1,0.02,0.02:f0=0.05,0.05,0.05:alpha=0.3' --quiet --out '" + page + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const std::string html = ReadFileText(page);
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
  EXPECT_NE(html.find("The MIT License"), std::string::npos) << "three.js's licence is kept";
  // Plane, slice, albedo, two spheres and the lobe's WebGL canvas.
  EXPECT_EQ(PageStatus(page, dir.File("profile")), "canvases=6;painted=6;lobe=1;errors=0");

  // The check can fail: a script error on the page is counted.
  const size_t body = html.rfind("</body>");
  dir.Write("broken.html",
            html.substr(0, body) + "<script>notDefinedAnywhere();</script>" + html.substr(body));
  const std::string broken = PageStatus(dir.File("broken.html"), dir.File("profile2"));
  EXPECT_NE(broken.find(";errors=1;"), std::string::npos) << broken;
}

}  // namespace
}  // namespace brdf
