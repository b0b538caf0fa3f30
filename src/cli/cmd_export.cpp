// brdf export FIT.json --to mitsuba3|pbrt-v4|gltf --out FILE [--samples FILE] [--json]: the
// fitted material in a renderer's own terms (DESIGN §3), with the mapping said to be exact or
// approximate, and the renderer's model, evaluated by our code, measured against the fit on the
// fit's samples (src/export/export.h); a warning on stderr when that error loses the fit.
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "core/atomic_file.h"
#include "export/export.h"
#include "io/formats.h"
#include "models/model_source.h"

namespace brdf::cli {

Command AddExportCommand(CLI::App& parent) {
  struct Options {
    std::string fit, to, out, samples, illuminant = "D65";
    bool json = false, quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "export",
      "Write a fit (brdf fit --out FIT.json) as a Mitsuba 3, pbrt-v4 or glTF 2.0 material, say "
      "where the mapping is exact, and measure the renderer's model against the fit; warn on "
      "stderr and in the JSON when it loses the fit (max relative error > 10, or log rmse > 2x "
      "the fit's own and > 0.02); the file is still written, exit status 0");
  app->add_option("FIT", options->fit, "a fit report written by brdf fit --out")->required();
  app->add_option("--to", options->to,
                  "mitsuba3 (scene XML), pbrt-v4 (scene text) or gltf (glTF 2.0 JSON)")
      ->required();
  app->add_option("--out", options->out, "the file to write")->required();
  app->add_option("--samples", options->samples,
                  "the measurement to measure the error on (default: the fit's \"source\", as "
                  "written, beside the report or one directory up; without it a 5-degree "
                  "hemisphere grid)");
  app->add_option("--illuminant", options->illuminant, "for spectral files: D65 or E")
      ->capture_default_str();
  app->add_flag("--json", options->json, "print the export report as JSON instead of the lines");
  app->add_flag("--quiet", options->quiet,
                "print nothing on success but the warnings (stderr) of a lossy export");

  return {app, [options]() {
            const exporters::Target target = exporters::ParseTarget(options->to);
            exporters::ExportRequest request;
            request.fit = ReadFitReportModel(options->fit);
            const std::string samples_path = options->samples.empty()
                                                 ? exporters::ResolveFitSource(options->fit)
                                                 : options->samples;
            if (samples_path.empty()) {
              request.samples = exporters::HemisphereGridSamples(exporters::kFallbackGridStepDeg);
            } else {
              ReadOptions read_options;
              read_options.illuminant = ParseIlluminant(options->illuminant);
              request.samples =
                  exporters::SamplesForExport(ReadMeasurement(samples_path, read_options));
            }
            const exporters::ExportedMaterial material = exporters::ExportMaterial(request, target);
            WriteFileAtomically(options->out, [&](std::ostream& out) { out << material.text; });
            // A lossy export is still written (exit status 0), but never silently.
            for (const std::string& warning : material.warnings) {
              std::cerr << "brdf export: warning: " << warning << "\n";
            }
            if (options->quiet) return 0;
            if (options->json) {
              std::cout << exporters::ExportJson(material, options->fit, options->out,
                                                 request.samples.origin)
                               .dump(2)
                        << "\n";
            } else {
              std::cout << exporters::ExportSummary(material, options->out, request.samples.origin);
            }
            return 0;
          }};
}

}  // namespace brdf::cli
