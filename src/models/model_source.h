// Where a command takes a MODEL (DESIGN §2-§3), a fit report is accepted too: the argument is
// either a model string (`phong:rho_d=0.5:...`) or the path of a FIT.json written by
// `brdf fit` (DESIGN §6: {"model": NAME, "params": {"rho_d": [r,g,b], ...}, ...}).
#pragma once

#include <string>

#include "models/registry.h"

namespace brdf {

// True when `spec` names an existing file ending in .json (case-insensitive).
bool IsFitReportPath(const std::string& spec);

// Reads the model of a fit report. Throws InputError naming the file and what is wrong
// (not JSON, no "model", unknown model, a parameter missing or of the wrong shape).
Model ReadFitReportModel(const std::string& path);

// A model string or a fit report path; throws UsageError / InputError.
Model LoadModel(const std::string& spec);

}  // namespace brdf
