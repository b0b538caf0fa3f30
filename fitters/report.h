// Fit reports (DESIGN §6): the JSON written by `brdf fit --out FIT.json` (read back wherever a
// model is accepted, src/models/model_source.h) and the table printed for a person.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "fitters/fit.h"
#include "fitters/select.h"

namespace brdf::fitters {

// `selection` may be null (a single named model was fitted).
nlohmann::json FitReportJson(const FitResult& fit, const std::string& source,
                             const Selection* selection);
void PrintFitReport(std::ostream& out, const FitResult& fit, const std::string& source,
                    const Selection* selection);

}  // namespace brdf::fitters
