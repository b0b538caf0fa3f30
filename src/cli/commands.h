// Subcommands of `brdf`, one file each. Every Add*Command registers its options on `parent`
// and returns the function to run when the subcommand was chosen; that function returns the
// exit status and throws the typed errors of core/errors.h, which main() maps to exit codes.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "core/errors.h"

namespace brdf::cli {

struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
  // Splits its work across MPI ranks under mpirun (DESIGN §11); the others refuse to run there.
  bool distributed = false;
};

// A check that an option's text is accepted by `parse` (a library's Parse* function): its
// UsageError, which names the accepted values, becomes the parser's error for the option
// ("--exr-type: unknown OpenEXR pixel type 'double' (known: half, float)").
template <typename Parse>
CLI::Validator ParsesAs(Parse parse) {
  return CLI::Validator(
      [parse](std::string& text) {
        try {
          parse(text);
          return std::string();
        } catch (const UsageError& error) {
          return std::string(error.what());
        }
      },
      "");
}

Command AddInfoCommand(CLI::App& parent);
Command AddConvertCommand(CLI::App& parent);
Command AddFitCommand(CLI::App& parent);
Command AddDemoCommand(CLI::App& parent);
Command AddMeasureCommand(CLI::App& parent);
Command AddEnergyCommand(CLI::App& parent);
Command AddTonemapCommand(CLI::App& parent);
Command AddRenderCommand(CLI::App& parent);
Command AddBatchCommand(CLI::App& parent);
Command AddExportCommand(CLI::App& parent);
Command AddPlanCommand(CLI::App& parent);
Command AddViewCommand(CLI::App& parent);

}  // namespace brdf::cli
