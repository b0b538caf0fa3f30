// brdfkit.Measurement, brdfkit.read and brdfkit.measure (DESIGN §4, §5, §10).
//
// Zero copy: the samples of a Measurement are an array of structs (core/measurement.h: wi, wo,
// value, missing), so wi, wo, rgb and missing are strided read-only views into it (row stride
// sizeof(Sample)), and sigma and weight views of their own contiguous vectors. Each view keeps
// the Measurement alive (its .base). metadata is a new dict at every access.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "core/errors.h"
#include "gonio/instrument.h"
#include "gonio/measure.h"
#include "gonio/schedule.h"
#include "io/formats.h"
#include "python/bindings.h"
#include "python/convert.h"

namespace brdf::python {
namespace {

using MeasurementPointer = std::shared_ptr<Measurement>;

// A read-only view of `rows` x `columns` values of type T starting at `first`, rows `stride`
// bytes apart, owned by `owner`.
template <typename T>
py::array View(const T* first, py::ssize_t rows, py::ssize_t columns, py::ssize_t stride,
               py::handle owner) {
  std::vector<py::ssize_t> shape = {rows}, strides = {stride};
  if (columns > 0) {
    shape.push_back(columns);
    strides.push_back(sizeof(T));
  }
  py::array view(py::dtype::of<T>(), shape, strides, rows > 0 ? first : nullptr, owner);
  view.attr("flags").attr("writeable") = false;
  return view;
}

template <typename Field>
py::array SampleView(const py::object& self, Field field) {
  const Measurement& measurement = self.cast<const Measurement&>();
  const py::ssize_t rows = measurement.samples.size();
  const double* first = rows > 0 ? field(measurement.samples.front()) : nullptr;
  return View(first, rows, 3, sizeof(Sample), self);
}

// Copies (N, 3) rows into the samples (the constructor from arrays).
std::vector<Vec3> Rows(const DirectionArray& array, const char* name, py::ssize_t expected) {
  if (array.ndim() != 2 || array.shape(1) != 3 || (expected >= 0 && array.shape(0) != expected)) {
    throw UsageError(std::string(name) + ": expected an (N, 3) array" +
                     (expected >= 0 ? " with N = " + std::to_string(expected) : ""));
  }
  std::vector<Vec3> rows(array.shape(0));
  for (py::ssize_t row = 0; row < array.shape(0); ++row) {
    rows[row] = Vec3(array.at(row, 0), array.at(row, 1), array.at(row, 2));
  }
  return rows;
}

MeasurementPointer FromArrays(const DirectionArray& wi, const DirectionArray& wo,
                              const DirectionArray& rgb, const py::object& sigma,
                              const py::object& weight, const py::object& metadata) {
  const std::vector<Vec3> wi_rows = Rows(wi, "wi", -1);
  const py::ssize_t count = wi_rows.size();
  const std::vector<Vec3> wo_rows = Rows(wo, "wo", count);
  const std::vector<Vec3> rgb_rows = Rows(rgb, "rgb", count);
  auto measurement = std::make_shared<Measurement>();
  measurement->format = "arrays";
  measurement->samples.resize(count);
  for (py::ssize_t k = 0; k < count; ++k) {
    Sample& sample = measurement->samples[k];
    sample.wi = wi_rows[k];
    sample.wo = wo_rows[k];
    sample.value = rgb_rows[k].array();
    sample.missing = !sample.value.allFinite();
  }
  if (!sigma.is_none()) {
    for (const Vec3& row : Rows(sigma.cast<DirectionArray>(), "sigma", count)) {
      measurement->sigma.push_back(row.array());
    }
  }
  if (!weight.is_none()) {
    const auto weights = weight.cast<py::array_t<double, py::array::forcecast>>();
    if (weights.ndim() != 1 || weights.shape(0) != count) {
      throw UsageError("weight: expected an (N,) array with N = " + std::to_string(count));
    }
    measurement->weight.assign(weights.data(), weights.data() + count);
  }
  if (!metadata.is_none()) {
    for (const auto& [key, value] : metadata.cast<py::dict>()) {
      measurement->metadata[py::str(key)] = py::str(value);
    }
  }
  return measurement;
}

}  // namespace

void RegisterMeasurement(py::module_& module) {
  py::class_<Measurement, MeasurementPointer>(module, "Measurement", R"doc(
A measurement in memory: N samples of (wi, wo, rgb), optional sigma and weight,
and metadata. Directions are unit vectors in the local frame (z = surface normal; wi toward
the light, wo toward the detector); rgb is the BRDF in 1/sr without the cosine factor.

wi, wo, rgb and missing are read-only views into the samples without a copy (their rows are
sizeof(Sample) bytes apart); sigma and weight are read-only views of their own arrays. Use
numpy.array(m.rgb) for a writable copy.

Measurement(wi, wo, rgb, sigma=None, weight=None, metadata=None) builds one from (N, 3) arrays
(copied); rows with a non-finite rgb are marked missing.)doc")
      .def(py::init(&FromArrays), py::arg("wi"), py::arg("wo"), py::arg("rgb"),
           py::arg("sigma") = py::none(), py::arg("weight") = py::none(),
           py::arg("metadata") = py::none())
      .def_property_readonly(
          "wi",
          [](const py::object& self) {
            return SampleView(self, [](const Sample& s) { return s.wi.data(); });
          },
          "(N, 3) float64 view: unit directions toward the light")
      .def_property_readonly(
          "wo",
          [](const py::object& self) {
            return SampleView(self, [](const Sample& s) { return s.wo.data(); });
          },
          "(N, 3) float64 view: unit directions toward the detector")
      .def_property_readonly(
          "rgb",
          [](const py::object& self) {
            return SampleView(self, [](const Sample& s) { return s.value.data(); });
          },
          "(N, 3) float64 view: the BRDF in 1/sr, no cosine factor")
      .def_property_readonly(
          "missing",
          [](const py::object& self) {
            const Measurement& measurement = self.cast<const Measurement&>();
            const py::ssize_t rows = measurement.samples.size();
            return View(rows > 0 ? &measurement.samples.front().missing : nullptr, rows, 0,
                        sizeof(Sample), self);
          },
          "(N,) bool view: samples the instrument has no value for (e.g. MERL's negative cells)")
      .def_property_readonly(
          "sigma",
          [](const py::object& self) -> py::object {
            const Measurement& measurement = self.cast<const Measurement&>();
            if (!measurement.has_sigma()) return py::none();
            return View(measurement.sigma.front().data(), measurement.sigma.size(), 3, sizeof(Rgb),
                        self);
          },
          "(N, 3) float64 view: one standard deviation per sample, or None")
      .def_property_readonly(
          "weight",
          [](const py::object& self) -> py::object {
            const Measurement& measurement = self.cast<const Measurement&>();
            if (!measurement.has_weight()) return py::none();
            return View(measurement.weight.data(), measurement.weight.size(), 0, sizeof(double),
                        self);
          },
          "(N,) float64 view: per-sample weights, or None")
      .def_property_readonly(
          "metadata", [](const Measurement& m) { return StringMap(m.metadata); },
          "dict of str: what the reader or instrument states (sample, units, illuminant, ...)")
      .def_readonly("format", &Measurement::format, "the reader's name, e.g. 'astm' or 'merl'")
      .def_readonly("source", &Measurement::source, "the path it was read from")
      .def_property_readonly(
          "tabulated", [](const Measurement& m) { return m.tabulated != nullptr; },
          "True when the reader offers an evaluator between the samples (MERL, RGL-EPFL)")
      .def(
          "eval",
          [](const Measurement& m, const DirectionArray& wi, const DirectionArray& wo) {
            if (m.tabulated == nullptr) {
              throw UsageError(m.source + ": " + m.format +
                               " data have no table evaluator (tabulated is False)");
            }
            const TabulatedBrdf& table = *m.tabulated;
            return EvalRows(wi, wo,
                            [&table](const Vec3& a, const Vec3& b) { return table.Eval(a, b); });
          },
          py::arg("wi"), py::arg("wo"), R"doc(
f(wi, wo) in 1/sr from the reader's table evaluator (tabulated readers only; NaN where the table
has no value). wi, wo: (N, 3) arrays of unit directions, or one (3,) direction for every row.
Returns (N, 3) float64.)doc")
      .def(
          "save",
          [](const Measurement& m, const std::string& path, const std::string& format) {
            py::gil_scoped_release release;
            return WriteMeasurement(m, path, format).warnings;
          },
          py::arg("path"), py::arg("format") = "", R"doc(
Writes the measurement as `brdf convert` and `brdf measure` do (native CSV, .csv; MERL,
.binary), atomically. format: a format name, or "" to choose by extension. Returns the writer's
warnings (a list of str).)doc")
      .def("__len__", [](const Measurement& m) { return m.samples.size(); })
      .def("__repr__", [](const Measurement& m) {
        return "<brdfkit.Measurement " + m.format + " '" + m.source + "', " +
               std::to_string(m.samples.size()) + " samples>";
      });

  module.def(
      "read",
      [](const std::string& path, const std::string& illuminant) {
        ReadOptions options;
        options.illuminant = ParseIlluminant(illuminant);
        py::gil_scoped_release release;
        return std::make_shared<Measurement>(ReadMeasurement(path, options));
      },
      py::arg("path"), py::arg("illuminant") = "D65", R"doc(
Reads a measurement file of any format `brdf info` reads (native CSV, MERL .binary, ASTM,
pbrt-v2 .brdf, Zemax and RGL-EPFL .bsdf, ALTA), detected by content.

path:       the file.
illuminant: for spectral files (ASTM, pbrt-v2), the illuminant under which they become RGB:
            "D65" (default) or "E".

Returns a Measurement. Raises InputError (with .path and .line or .byte) for a broken file.)doc");

  module.def(
      "measure",
      [](const std::string& sample, const std::string& schedule, const std::string& instrument,
         uint64_t seed, int threads) {
        gonio::MeasureOptions options;
        options.sample = sample;
        options.schedule = schedule;
        options.seed = seed;
        if (!instrument.empty()) {
          options.instrument = gonio::ReadInstrument(instrument);
          options.instrument_name = instrument;
        }
        py::gil_scoped_release release;
        const ThreadLimit limit(threads);
        const gonio::Schedule parsed = gonio::MakeSchedule(schedule);
        return std::make_shared<Measurement>(gonio::Measure(options, parsed));
      },
      py::arg("sample"), py::arg("schedule") = "hemisphere", py::arg("instrument") = "",
      py::arg("seed") = 1, py::arg("threads") = 0, R"doc(
The virtual gonioreflectometer, as `brdf measure`; the same seed gives the same
samples, bit for bit, whatever the thread count.

sample:     "model:MODEL" (a flat analytic sample; MODEL a model string or FIT.json),
            "surface:FILE.json" (ray-traced micro-geometry) or "sphere:MODEL" (image-based:
            a camera views a rasterized sphere).
schedule:   "inplane[:step=D]", "hemisphere[:theta_i_step=D:theta_o_step=D:phi_o_step=D]"
            (default "hemisphere"), "merl", "equal-area:cells=N[:theta_i_step=D]" or
            "adaptive[:theta_i_step=D:base_step=D]" (degrees).
instrument: path of an instrument JSON file ("" = the default instrument; see docs/gonio.md).
seed:       random seed (default 1).
threads:    worker threads, 0 = all cores; the result does not depend on it.

Returns a Measurement (with sigma). Save it with Measurement.save(path).)doc");
}

}  // namespace brdf::python
