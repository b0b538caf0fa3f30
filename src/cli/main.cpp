// brdf: measure, fit, check and preview reflectance. Maps typed errors to exit statuses
// (DESIGN §3): 0 success, 2 bad usage or bad input, 3 a computation failed, 1 an internal error.
#include <malloc.h>

#include <iostream>
#include <vector>

#include "cli/commands.h"
#include "core/errors.h"

int main(int argc, char** argv) {
  // A 1080p float RGBA image is 33 MB, above glibc's largest mmap threshold (32 MB): every such
  // buffer would be mapped fresh and returned on free, and the kernel's page clearing took over
  // half of the HDR pipeline's time. Serving large blocks from the heap and keeping them lets
  // the pipeline's stages reuse freed memory.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  CLI::App app{"brdfkit: measure, fit, check and preview reflectance (BRDFs)", "brdf"};
  app.set_version_flag("--version", std::string("brdf ") + BRDFKIT_VERSION);
  app.require_subcommand(1);
  app.footer("Run 'brdf COMMAND --help' for the options of each command.");

  const std::vector<brdf::cli::Command> commands = {
      brdf::cli::AddDemoCommand(app),    brdf::cli::AddInfoCommand(app),
      brdf::cli::AddConvertCommand(app), brdf::cli::AddMeasureCommand(app),
      brdf::cli::AddFitCommand(app),     brdf::cli::AddEnergyCommand(app),
      brdf::cli::AddRenderCommand(app),  brdf::cli::AddTonemapCommand(app),
  };

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int status = app.exit(error);
    return status == 0 ? 0 : 2;
  }

  try {
    for (const brdf::cli::Command& command : commands) {
      if (command.app->parsed()) return command.run();
    }
  } catch (const brdf::ComputeError& error) {
    std::cerr << "brdf: " << error.what() << "\n";
    return 3;
  } catch (const brdf::Error& error) {
    std::cerr << "brdf: " << error.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "brdf: out of memory\n";
    return 1;
  } catch (const std::exception& error) {
    std::cerr << "brdf: internal error: " << error.what() << "\n";
    return 1;
  }
  return 2;
}
