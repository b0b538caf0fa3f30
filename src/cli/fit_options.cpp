#include "cli/fit_options.h"

#include "fitters/select.h"
#include "io/formats.h"
#include "models/registry.h"

namespace brdf::cli {

std::string ModelNames() {
  std::string names;
  for (const ModelInfo& info : ModelRegistry()) names += (names.empty() ? "" : ", ") + info.name;
  return names;
}

void AddFitOptions(CLI::App* app, FitArguments* arguments) {
  std::string candidates;
  for (const std::string& name : fitters::AutoCandidates()) {
    candidates += (candidates.empty() ? "" : ", ") + name;
  }
  app->add_option("--model", arguments->model,
                  ModelNames() + ", or auto (the simplest of " + candidates +
                      " that the data support, by BIC; for tables that can be rendered, by the "
                      "image error of their rendered spheres)")
      ->capture_default_str();
  app->add_option("--loss", arguments->loss,
                  "auto (image for tables that can be rendered, l2 for readings that state their "
                  "noise, sqrt otherwise), image (sqrt on the pixels of rendered spheres), sqrt "
                  "(sqrt(f cos theta_i)), l2 (on f), log (log(1 + f cos theta_i)) or cosine-l2 "
                  "(Ngan et al. 2005)")
      ->capture_default_str();
  app->add_option("--robust", arguments->robust, "none, huber or cauchy (for outliers)")
      ->capture_default_str();
  app->add_option("--max-samples", arguments->max_samples,
                  "stratified subsample for the multi-start, then a polish on all samples "
                  "(0: all samples throughout)")
      ->capture_default_str();
  app->add_option("--seed", arguments->seed, "seed of the subsample draw")->capture_default_str();
  app->add_option("--max-iterations", arguments->max_iterations,
                  "iterations of each Ceres solve; a fit that needs more is reported as not "
                  "converged (exit status 3)")
      ->capture_default_str();
  app->add_flag("--grey-specular", arguments->grey_specular,
                "one rho_s (or f0, for ggx and beckmann) for all channels");
  app->add_option("--illuminant", arguments->illuminant, "for spectral files: D65 or E")
      ->capture_default_str();
  app->add_flag("--reciprocal", arguments->reciprocal,
                "RGL-EPFL files: read the table with the more grazing direction as the light "
                "(reciprocal by construction) instead of as the format's reference evaluates it");
}

}  // namespace brdf::cli
