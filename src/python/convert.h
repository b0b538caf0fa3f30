// Conversions between numpy/Python values and the library's types. Nothing here computes
// anything of its own: direction arrays in, the library's evaluators called per row, arrays
// out; JSON reports become dicts.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/vec.h"

namespace brdf::python {

namespace py = pybind11;

using DirectionArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// The rows two direction arrays pair up: (N, 3) with (N, 3), or one of them a single (3,)
// direction used for every row. Throws UsageError for any other shape.
struct DirectionPairs {
  py::ssize_t rows = 0;
  bool wi_single = false, wo_single = false;
};
DirectionPairs PairDirections(const DirectionArray& wi, const DirectionArray& wo);

// f(wi, wo) for every row (PairDirections), the GIL released during the loop. Returns (N, 3)
// float64, or (3,) when both inputs are single directions.
template <typename Eval>
py::array_t<double> EvalRows(const DirectionArray& wi, const DirectionArray& wo, Eval&& eval) {
  const DirectionPairs pairs = PairDirections(wi, wo);
  py::array_t<double> result = pairs.wi_single && pairs.wo_single
                                   ? py::array_t<double>({py::ssize_t{3}})
                                   : py::array_t<double>({pairs.rows, py::ssize_t{3}});
  const double* wi_data = wi.data();
  const double* wo_data = wo.data();
  double* out = result.mutable_data();
  {
    py::gil_scoped_release release;
    for (py::ssize_t row = 0; row < pairs.rows; ++row) {
      const double* a = wi_data + (pairs.wi_single ? 0 : 3 * row);
      const double* b = wo_data + (pairs.wo_single ? 0 : 3 * row);
      const Rgb f = eval(Vec3(a[0], a[1], a[2]), Vec3(b[0], b[1], b[2]));
      for (int c = 0; c < 3; ++c) out[3 * row + c] = f[c];
    }
  }
  return result;
}

// A JSON value as the Python object `json.loads` would give for the library's JSON text
// (non-finite numbers, written as null, become None).
py::object JsonToPython(const nlohmann::json& value);

py::dict StringMap(const std::map<std::string, std::string>& map);

// "auto" or a positive number, as the command line's text: a Python number becomes the
// shortest text that reads back to the same double (Python's repr).
std::string NumberOrAuto(const py::object& value, const char* keyword);

// A str, or a list/tuple of str (a repeatable command-line option).
std::vector<std::string> StringList(const py::object& value, const char* keyword);

}  // namespace brdf::python
