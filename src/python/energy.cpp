// brdfkit.Energy and brdfkit.energy (DESIGN §7): the energy library's albedo curve of a model,
// a fit or a measurement, and the `brdf energy --json` object.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <chrono>

#include "core/errors.h"
#include "energy/albedo_source.h"
#include "python/bindings.h"
#include "python/convert.h"

namespace brdf::python {
namespace {

// One column per channel of a per-angle quantity: (angles, 3).
template <typename Field>
py::array_t<double> PerAngle(const AlbedoCurve& curve, Field field) {
  py::array_t<double> array({static_cast<py::ssize_t>(curve.points.size()), py::ssize_t{3}});
  auto out = array.mutable_unchecked<2>();
  for (size_t k = 0; k < curve.points.size(); ++k) {
    const Rgb value = field(curve.points[k]);
    for (int c = 0; c < 3; ++c) out(k, c) = value[c];
  }
  return array;
}

py::array_t<double> Rgb3(const Rgb& value) {
  py::array_t<double> array(py::ssize_t{3});
  for (int c = 0; c < 3; ++c) array.mutable_at(c) = value[c];
  return array;
}

}  // namespace

void RegisterEnergy(py::module_& module) {
  py::class_<PythonEnergy>(module, "Energy", R"doc(
Directional albedo against incidence angle and the conservation check, as `brdf energy`.
theta_deg (M,), albedo (M, 3), error (M, 3), coverage (M,); max (3,), theta_deg_at_max (3,),
verdict ("conserving", "not conserving" or "undecided"), reason (the sentence it rests on),
notes, warnings; report: the same dict as `brdf energy --json`.)doc")
      .def_property_readonly("theta_deg",
                             [](const PythonEnergy& energy) {
                               std::vector<double> theta;
                               for (const AlbedoPoint& p : energy.curve.points) {
                                 theta.push_back(p.theta_deg);
                               }
                               return py::array_t<double>(theta.size(), theta.data());
                             })
      .def_property_readonly(
          "albedo",
          [](const PythonEnergy& energy) {
            return PerAngle(energy.curve, [](const AlbedoPoint& p) { return p.estimate.albedo; });
          })
      .def_property_readonly(
          "error",
          [](const PythonEnergy& energy) {
            return PerAngle(energy.curve, [](const AlbedoPoint& p) { return p.estimate.error; });
          })
      .def_property_readonly("coverage",
                             [](const PythonEnergy& energy) {
                               std::vector<double> coverage;
                               for (const AlbedoPoint& p : energy.curve.points) {
                                 coverage.push_back(p.estimate.coverage);
                               }
                               return py::array_t<double>(coverage.size(), coverage.data());
                             })
      .def_property_readonly(
          "max", [](const PythonEnergy& energy) { return Rgb3(energy.curve.max_albedo); })
      .def_property_readonly("theta_deg_at_max",
                             [](const PythonEnergy& energy) {
                               const auto& at = energy.curve.theta_deg_at_max;
                               return Rgb3(Rgb(at[0], at[1], at[2]));
                             })
      .def_property_readonly(
          "verdict", [](const PythonEnergy& energy) { return energy.curve.verdict().name(); })
      .def_property_readonly(
          "reason", [](const PythonEnergy& energy) { return energy.curve.verdict().reason; })
      .def_property_readonly("notes", [](const PythonEnergy& energy) { return energy.curve.notes; })
      .def_property_readonly("warnings",
                             [](const PythonEnergy& energy) { return energy.curve.warnings; })
      .def_property_readonly("report",
                             [](const PythonEnergy& energy) { return JsonToPython(energy.report); })
      .def("__repr__", [](const PythonEnergy& energy) {
        return "<brdfkit.Energy " + energy.curve.Summary() + ">";
      });

  const AlbedoOptions defaults;
  module.def(
      "energy",
      [](const py::object& source, const std::string& method, int theta_steps, int64_t samples,
         uint64_t seed, int threads) {
        AlbedoOptions options;
        options.method = ParseAlbedoMethod(method);
        options.theta_steps = theta_steps;
        options.samples = samples;
        options.seed = seed;
        options.Validate();
        // The source as the CLI would be given it: a model (or a fit's), a measurement in
        // memory, or the CLI's SOURCE text.
        std::optional<Model> model;
        std::shared_ptr<const Measurement> measurement;
        std::string text;
        if (py::isinstance<Model>(source)) {
          model = source.cast<Model>();
        } else if (py::isinstance<PythonFit>(source)) {
          model = source.cast<const PythonFit&>().model_fit.fit.model;
        } else if (py::isinstance<Measurement>(source)) {
          measurement = source.cast<std::shared_ptr<Measurement>>();
        } else if (py::isinstance<py::str>(source)) {
          text = source.cast<std::string>();
        } else {
          throw UsageError(
              "source: expected a Model, FitResult, Measurement, model string or path, got " +
              py::repr(source).cast<std::string>());
        }
        auto result = std::make_unique<PythonEnergy>();
        {
          py::gil_scoped_release release;
          const ThreadLimit limit(threads);
          const auto start = std::chrono::steady_clock::now();
          if (model) {
            result->curve = ModelAlbedoCurve(*model, options);
          } else if (measurement) {
            result->curve = MeasuredAlbedoCurve(MeasuredBrdfOf(*measurement), options);
          } else {
            result->curve = SourceAlbedoCurve(text, options);
          }
          const double seconds =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          result->report = AlbedoCurveJson(result->curve, seconds);
        }
        return result;
      },
      py::arg("source"), py::arg("method") = AlbedoMethodName(defaults.method),
      py::arg("theta_steps") = defaults.theta_steps, py::arg("samples") = defaults.samples,
      py::arg("seed") = defaults.seed, py::arg("threads") = 0, R"doc(
Directional albedo a(theta) per RGB channel and the energy-conservation check, as
`brdf energy`; the same inputs give the same numbers, bit for bit.

source:      a Model, a FitResult (its model), a Measurement (through its table evaluator, or
             inverse-distance interpolation of scattered samples), or the CLI's SOURCE text:
             a model string, a FIT.json path or a measurement file path.
method:      "quadrature" (adaptive, lobe-centred; default), "mc" (cosine-weighted Monte
             Carlo) or "importance" (cosine + lobe mixture; models only).
theta_steps: incidence angles, evenly spaced over 0..89 degrees (default 90).
samples:     Monte Carlo samples per angle (default 65536).
seed:        Monte Carlo seed (default 1).
threads:     worker threads, 0 = all cores; the result does not depend on it.

Returns an Energy. A material that does not conserve energy is a finding (verdict
"not conserving"), not an error. The GIL is released during the integration.)doc");
}

}  // namespace brdf::python
