// brdf demo [--out DIR] [--data DIR]: the main job on built-in defaults. For now it does what
// the tool truly can: read every bundled real measurement, summarize each, print the table and
// keep the summaries in DIR/summary.json. Later capabilities (simulate, fit, check energy,
// render) extend it.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/summary_report.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "io/formats.h"

namespace brdf::cli {
namespace {

// Measurement files under `directory`, recognised by extension, in a stable order.
std::vector<std::string> FindMeasurements(const std::string& directory) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(directory)) {
    throw UsageError(directory + ": not a directory (give the bundled data with --data DIR)");
  }
  std::vector<std::string> paths;
  for (const auto& entry : fs::recursive_directory_iterator(directory)) {
    if (!entry.is_regular_file()) continue;
    std::string extension = entry.path().extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
    for (const FileFormat& format : FileFormats()) {
      if (std::find(format.extensions.begin(), format.extensions.end(), extension) !=
          format.extensions.end()) {
        paths.push_back(entry.path().string());
        break;
      }
    }
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

}  // namespace

Command AddDemoCommand(CLI::App& parent) {
  struct Options {
    std::string out = "brdf-demo";
    std::string data = BRDFKIT_DATA_DIR;
    bool quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "demo",
      "The main job on built-in defaults: read every bundled real measurement and "
      "summarize it");
  app->add_option("--out", options->out, "directory for the outputs")->capture_default_str();
  app->add_option("--data", options->data, "directory of bundled measurements")
      ->capture_default_str();
  app->add_flag("--quiet", options->quiet, "no progress on stderr");

  return {app, [options]() {
            const std::vector<std::string> paths = FindMeasurements(options->data);
            if (paths.empty()) throw UsageError(options->data + ": no measurement files found");
            const bool progress = !options->quiet && ::isatty(STDERR_FILENO);
            std::vector<SummaryRow> rows;
            nlohmann::json report = nlohmann::json::array();
            for (size_t k = 0; k < paths.size(); ++k) {
              if (progress) {
                std::cerr << "\r[" << k + 1 << "/" << paths.size() << "] reading " << paths[k]
                          << "\033[K" << std::flush;
              }
              SummaryRow row = SummarizeFile(paths[k]);
              // Shown relative to the data directory: shorter, and the same on every machine.
              row.path = std::filesystem::relative(paths[k], options->data).string();
              row.measurement.samples.clear();  // keep the summaries, not the data
              report.push_back(SummaryJson(row));
              rows.push_back(std::move(row));
            }
            if (progress) std::cerr << "\r\033[K";
            std::filesystem::create_directories(options->out);
            const std::string summary_path = options->out + "/summary.json";
            WriteFileAtomically(summary_path, [&](std::ostream& out) {
              out << nlohmann::json{{"measurements", report}}.dump(2) << "\n";
            });
            std::cout << "Bundled real measurements (" << rows.size() << " files in "
                      << options->data << "):\n";
            PrintSummaryTable(std::cout, rows);
            std::cout << "\nwrote " << summary_path << "\n";
            return 0;
          }};
}

}  // namespace brdf::cli
