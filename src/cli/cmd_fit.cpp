// brdf fit FILE --model M|auto [--loss ...] [--robust ...] [--max-samples N] [--seed N]
//   [--out FIT.json]: Ceres fit of a reflectance model to a measurement (DESIGN §6). Prints
// the report table (or JSON with --json) and writes the JSON report; exit status 3 when the
// fit did not converge (the report is still written and says so).
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/slice_plot.h"
#include "core/atomic_file.h"
#include "fitters/fit.h"
#include "fitters/report.h"
#include "fitters/select.h"
#include "io/formats.h"

namespace brdf::cli {

Command AddFitCommand(CLI::App& parent) {
  struct Options {
    std::string path, model = "auto", loss = "l2", robust = "none", out, illuminant = "D65", plot;
    size_t max_samples = 20000;
    uint64_t seed = 1;
    int threads = 0, max_iterations = fitters::FitOptions{}.max_iterations;
    bool grey_specular = false, json = false;
  };
  auto options = std::make_shared<Options>();
  std::string names;
  for (const ModelInfo& info : ModelRegistry()) names += (names.empty() ? "" : ", ") + info.name;
  CLI::App* app = parent.add_subcommand("fit", "Fit " + names + " to a measurement (Ceres)");
  app->add_option("FILE", options->path, "measurement file (any format brdf info reads)")
      ->required();
  app->add_option("--model", options->model,
                  names + ", or auto (the simplest model the data support, by BIC)")
      ->capture_default_str();
  app->add_option("--loss", options->loss,
                  "l2 (on f), log (log(1 + f cos theta_i)) or cosine-l2 (Ngan et al. 2005)")
      ->capture_default_str();
  app->add_option("--robust", options->robust, "none, huber or cauchy (for outliers)")
      ->capture_default_str();
  app->add_option("--max-samples", options->max_samples,
                  "stratified subsample for the multi-start, then a polish on all samples "
                  "(0: all samples throughout)")
      ->capture_default_str();
  app->add_option("--seed", options->seed, "seed of the subsample draw")->capture_default_str();
  app->add_option("--threads", options->threads,
                  "worker threads (0: all cores); the output does not depend on it")
      ->capture_default_str();
  app->add_option("--max-iterations", options->max_iterations,
                  "iterations of each Ceres solve; a fit that needs more is reported as not "
                  "converged (exit status 3)")
      ->capture_default_str();
  app->add_flag("--grey-specular", options->grey_specular,
                "one rho_s (or f0, for ggx and beckmann) for all channels");
  app->add_option("--illuminant", options->illuminant, "for spectral files: D65 or E")
      ->capture_default_str();
  app->add_option("--out", options->out, "write the JSON fit report here");
  app->add_flag("--json", options->json, "print the JSON report instead of the table");
  app->add_option("--plot", options->plot,
                  "write the plane-of-incidence slice chart here (PNG): the in-plane samples "
                  "(+- sigma) and the fitted model, one panel per incidence, log scale");

  return {app, [options]() {
            fitters::FitOptions fit_options;
            fit_options.loss = fitters::ParseLoss(options->loss);
            fit_options.robust = fitters::ParseRobust(options->robust);
            fit_options.max_samples = options->max_samples;
            fit_options.seed = options->seed;
            fit_options.threads = options->threads;
            fit_options.max_iterations = options->max_iterations;
            fit_options.grey_specular = options->grey_specular;
            fit_options.Validate();
            ReadOptions read_options;
            read_options.illuminant = ParseIlluminant(options->illuminant);
            const Measurement measurement = ReadMeasurement(options->path, read_options);

            const fitters::ModelFit model_fit =
                fitters::FitModelOrAuto(measurement, options->model, fit_options);
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
            if (options->json) {
              std::cout << report.dump(2) << "\n";
            } else {
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
