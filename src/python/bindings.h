// The pieces of the `brdfkit` module, one Register* per file, and the result objects that hold
// a library result next to its JSON report (converted to a dict on access).
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/measurement.h"
#include "energy/albedo.h"
#include "fitters/select.h"

namespace brdf::python {

namespace py = pybind11;

// brdfkit.FitResult: what `brdf fit` computes and its report (the --json object).
struct PythonFit {
  fitters::ModelFit model_fit;
  nlohmann::json report;
};

// brdfkit.Energy: what `brdf energy` computes and its --json object.
struct PythonEnergy {
  AlbedoCurve curve;
  nlohmann::json report;
};

void RegisterMeasurement(py::module_& module);  // Measurement, read, measure
void RegisterModel(py::module_& module);        // Model, model, models
void RegisterFit(py::module_& module);          // FitResult, fit
void RegisterEnergy(py::module_& module);       // Energy, energy
void RegisterImages(py::module_& module);       // render, tonemap
void RegisterView(py::module_& module);         // view
void RegisterExport(py::module_& module);       // export

// Limits TBB's worker threads for the lifetime of the object when `threads` > 0, as the CLI's
// --threads does (0: all cores); throws UsageError when negative.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  struct Control;
  std::unique_ptr<Control> control_;
};

}  // namespace brdf::python
