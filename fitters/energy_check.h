// The energy check of a finished fit (DESIGN §6, §7): the bound is built into the
// parameterization (energy_bound.h); the report checks the fitted material independently with
// the albedo integrator of `brdf energy` over 90 incidence angles, and warns where the bound is
// active. `--model auto` runs it for the chosen model only (select.cpp).
#pragma once

#include "fitters/fit.h"

namespace brdf::fitters {

// Fills result->energy and appends the "energy bound active" warnings.
void CheckFitEnergy(FitResult* result);

}  // namespace brdf::fitters
