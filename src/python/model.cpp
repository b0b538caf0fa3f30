// brdfkit.Model, brdfkit.model, brdfkit.models; brdfkit.FitResult and brdfkit.fit (DESIGN §2,
// §6, §10): the model registry and the fit library, called as `brdf fit` calls them.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "core/errors.h"
#include "fitters/fit_arguments.h"
#include "fitters/report.h"
#include "io/formats.h"
#include "models/model_source.h"
#include "models/model_string.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/errors.h"

namespace brdf::python {
namespace {

// {name: value} with an RGB parameter as [r, g, b], the shape of the fit report's "params".
py::dict ParamsDict(const ModelInfo& info, const std::vector<double>& values) {
  py::dict dict;
  for (const ParamInfo& param : info.params) {
    if (param.channels == 1) {
      dict[py::str(param.name)] = values[param.slot];
    } else {
      py::list channels;
      for (int c = 0; c < param.channels; ++c) channels.append(values[param.slot + c]);
      dict[py::str(param.name)] = channels;
    }
  }
  return dict;
}

py::list ParamTable(const ModelInfo& info) {
  py::list table;
  for (const ParamInfo& param : info.params) {
    table.append(py::dict(py::arg("name") = param.name, py::arg("channels") = param.channels,
                          py::arg("lower") = param.lower, py::arg("upper") = param.upper,
                          py::arg("default") = param.default_value,
                          py::arg("meaning") = param.meaning));
  }
  return table;
}

py::array_t<double> EvalModel(const Model& model, const DirectionArray& wi,
                              const DirectionArray& wo) {
  return EvalRows(wi, wo, [&model](const Vec3& a, const Vec3& b) { return model.Eval(a, b); });
}

constexpr const char* kEvalDoc = R"doc(
f(wi, wo) in 1/sr, no cosine factor, the library's evaluation of the model.
wi, wo: (N, 3) arrays of unit directions in the local frame (z = normal), or one (3,)
direction used for every row; not normalised here. Returns (N, 3) float64 (or (3,)).
The GIL is released during the loop.)doc";

}  // namespace

void RegisterModel(py::module_& module) {
  py::class_<Model>(module, "Model", R"doc(
A reflectance model with its parameter values, from brdfkit.model(spec) or a fit.
name: the model's name; string: the canonical model string (reads back to the same doubles);
params: {name: value} (RGB parameters as [r, g, b]); info: the model's parameter table.)doc")
      .def_property_readonly("name", &Model::name)
      .def_property_readonly("string", [](const Model& model) { return model.ToString(); })
      .def_property_readonly(
          "params", [](const Model& model) { return ParamsDict(model.info(), model.params()); })
      .def_property_readonly("formula", [](const Model& model) { return model.info().formula; })
      .def_property_readonly("info", [](const Model& model) { return ParamTable(model.info()); })
      .def("eval", &EvalModel, py::arg("wi"), py::arg("wo"), kEvalDoc)
      .def("__str__", [](const Model& model) { return model.ToString(); })
      .def("__repr__",
           [](const Model& model) { return "brdfkit.model('" + model.ToString() + "')"; });

  module.def("model", &LoadModel, py::arg("spec"), R"doc(
A model from a model string, NAME[:key=value]... (RGB values as r,g,b or one grey number;
parameters not named take their defaults), e.g. "ggx:rho_d=0.2:f0=0.04:alpha=0.1", or from the
path of a fit report (FIT.json written by `brdf fit --out` or FitResult.report). Raises
UsageError for a bad string, InputError for a bad report.)doc");

  module.def(
      "models",
      [] {
        py::list list;
        for (const ModelInfo& info : ModelRegistry()) {
          list.append(py::dict(py::arg("name") = info.name, py::arg("formula") = info.formula,
                               py::arg("params") = ParamTable(info),
                               py::arg("auto") = info.auto_candidate));
        }
        return list;
      },
      "Every model brdfkit knows, in its registry's order: a list of {name, formula, params, "
      "auto} (auto: a rung `--model auto` climbs).");
}

void RegisterFit(py::module_& module) {
  py::class_<PythonFit>(module, "FitResult", R"doc(
The result of brdfkit.fit, as `brdf fit` reports it.
model: the fitted Model; params, stderr, metrics: the report's dicts; report: the whole report,
the same dict as `brdf fit --json` (and FIT.json); converged, summary, warnings; eval(wi, wo):
the fitted model's f.)doc")
      .def_property_readonly("model", [](const PythonFit& fit) { return fit.model_fit.fit.model; })
      .def_property_readonly(
          "params", [](const PythonFit& fit) { return JsonToPython(fit.report["params"]); })
      .def_property_readonly(
          "stderr", [](const PythonFit& fit) { return JsonToPython(fit.report["stderr"]); })
      .def_property_readonly(
          "metrics", [](const PythonFit& fit) { return JsonToPython(fit.report["metrics"]); })
      .def_property_readonly("report",
                             [](const PythonFit& fit) { return JsonToPython(fit.report); })
      .def_property_readonly("converged",
                             [](const PythonFit& fit) { return fit.model_fit.fit.converged; })
      .def_property_readonly("warnings",
                             [](const PythonFit& fit) { return fit.model_fit.fit.warnings; })
      .def_property_readonly("summary",
                             [](const PythonFit& fit) { return fit.model_fit.fit.Summary(); })
      .def(
          "eval",
          [](const PythonFit& fit, const DirectionArray& wi, const DirectionArray& wo) {
            return EvalModel(fit.model_fit.fit.model, wi, wo);
          },
          py::arg("wi"), py::arg("wo"), kEvalDoc)
      .def("__repr__", [](const PythonFit& fit) {
        return "<brdfkit.FitResult " + fit.model_fit.fit.Summary() + ">";
      });

  const fitters::FitOptions defaults;
  const fitters::FitArguments default_arguments;
  module.def(
      "fit",
      [](const py::object& measurement_or_path, const std::string& model, const std::string& loss,
         const std::string& robust, size_t max_samples, uint64_t seed, int threads,
         int max_iterations, bool grey_specular, const std::string& illuminant, bool reciprocal) {
        const fitters::FitArguments arguments{model,         loss,       robust,
                                              max_samples,   seed,       max_iterations,
                                              grey_specular, illuminant, reciprocal};
        const fitters::FitOptions options = arguments.ToFitOptions(threads);
        std::shared_ptr<const Measurement> measurement;
        if (py::isinstance<py::str>(measurement_or_path)) {
          const std::string path = measurement_or_path.cast<std::string>();
          py::gil_scoped_release release;
          measurement = std::make_shared<Measurement>(fitters::ReadForFit(path, arguments));
        } else if (py::isinstance<Measurement>(measurement_or_path)) {
          measurement = measurement_or_path.cast<std::shared_ptr<Measurement>>();
        } else {
          throw UsageError("measurement: expected a brdfkit.Measurement or a path, got " +
                           py::repr(measurement_or_path).cast<std::string>());
        }
        auto result = std::make_unique<PythonFit>(PythonFit{[&] {
                                                              py::gil_scoped_release release;
                                                              return fitters::FitModelOrAuto(
                                                                  *measurement, model, options);
                                                            }(),
                                                            {}});
        result->report = fitters::FitReportJson(result->model_fit.fit, measurement->source,
                                                result->model_fit.selection_or_null());
        if (!result->model_fit.fit.converged) {
          const std::string message =
              "the fit did not converge (" + result->model_fit.fit.termination + ")";
          if (PyErr_WarnEx(ConvergenceWarning().ptr(), message.c_str(), 1) != 0) {
            throw py::error_already_set();
          }
        }
        return result;
      },
      py::arg("measurement"), py::arg("model") = default_arguments.model,
      py::arg("loss") = default_arguments.loss, py::arg("robust") = "none",
      py::arg("max_samples") = defaults.max_samples, py::arg("seed") = defaults.seed,
      py::arg("threads") = defaults.threads, py::arg("max_iterations") = defaults.max_iterations,
      py::arg("grey_specular") = defaults.grey_specular, py::arg("illuminant") = "D65",
      py::arg("reciprocal") = false,
      R"doc(
Fits a reflectance model to a measurement with Ceres, as `brdf fit` does; the same
inputs give the same report, bit for bit (time_s aside).

measurement:    a Measurement, or the path of a measurement file (read as brdfkit.read does).
model:          a model name (brdfkit.models()), or "auto" (default): every model is fitted and
                the simplest the data support is kept, by BIC (for tables that can be
                rendered, by the image error of their spheres); report["selection"] says why.
loss:           "auto" (default: "image" for tables that can be rendered, "l2" for readings
                that state their noise, "sqrt" otherwise), "image" (sqrt on the pixels of
                rendered spheres), "sqrt" (sqrt(f cos theta_i)), "l2" (on f), "log"
                (log(1 + f cos theta_i)) or "cosine-l2" (Ngan et al. 2005).
robust:         "none" (default), "huber" or "cauchy" (for outliers).
max_samples:    stratified subsample for the multi-start, then a polish on all samples (0:
                all samples throughout; default 20000).
seed:           seed of the subsample draw (default 1).
threads:        worker threads, 0 = all cores (default); the result does not depend on it.
max_iterations: iterations of each Ceres solve (default 200); a fit that needs more is not
                converged.
grey_specular:  one rho_s (or f0, for ggx and beckmann) for all channels.
illuminant:     when `measurement` is the path of a spectral file: "D65" (default) or "E".
reciprocal:     when `measurement` is the path of an RGL-EPFL file: read its table with the more
                grazing direction as the light (reciprocal by construction) instead of as the
                format's reference evaluates it (default False).

Returns a FitResult. A fit that did not converge warns (brdfkit.ConvergenceWarning) and
returns its result with converged False. The GIL is released while fitting.)doc");
}

}  // namespace brdf::python
