// The fit options shared by `brdf fit` and `brdf batch` (DESIGN §3, §6), defined once: the
// command-line spelling and the help text with defaults; fitters::FitArguments parses them.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "core/measurement.h"
#include "fitters/fit_arguments.h"

namespace brdf::cli {

using fitters::FitArguments;

// Registers --model, --loss, --robust, --max-samples, --seed, --max-iterations,
// --grey-specular and --illuminant on `app`.
void AddFitOptions(CLI::App* app, FitArguments* arguments);

// "lambert, phong, ..., ggx, beckmann": the registry's names, for help texts.
std::string ModelNames();

// Reads a measurement for `brdf fit` and `brdf batch`, which evaluate nothing between its
// samples: without its table evaluator (Measurement::tabulated; a fit reads the samples and the
// cell measure, while a MERL table's evaluator holds a second, 35 MB copy of the values), whose
// pages go back to the system before the fit's peak of memory. Unless `samples` is set (a caller
// that reads Measurement::samples itself, such as `brdf fit --plot`), a reader that can leaves its
// samples to be made on demand (ReadOptions::samples): the fit copies those it uses into its own
// buffer, and a MERL table's 117 MB of samples are then never held beside that copy.
Measurement ReadForFit(const std::string& path, const FitArguments& arguments,
                       bool samples = false);

}  // namespace brdf::cli
