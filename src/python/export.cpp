// brdfkit.export: `brdf export` from Python (DESIGN §3, §10). The report is the CLI's --json
// object; an export that loses the material (export.h, ExportWarnings) warns with a UserWarning,
// as the CLI warns on stderr.
#include "export/export.h"

#include <pybind11/stl.h>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "io/formats.h"
#include "models/model_source.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/errors.h"

namespace brdf::python {

void RegisterExport(py::module_& module) {
  module.def(
      "export",
      [](const py::object& fit, const std::string& to, const py::object& out,
         const py::object& samples, const std::string& illuminant) {
        const exporters::Target target = exporters::ParseTarget(to);
        exporters::ExportRequest request;
        std::string fit_path;
        std::shared_ptr<const Measurement> measurement;
        if (py::isinstance<PythonFit>(fit)) {
          request.fit = fit.cast<const PythonFit&>().model_fit.fit.model;
        } else if (py::isinstance<Model>(fit)) {
          request.fit = fit.cast<Model>();
        } else if (py::isinstance<py::str>(fit)) {
          fit_path = fit.cast<std::string>();
          request.fit = ReadFitReportModel(fit_path);
        } else {
          throw UsageError("fit: expected a FitResult, a Model or a FIT.json path, got " +
                           py::repr(fit).cast<std::string>());
        }
        std::string samples_path;
        if (py::isinstance<Measurement>(samples)) {
          measurement = samples.cast<std::shared_ptr<Measurement>>();
        } else if (py::isinstance<py::str>(samples)) {
          samples_path = samples.cast<std::string>();
        } else if (!samples.is_none()) {
          throw UsageError("samples: expected a Measurement, a path or None, got " +
                           py::repr(samples).cast<std::string>());
        } else if (!fit_path.empty()) {
          samples_path = exporters::ResolveFitSource(fit_path);
        }
        const std::string out_path = out.is_none() ? "" : out.cast<std::string>();
        exporters::ExportedMaterial material;
        {
          py::gil_scoped_release release;
          if (measurement) {
            request.samples = exporters::SamplesForExport(*measurement);
          } else if (!samples_path.empty()) {
            ReadOptions read_options;
            read_options.illuminant = ParseIlluminant(illuminant);
            request.samples =
                exporters::SamplesForExport(ReadMeasurement(samples_path, read_options));
          } else {
            request.samples = exporters::HemisphereGridSamples(exporters::kFallbackGridStepDeg);
          }
          material = exporters::ExportMaterial(request, target);
          if (!out_path.empty()) {
            WriteFileAtomically(out_path, [&](std::ostream& file) { file << material.text; });
          }
        }
        for (const std::string& warning : material.warnings) Warn(warning);
        nlohmann::json report =
            exporters::ExportJson(material, fit_path, out_path, request.samples.origin);
        report["text"] = material.text;
        return JsonToPython(report);
      },
      py::arg("fit"), py::arg("to"), py::arg("out") = py::none(), py::arg("samples") = py::none(),
      py::arg("illuminant") = "D65", R"doc(
The fitted material in a renderer's own terms, as `brdf export` (DESIGN §3).

fit:        a FitResult, a Model, or a FIT.json path (written by brdf fit --out).
to:         "mitsuba3", "pbrt-v4" or "gltf".
out:        the file to write (atomically), or None to write nothing.
samples:    the measurement the error is measured on: a Measurement or a path; by default the
            fit report's "source" when fit is a path, else a 5-degree hemisphere grid.
illuminant: for spectral files: "D65" or "E".

Returns the CLI's --json dict plus "text", the file's contents. When the renderer's material
differs from the fit by more than the thresholds of docs/export.md (max relative error above 10,
log-rmse above twice the fit's own and above 0.02, or the fit's highlight below half or above
twice its brightness), each finding is also issued as a UserWarning; the dict's "warnings" holds
them.)doc");
}

}  // namespace brdf::python
