// The MERL benchmark (DESIGN §12, docs/real-data.md): every given MERL table fitted with every
// rung and with `auto`, under each given loss, as `brdf fit FILE --model M --loss L` fits it; each
// fit scored by the weighted log-rmse of its report and by the image error (fitters/
// image_error.h: spheres of the table and of the fit under directional lights at 20 and 60
// degrees, relative L1 of RGB radiance over the lit sphere; and, as image_error_back, under
// lights at 100 and 140 degrees, behind the sphere), with its wall time. Run by
// bench/merl_benchmark, which makes the tables and draws the chart.
//
// Usage: merl_bench OUT.csv LOSSES MODELS TABLE...
//   LOSSES  comma-separated loss names (e.g. l2,log)
//   MODELS  comma-separated model names, `auto` among them for the selection
// One CSV row per table x loss x model.
#include <chrono>
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/format.h"
#include "fitters/fit.h"
#include "fitters/fit_arguments.h"
#include "fitters/image_error.h"
#include "fitters/select.h"
#include "io/formats.h"

namespace {

using namespace brdf;
using namespace brdf::fitters;

std::vector<std::string> SplitComma(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  std::string part;
  while (std::getline(stream, part, ',')) {
    if (!part.empty()) parts.push_back(part);
  }
  return parts;
}

std::string Stem(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  return name.substr(0, name.find('.'));
}

// CSV-safe: the selection's sentence holds commas and semicolons.
std::string Quoted(const std::string& text) {
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

int Run(int argc, char** argv) {
  if (argc < 5) {
    std::cerr << "usage: merl_bench OUT.csv LOSSES MODELS TABLE...\n";
    return 2;
  }
  const std::string out_path = argv[1];
  const std::vector<std::string> losses = SplitComma(argv[2]);
  const std::vector<std::string> models = SplitComma(argv[3]);
  const std::string default_loss = FitArguments{}.loss;
  std::ofstream out(out_path + ".tmp");
  out << "material,loss,model,chosen,image_error,image_error_back,log_rmse,rmse,time_s,converged,"
         "is_default_loss,"
         "selection\n";
  for (int t = 4; t < argc; ++t) {
    const std::string table = argv[t];
    const Measurement measurement = ReadMeasurement(table);
    if (!measurement.tabulated) throw InputError(table, "no evaluator (a MERL table?)");
    const TabulatedBrdf& reference_brdf = *measurement.tabulated;
    const SphereRadiance reference = RenderLitSphere(
        [&](const Vec3& wi, const Vec3& wo) { return reference_brdf.Eval(wi, wo); });
    ImageErrorSetup back;
    back.light_theta_deg = {100.0, 140.0};
    const SphereRadiance reference_back = RenderLitSphere(
        [&](const Vec3& wi, const Vec3& wo) { return reference_brdf.Eval(wi, wo); }, back);
    for (const std::string& loss : losses) {
      FitOptions options;
      options.loss = ParseLoss(loss);
      for (const std::string& model : models) {
        const auto start = std::chrono::steady_clock::now();
        const ModelFit result = FitModelOrAuto(measurement, model, options);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const FitResult& fit = result.fit;
        const double error =
            RelativeL1(reference, RenderLitSphere([&](const Vec3& wi, const Vec3& wo) {
                         return fit.model.Eval(wi, wo);
                       }));
        const double error_back = RelativeL1(
            reference_back,
            RenderLitSphere([&](const Vec3& wi, const Vec3& wo) { return fit.model.Eval(wi, wo); },
                            back));
        const std::string selection = result.selection ? result.selection->reason : "";
        const std::string row =
            Format("%s,%s,%s,%s,%.5g,%.5g,%.5g,%.5g,%.3f,%d,%d,", Stem(table).c_str(), loss.c_str(),
                   model.c_str(), fit.model.name().c_str(), error, error_back, fit.metrics.log_rmse,
                   fit.metrics.rmse, seconds, fit.converged ? 1 : 0, loss == default_loss ? 1 : 0);
        out << row << Quoted(selection) << "\n";
        out.flush();
        std::cerr << row << fit.model.ToString(4) << "\n";
      }
    }
  }
  out.close();
  if (std::rename((out_path + ".tmp").c_str(), out_path.c_str()) != 0) {
    throw OutputError(out_path, "cannot rename the finished CSV into place");
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
    std::cerr << "merl_bench: " << message << "\n";
    return status;
  }
}
