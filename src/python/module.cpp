// The `brdfkit` Python module (DESIGN §10): the library's entry points, as the `brdf` commands
// call them, with numpy arrays in and out. No logic of its own beyond conversion; see README.md.
#include <pybind11/pybind11.h>
#include <tbb/global_control.h>

#include <optional>

#include "core/errors.h"
#include "python/bindings.h"
#include "python/errors.h"

namespace brdf::python {

struct ThreadLimit::Control {
  tbb::global_control control;
};

ThreadLimit::ThreadLimit(int threads) {
  if (threads < 0) throw UsageError("threads must not be negative (0 = all cores)");
  if (threads > 0) {
    control_ = std::make_unique<Control>(Control{tbb::global_control(
        tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads))});
  }
}

ThreadLimit::~ThreadLimit() = default;

}  // namespace brdf::python

PYBIND11_MODULE(brdfkit, module) {
  module.doc() = R"doc(
brdfkit: measure (virtual gonioreflectometer), fit (Ceres), check (energy conservation) and
preview (HDR render) BRDFs, from Python. The same libraries as the `brdf` command line, with
its option names and defaults as keywords; the same inputs and seeds give the same bits.

    import brdfkit
    m = brdfkit.read("data/cornell-astm/cayman.astm")     # Measurement: wi, wo, rgb, sigma
    fit = brdfkit.fit(m, model="auto", loss="log")        # FitResult: model, params, report
    curve = brdfkit.energy(fit)                           # Energy: theta_deg, albedo, verdict, reason
    img = brdfkit.render(fit, size=256, spp=16)           # float32 (256, 256, 4), W/(m^2 sr)
    png = brdfkit.tonemap(img, operator="reinhard")       # uint8 (256, 256, 3)

Functions: read, measure, model, models, fit, energy, render, tonemap, read_hdr.
Errors: InputError (.path, .line, .byte), UsageError (a ValueError), OutputError (.path),
ComputationError; all are brdfkit.Error. Long calls release the GIL; threads=0 uses all cores.)doc";
  module.attr("__version__") = BRDFKIT_VERSION;
  brdf::python::RegisterErrors(module);
  brdf::python::RegisterMeasurement(module);
  brdf::python::RegisterModel(module);
  brdf::python::RegisterFit(module);
  brdf::python::RegisterEnergy(module);
  brdf::python::RegisterImages(module);
  brdf::python::RegisterView(module);
  brdf::python::RegisterExport(module);
}
