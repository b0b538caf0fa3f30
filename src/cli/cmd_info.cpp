// brdf info FILE [--json]: format, sample count, angular coverage, value range, and counts of
// missing, negative and NaN entries.
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/summary_report.h"

namespace brdf::cli {

Command AddInfoCommand(CLI::App& parent) {
  struct Options {
    std::string path;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "info", "Describe a measurement file: format, samples, angular coverage, value range");
  app->add_option("FILE", options->path,
                  "measurement file (native CSV, MERL .binary, ASTM, pbrt-v2 .brdf, Zemax or "
                  "RGL-EPFL .bsdf, ALTA .dat)")
      ->required();
  app->add_flag("--json", options->json, "print JSON instead of the text table");

  return {app, [options]() {
            const SummaryRow row = SummarizeFile(options->path);
            if (options->json) {
              std::cout << SummaryJson(row).dump(2) << "\n";
            } else {
              PrintSummary(std::cout, row);
            }
            return 0;
          }};
}

}  // namespace brdf::cli
