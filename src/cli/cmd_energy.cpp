// brdf energy MODEL|FIT.json|FILE [--method quadrature|mc|importance] [--theta-steps N]
//   [--samples N] [--seed N] [--json] [--out albedo.csv] [--plot albedo.png] [--quiet]
// Directional albedo per channel against incidence angle, its maximum and where, an error
// estimate per value, and the energy-conservation verdict (DESIGN §7). A material that does
// not conserve energy is a finding, not a failure: the exit status is 0 whenever the check ran.
#include <chrono>
#include <iostream>
#include <memory>

#include "cli/albedo_plot.h"
#include "cli/commands.h"
#include "core/atomic_file.h"
#include "core/progress.h"
#include "core/text.h"
#include "energy/albedo_source.h"

namespace brdf::cli {
namespace {

void WriteAlbedoCsv(const AlbedoCurve& curve, const std::string& path) {
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << "theta_deg,r,g,b,error_r,error_g,error_b,coverage\n";
    for (const AlbedoPoint& point : curve.points) {
      out << FormatNumber(point.theta_deg);
      for (int c = 0; c < 3; ++c) out << "," << FormatNumber(point.estimate.albedo[c]);
      for (int c = 0; c < 3; ++c) out << "," << FormatNumber(point.estimate.error[c]);
      out << "," << FormatNumber(point.estimate.coverage) << "\n";
    }
  });
}

}  // namespace

Command AddEnergyCommand(CLI::App& parent) {
  struct Options {
    std::string source, method = "quadrature", out, plot;
    AlbedoOptions albedo;
    bool json = false, quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "energy",
      "Directional albedo vs incidence angle and the energy-conservation check (exit status 0 "
      "whether or not the material conserves energy; the verdict is in the output)");
  app->add_option("SOURCE", options->source,
                  "a model string (e.g. blinn-phong:rho_s=0.04:m=200), a fit report (.json) or a "
                  "measurement file (MERL .binary, ASTM, pbrt-v2 .brdf, Zemax or RGL-EPFL .bsdf, "
                  "ALTA .dat, native CSV)")
      ->required();
  app->add_option("--method", options->method,
                  "quadrature (adaptive, lobe-centred), mc (cosine-weighted Monte Carlo) or "
                  "importance (cosine + lobe mixture; models only)")
      ->capture_default_str();
  app->add_option("--theta-steps", options->albedo.theta_steps,
                  "incidence angles, evenly spaced over 0..89 degrees")
      ->capture_default_str();
  app->add_option("--samples", options->albedo.samples, "Monte Carlo samples per angle")
      ->capture_default_str();
  app->add_option("--seed", options->albedo.seed,
                  "Monte Carlo seed (results do not depend on the thread count)")
      ->capture_default_str();
  app->add_flag("--json", options->json,
                "print JSON (the curve, the verdict and its reason) instead of the table");
  app->add_option("--out", options->out,
                  "also write the curve as CSV (theta_deg, r, g, b, errors, coverage)");
  app->add_option("--plot", options->plot, "also draw albedo vs theta as a PNG");
  app->add_flag("--quiet", options->quiet, "no progress on stderr");

  return {app, [options]() {
            options->albedo.method = ParseAlbedoMethod(options->method);
            options->albedo.Validate();
            const auto start = std::chrono::steady_clock::now();
            Progress progress("energy", options->albedo.theta_steps, options->quiet);
            const AlbedoCurve curve =
                SourceAlbedoCurve(options->source, options->albedo, &progress);
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (!options->out.empty()) WriteAlbedoCsv(curve, options->out);
            if (!options->plot.empty()) WriteAlbedoPlot(curve, options->plot);
            if (options->json) {
              for (const std::string& warning : curve.warnings) {
                std::cerr << "brdf energy: warning: " << warning << "\n";
              }
              std::cout << AlbedoCurveJson(curve, seconds).dump(2) << "\n";
            } else {
              std::cout << curve.Report();
            }
            return 0;
          }};
}

}  // namespace brdf::cli
