// brdf convert IN OUT [--format NAME] [--illuminant D65|E] [--schedule SPEC]: rewrite a
// measurement in another format. MERL to MERL copies the validated table unchanged, so the
// round trip is bit-exact (a detour through sr^-1 values would not be: x * (1/1500) * 1500 is
// not always x). Dense tables (a reader's evaluator, Measurement::tabulated) become a MERL table
// by evaluation at the cell centres (WriteMerl), and with --schedule are evaluated at the
// geometries of a gonio schedule instead of writing their own samples. A model (string or
// FIT.json) is such a dense input: `brdf convert ggx:... ggx.binary` tabulates it for renderers
// that read MERL tables.
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "core/colour.h"
#include "core/errors.h"
#include "gonio/schedule.h"
#include "io/formats.h"
#include "io/merl.h"
#include "models/model_source.h"

namespace brdf::cli {
namespace {

// The input's evaluator at every geometry of the schedule; NaN (a missing MERL cell) becomes a
// missing sample.
Measurement EvaluateOnSchedule(const Measurement& input, const std::string& spec) {
  if (input.tabulated == nullptr) {
    throw UsageError("--schedule needs a dense input with an evaluator (MERL, RGL-EPFL); " +
                     input.source + " is " + input.format + " (scattered samples)");
  }
  const gonio::Schedule schedule = gonio::MakeSchedule(spec);
  Measurement output;
  output.metadata = input.metadata;
  // What described the input's own samples no longer applies (a "grid: MERL" key would make a
  // fit weight these samples as MERL cells).
  for (const char* key : {"grid", "samples", "missing"}) output.metadata.erase(key);
  output.metadata["schedule"] = schedule.spec;
  output.metadata["evaluation"] = "values evaluated at the schedule's geometries through " +
                                  input.tabulated->LookupName() + " (" + input.format + " " +
                                  input.source + ")";
  output.source = input.source;
  output.format = input.format;
  for (const gonio::Incidence& incidence : schedule.incidences) {
    for (const gonio::Detector& detector : incidence.detectors) {
      Sample sample;
      sample.wi = incidence.wi;
      sample.wo = detector.wo;
      sample.value = input.tabulated->Eval(sample.wi, sample.wo);
      sample.missing = !sample.value.allFinite();
      if (sample.missing) sample.value = Rgb::Zero();
      output.samples.push_back(sample);
      if (schedule.has_weight) output.weight.push_back(detector.weight);
    }
  }
  return output;
}

}  // namespace

Command AddConvertCommand(CLI::App& parent) {
  struct Options {
    std::string input, output, format, illuminant = "D65", schedule;
    bool reciprocal = false;
    bool quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app =
      parent.add_subcommand("convert", "Convert a measurement file to native CSV or MERL .binary");
  app->add_option("IN", options->input,
                  "input measurement file, or a model (model string or FIT.json) to tabulate")
      ->required();
  app->add_option("OUT", options->output,
                  "output file; the format follows the extension (.csv, .binary)")
      ->required();
  app->add_option("--format", options->format,
                  "output format, overriding the extension (native-csv, merl)");
  app->add_option("--illuminant", options->illuminant, "illuminant for spectral inputs (D65 or E)")
      ->capture_default_str();
  app->add_flag("--reciprocal", options->reciprocal,
                "RGL-EPFL inputs: read the table with the more grazing direction as the light "
                "(reciprocal by construction) instead of as the format's reference evaluates it");
  app->add_option("--schedule", options->schedule,
                  "evaluate a dense input (MERL, RGL-EPFL) at the geometries of a gonio schedule "
                  "(as in brdf measure, e.g. inplane:step=5) instead of writing its own samples");
  app->add_flag("--quiet", options->quiet, "print nothing on success");

  return {
      app, [options]() {
        const FileFormat& output_format = OutputFormat(options->output, options->format);
        WriteReport report;
        std::string from;  // what the output was made from, for the closing line
        if (IsModelSpec(options->input)) {
          Measurement model = ModelAsMeasurement(LoadModel(options->input), options->input);
          if (!options->schedule.empty()) {
            model = EvaluateOnSchedule(model, options->schedule);
          } else if (!output_format.fixed_grid) {
            throw UsageError(
                "a model has no samples of its own: give --schedule to evaluate it at a gonio "
                "schedule's geometries, or write a MERL .binary");
          }
          report = WriteMeasurement(model, options->output, output_format.name);
          from = std::to_string(model.samples.empty() ? MerlTable::kCells : model.samples.size()) +
                 " evaluations of " + model.metadata["model"];
        } else if (const FileFormat& input_format = DetectFormat(options->input);
                   &input_format == &output_format && input_format.copy != nullptr &&
                   options->schedule.empty()) {
          input_format.copy(options->input, options->output);
          from = "an unchanged copy of the " + input_format.name + " file";
        } else {
          ReadOptions read_options;
          read_options.illuminant = ParseIlluminant(options->illuminant);
          read_options.reciprocal = options->reciprocal;
          Measurement measurement = ReadMeasurement(options->input, read_options);
          if (!options->schedule.empty()) {
            measurement = EvaluateOnSchedule(measurement, options->schedule);
          }
          from = std::to_string(measurement.samples.size()) + " " + input_format.name + " samples";
          report = WriteMeasurement(measurement, options->output, output_format.name);
        }
        for (const std::string& warning : report.warnings) {
          std::cerr << "brdf convert: warning: " << warning << "\n";
        }
        if (!options->quiet) {
          std::cout << "wrote " << options->output << " (" << output_format.name << ", from "
                    << from << ")\n";
        }
        return 0;
      }};
}

}  // namespace brdf::cli
