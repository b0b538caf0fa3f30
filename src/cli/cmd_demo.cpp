// brdf demo [--out DIR] [--quick] [--data DIR]: the main job on built-in defaults (demo.h):
// simulate three samples, fit every model to them and to the bundled real measurements, check
// energy, keep everything in DIR with report.html, and print the summary table.
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/demo.h"

namespace brdf::cli {

Command AddDemoCommand(CLI::App& parent) {
  auto options = std::make_shared<DemoOptions>();
  options->data_dir = BRDFKIT_DATA_DIR;
  CLI::App* app = parent.add_subcommand(
      "demo",
      "The main job on built-in defaults: simulate measurements, fit every model, check "
      "energy, write DIR/report.html");
  app->add_option("--out", options->out_dir, "directory for every output")->capture_default_str();
  app->add_option("--data", options->data_dir, "directory of bundled measurements")
      ->capture_default_str();
  app->add_flag("--quick", options->quick,
                "coarser simulations and fits, fewer real files (about 10 s)");
  app->add_flag("--quiet", options->quiet, "no progress on stderr");

  return {app, [options]() {
            const DemoResult result = RunDemo(*options);
            WriteDemoReport(result, *options);
            WriteDemoSummaryJson(result, *options);
            PrintDemoSummary(std::cout, result);
            std::cout << "\nwrote " << options->out_dir << "/report.html (" << result.seconds
                      << " s)\n";
            return 0;
          }};
}

}  // namespace brdf::cli
