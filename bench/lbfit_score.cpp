// The peer lbfit's fits of a MERL table scored in brdfkit's image space (the MERL benchmark,
// DESIGN §12, docs/real-data.md): each model lbfit printed is evaluated with lbfit's own
// conventions (lbfit_models.h) and rendered, as the table is, on the spheres of
// fitters/image_error.h (lights at 20 and 60 degrees, relative L1 of RGB radiance over the lit
// sphere), the same score bench/merl_bench gives brdfkit's fits. With --brdfkit, a brdfkit fit
// report (`brdf fit --out FIT.json`) is scored against the same render of the table. Run by
// bench/lbfit_compare.
//
// Usage: lbfit_score LBFIT_STDOUT TABLE [--brdfkit FIT.json] [--json]
//   LBFIT_STDOUT  what `lbfit TABLE` printed
//   TABLE         the table lbfit fitted (any file with an evaluator)
// Prints one line per lbfit model (its image error, lbfit's own error, its parameters), the best
// of them by image error and, with --brdfkit, the brdfkit fit's image error; --json prints the
// same as one JSON object.
#include <cstdio>
#include <exception>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/format.h"
#include "fitters/image_error.h"
#include "io/formats.h"
#include "lbfit_models.h"
#include "lbfit_output.h"
#include "models/model_source.h"

namespace {

using namespace brdf;
using namespace brdf::fitters;

struct ScoredFit {
  const lbfit::PrintedFit* printed;
  double image_error;
};

std::string Stem(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  return name.substr(0, name.find('.'));
}

std::string ParameterText(const lbfit::PrintedParameters& parameters) {
  std::string text;
  for (const auto& [name, values] : parameters) {
    text += (text.empty() ? "" : "; ") + name + " =";
    for (double value : values) text += Format(" %.6g", value);
  }
  return text;
}

int Run(int argc, char** argv) {
  std::vector<std::string> positional;
  std::string brdfkit_report;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument == "--json") {
      json = true;
    } else if (argument == "--brdfkit" && i + 1 < argc) {
      brdfkit_report = argv[++i];
    } else if (argument.rfind("--", 0) == 0) {
      throw UsageError("unknown option '" + argument + "'");
    } else {
      positional.push_back(argument);
    }
  }
  if (positional.size() != 2) {
    throw UsageError("usage: lbfit_score LBFIT_STDOUT TABLE [--brdfkit FIT.json] [--json]");
  }
  const std::string& lbfit_path = positional[0];
  const std::string& table = positional[1];
  const std::vector<lbfit::PrintedFit> printed = lbfit::ReadLbfitOutput(lbfit_path);
  std::optional<Model> brdfkit_model;
  if (!brdfkit_report.empty()) brdfkit_model = ReadFitReportModel(brdfkit_report);
  const Measurement measurement = ReadMeasurement(table);
  if (!measurement.tabulated) throw InputError(table, "no evaluator (a MERL table?)");
  const TabulatedBrdf& reference_brdf = *measurement.tabulated;
  const SphereRadiance reference =
      RenderLitSphere([&](const Vec3& wi, const Vec3& wo) { return reference_brdf.Eval(wi, wo); });

  std::vector<ScoredFit> scored;
  const ScoredFit* best = nullptr;
  for (const lbfit::PrintedFit& fit : printed) {
    const lbfit::Evaluator evaluate = fit.kind->make_evaluator(fit.parameters);
    scored.push_back({&fit, RelativeL1(reference, RenderLitSphere(evaluate))});
  }
  for (const ScoredFit& fit : scored) {
    if (!best || fit.image_error < best->image_error) best = &fit;
  }
  const double brdfkit_error =
      brdfkit_model ? RelativeL1(reference, RenderLitSphere([&](const Vec3& wi, const Vec3& wo) {
                                   return brdfkit_model->Eval(wi, wo);
                                 }))
                    : std::numeric_limits<double>::quiet_NaN();

  if (json) {
    nlohmann::json out;
    out["material"] = Stem(table);
    out["lbfit"] = nlohmann::json::array();
    for (const ScoredFit& fit : scored) {
      out["lbfit"].push_back({{"model", fit.printed->kind->heading},
                              {"key", fit.printed->kind->key},
                              {"image_error", fit.image_error},
                              {"lbfit_error", fit.printed->lbfit_error},
                              {"parameters", fit.printed->parameters}});
    }
    out["best"] = {{"model", best->printed->kind->heading},
                   {"key", best->printed->kind->key},
                   {"image_error", best->image_error}};
    if (brdfkit_model) {
      out["brdfkit"] = {{"model", brdfkit_model->name()},
                        {"parameters", brdfkit_model->ToString(4)},
                        {"image_error", brdfkit_error}};
    }
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::cout << "image error (lights 20 and 60 deg, relative L1) of lbfit's fits of " << Stem(table)
            << "\n";
  for (const ScoredFit& fit : scored) {
    std::cout << Format("  %-40s %8.4f   (lbfit's own error %.4g)  %s\n",
                        fit.printed->kind->heading.c_str(), fit.image_error,
                        fit.printed->lbfit_error, ParameterText(fit.printed->parameters).c_str());
  }
  std::cout << Format("  best: %s, %.4f\n", best->printed->kind->heading.c_str(),
                      best->image_error);
  if (brdfkit_model) {
    std::cout << Format("brdfkit (%s): %.4f  %s\n", brdfkit_model->name().c_str(), brdfkit_error,
                        brdfkit_model->ToString(4).c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (...) {
    std::string message;
    const int status = brdf::ExitStatus(std::current_exception(), &message);
    std::cerr << "lbfit_score: " << message << "\n";
    return status;
  }
}
