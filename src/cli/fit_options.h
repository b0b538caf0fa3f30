// The fit options shared by `brdf fit` and `brdf batch` (DESIGN §3, §6), defined once: the
// command-line spelling, the help text with defaults, and the conversion to FitOptions.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

#include "fitters/fit.h"
#include "io/formats.h"

namespace brdf::cli {

// As typed on the command line; ToFitOptions() and ToReadOptions() parse and validate.
struct FitArguments {
  std::string model = "auto";
  std::string loss = "l2";
  std::string robust = "none";
  size_t max_samples = fitters::FitOptions{}.max_samples;
  uint64_t seed = 1;
  int max_iterations = fitters::FitOptions{}.max_iterations;
  bool grey_specular = false;
  std::string illuminant = "D65";

  bool Automatic() const { return model == "auto"; }
  // Checks the model name (a usage error names the known ones) and the numbers.
  fitters::FitOptions ToFitOptions(int threads) const;
  brdf::ReadOptions ToReadOptions() const;
};

// Registers --model, --loss, --robust, --max-samples, --seed, --max-iterations,
// --grey-specular and --illuminant on `app`.
void AddFitOptions(CLI::App* app, FitArguments* arguments);

// "lambert, phong, ..., ggx, beckmann": the registry's names, for help texts.
std::string ModelNames();

}  // namespace brdf::cli
