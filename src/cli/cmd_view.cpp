// brdf view FILE|FIT.json|MODEL... [--out view.html]: one self-contained interactive page of
// measurements and fitted models (DESIGN §3; render/view_page.h).
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "render/view_page.h"

namespace brdf::cli {

Command AddViewCommand(CLI::App& parent) {
  struct Options {
    std::vector<std::string> sources;
    std::string output = "view.html";
    bool quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "view",
      "Write one self-contained HTML page (offline, no network) that overlays measurements and "
      "fitted models: plane-of-incidence plot, 3D lobe, (theta_h, theta_d) slice, albedo curve "
      "with the verdict, and a sphere lit from the mouse");
  app->add_option("SOURCE", options->sources,
                  "measurement files, fit reports (FIT.json) or model strings, drawn in order")
      ->required();
  app->add_option("--out", options->output, "the HTML page to write")->capture_default_str();
  app->add_flag("--quiet", options->quiet, "print nothing on success");
  return {app, [options]() {
            WriteViewPage(options->sources, options->output);
            if (!options->quiet) {
              std::cout << "brdf view: wrote " << options->output << " (" << options->sources.size()
                        << " source" << (options->sources.size() == 1 ? "" : "s") << ")\n";
            }
            return 0;
          }};
}

}  // namespace brdf::cli
