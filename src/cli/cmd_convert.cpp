// brdf convert IN OUT [--format NAME] [--illuminant D65|E]: rewrite a measurement in another
// format. MERL to MERL copies the validated table unchanged, so the round trip is bit-exact
// (a detour through sr^-1 values would not be: x * (1/1500) * 1500 is not always x).
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "core/colour.h"
#include "io/formats.h"
#include "io/merl.h"

namespace brdf::cli {

Command AddConvertCommand(CLI::App& parent) {
  struct Options {
    std::string input, output, format, illuminant = "D65";
    bool quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app =
      parent.add_subcommand("convert", "Convert a measurement file to native CSV or MERL .binary");
  app->add_option("IN", options->input, "input measurement file")->required();
  app->add_option("OUT", options->output,
                  "output file; the format follows the extension (.csv, .binary)")
      ->required();
  app->add_option("--format", options->format,
                  "output format, overriding the extension (native-csv, merl)");
  app->add_option("--illuminant", options->illuminant, "illuminant for spectral inputs (D65 or E)")
      ->capture_default_str();
  app->add_flag("--quiet", options->quiet, "print nothing on success");

  return {app, [options]() {
            const FileFormat& output_format = OutputFormat(options->output, options->format);
            const FileFormat& input_format = DetectFormat(options->input);
            WriteReport report;
            size_t samples = 0;
            if (input_format.name == "merl" && output_format.name == "merl") {
              MerlTable::Read(options->input).Write(options->output);
              samples = MerlTable::kCells;
            } else {
              ReadOptions read_options;
              read_options.illuminant = ParseIlluminant(options->illuminant);
              const Measurement measurement = ReadMeasurement(options->input, read_options);
              samples = measurement.samples.size();
              report = WriteMeasurement(measurement, options->output, output_format.name);
            }
            for (const std::string& warning : report.warnings) {
              std::cerr << "brdf convert: warning: " << warning << "\n";
            }
            if (!options->quiet) {
              std::cout << "wrote " << options->output << " (" << output_format.name << ", from "
                        << samples << " " << input_format.name << " samples)\n";
            }
            return 0;
          }};
}

}  // namespace brdf::cli
