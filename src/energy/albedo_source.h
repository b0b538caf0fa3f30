// What `brdf energy SOURCE` and `brdfkit.energy(...)` share: the reading of SOURCE (a model
// string, a fit report or a measurement file) and the JSON of a curve (DESIGN §7's fields, and
// what a script needs to trust them: errors, coverage, notes).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "energy/albedo.h"

namespace brdf {

// A fit report or a model string names a model; any other existing path is data (a directory
// or a device then gets the reader's diagnosis). Throws UsageError / InputError naming SOURCE.
AlbedoCurve SourceAlbedoCurve(const std::string& source, const AlbedoOptions& options,
                              Progress* progress = nullptr);

// The `brdf energy --json` object; `seconds` is the wall time of the computation.
nlohmann::json AlbedoCurveJson(const AlbedoCurve& curve, double seconds);

}  // namespace brdf
