// Where a command takes a MODEL (DESIGN §2-§3), a fit report is accepted too: the argument is
// either a model string (`phong:rho_d=0.5:...`) or the path of a FIT.json written by
// `brdf fit` (DESIGN §6: {"model": NAME, "params": {"rho_d": [r,g,b], ...}, ...}).
#pragma once

#include <string>

#include "core/measurement.h"
#include "models/registry.h"

namespace brdf {

// True when `spec` names an existing file ending in .json (case-insensitive).
bool IsFitReportPath(const std::string& spec);

// Reads the model of a fit report. Throws InputError naming the file and what is wrong
// (not JSON, no "model", unknown model, a parameter missing or of the wrong shape).
Model ReadFitReportModel(const std::string& path);

// A model string or a fit report path; throws UsageError / InputError.
Model LoadModel(const std::string& spec);

// For arguments that take a model or a measurement: true when `spec` is a model (a fit report
// path, or a string that names no existing path and starts with a model's name), false when it
// is data (any other existing path, even a directory or a device, so that the reader says what
// is wrong with it). A string that is neither throws InputError saying so.
bool IsModelSpec(const std::string& spec);

// A model standing in for a dense measurement: no samples of its own, and an evaluator
// (Measurement::tabulated) that is the model itself, so that whatever tabulates a dense input
// (a MERL table at its cell centres, a gonio schedule's geometries) tabulates the model.
Measurement ModelAsMeasurement(const Model& model, const std::string& spec);

}  // namespace brdf
