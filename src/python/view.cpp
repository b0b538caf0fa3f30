// brdfkit.view (DESIGN §10): the page of `brdf view` for sources given as in the CLI (paths,
// model strings) or as Model / FitResult objects.
#include <pybind11/stl.h>

#include "core/errors.h"
#include "python/bindings.h"
#include "render/view_page.h"

namespace brdf::python {

void RegisterView(py::module_& module) {
  module.def(
      "view",
      [](const py::list& sources, const std::optional<std::string>& out) {
        std::vector<std::string> specs;
        for (const py::handle& source : sources) {
          if (py::isinstance<Model>(source)) {
            specs.push_back(source.cast<Model>().ToString(17));
          } else if (py::isinstance<PythonFit>(source)) {
            specs.push_back(source.cast<const PythonFit&>().model_fit.fit.model.ToString(17));
          } else if (py::isinstance<py::str>(source)) {
            specs.push_back(source.cast<std::string>());
          } else {
            throw UsageError("sources: expected Models, FitResults, model strings or paths, got " +
                             py::repr(source).cast<std::string>());
          }
        }
        std::string page;
        {
          py::gil_scoped_release release;
          if (out) {
            WriteViewPage(specs, *out);
          } else {
            page = ViewPageHtml(specs);
          }
        }
        return out ? py::object(py::none()) : py::object(py::str(page));
      },
      py::arg("sources"), py::arg("out") = py::none(),
      R"doc(The self-contained HTML page of `brdf view` for `sources` (measurement paths, fit
report paths, model strings, Model or FitResult objects, drawn in order): returned as a str, or
written atomically to `out` (then None is returned).)doc");
}

}  // namespace brdf::python
