// brdf fit FILE --model M|auto [--loss ...] [--robust ...] [--max-samples N] [--seed N]
//   [--out FIT.json]: Ceres fit of a reflectance model to a measurement (DESIGN §6). Prints
// the report table (or JSON with --json) and writes the JSON report; exit status 3 when the
// fit did not converge (the report is still written and says so).
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/fit_options.h"
#include "cli/slice_plot.h"
#include "core/atomic_file.h"
#include "fitters/fit.h"
#include "fitters/report.h"
#include "fitters/select.h"
#include "io/formats.h"

namespace brdf::cli {

Command AddFitCommand(CLI::App& parent) {
  struct Options {
    std::string path, out, plot, instrument;
    FitArguments fit;
    int threads = 0;
    bool json = false, quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand("fit", "Fit " + ModelNames() + " to a measurement (Ceres)");
  app->add_option("FILE", options->path, "measurement file (any format brdf info reads)")
      ->required();
  AddFitOptions(app, &options->fit);
  app->add_option("--instrument", options->instrument,
                  "fit through this instrument (JSON, as brdf measure takes): each reading is "
                  "predicted as the model averaged over the source and detector apertures. "
                  "Default: the instrument the measurement records (brdf measure's CSV does); "
                  "'none': the model at the nominal directions");
  app->add_option("--threads", options->threads,
                  "worker threads (0: all cores); the output does not depend on it")
      ->capture_default_str();
  app->add_option("--out", options->out, "write the JSON fit report here");
  app->add_flag("--json", options->json, "print the JSON report instead of the table");
  app->add_flag("--quiet", options->quiet,
                "print nothing on success (the report still goes to --out); errors and a fit "
                "that did not converge are still reported");
  app->add_option("--plot", options->plot,
                  "write the plane-of-incidence slice chart here (PNG): the in-plane samples "
                  "(+- sigma) and the fitted model, one panel per incidence, log scale");

  return {app, [options]() {
            const fitters::FitOptions fit_options = options->fit.ToFitOptions(options->threads);
            Measurement measurement =
                ReadForFit(options->path, options->fit, !options->plot.empty());
            fitters::ApplyInstrument(options->instrument, &measurement);

            const fitters::ModelFit model_fit =
                fitters::FitModelOrAuto(measurement, options->fit.model, fit_options);
            const fitters::FitResult& fit = model_fit.fit;
            const fitters::Selection* chosen = model_fit.selection_or_null();
            const nlohmann::json report = fitters::FitReportJson(fit, options->path, chosen);
            if (!options->out.empty()) {
              WriteFileAtomically(options->out,
                                  [&](std::ostream& out) { out << report.dump(2) << "\n"; });
            }
            if (!options->plot.empty()) {
              const Model& model = fit.model;
              WriteSlicePlot(
                  measurement,
                  {{model.ToString(4),
                    [&model](const Vec3& wi, const Vec3& wo) { return model.Eval(wi, wo); }}},
                  "plane of incidence: " + options->path, options->plot);
            }
            if (options->json && !options->quiet) {
              std::cout << report.dump(2) << "\n";
            } else if (!options->quiet) {
              fitters::PrintFitReport(std::cout, fit, options->path, chosen);
            }
            if (!fit.converged) {
              std::cerr << "brdf fit: the fit did not converge (" << fit.termination << ")\n";
              return 3;
            }
            return 0;
          }};
}

}  // namespace brdf::cli
