// The fit options shared by `brdf fit` and `brdf batch` (DESIGN §3, §6), defined once: the
// command-line spelling and the help text with defaults; fitters::FitArguments parses them.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "core/measurement.h"
#include "fitters/fit_arguments.h"

namespace brdf::cli {

using fitters::FitArguments;
using fitters::ReadForFit;

// Registers --model, --loss, --robust, --max-samples, --seed, --max-iterations,
// --grey-specular and --illuminant on `app`.
void AddFitOptions(CLI::App* app, FitArguments* arguments);

// "lambert, phong, ..., ggx, beckmann": the registry's names, for help texts.
std::string ModelNames();

}  // namespace brdf::cli
