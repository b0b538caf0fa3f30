#include "python/convert.h"

#include <cmath>

#include "core/errors.h"

namespace brdf::python {
namespace {

// Rows of a direction array: (N, 3) gives N, (3,) gives 1 and a broadcast flag.
py::ssize_t DirectionRows(const DirectionArray& array, const char* name, bool* single) {
  if (array.ndim() == 1 && array.shape(0) == 3) {
    *single = true;
    return 1;
  }
  if (array.ndim() == 2 && array.shape(1) == 3) {
    *single = false;
    return array.shape(0);
  }
  std::string shape = "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d) {
    shape += (d > 0 ? ", " : "") + std::to_string(array.shape(d));
  }
  throw UsageError(std::string(name) + ": expected an (N, 3) array of directions or one (3,) " +
                   "direction, got shape " + shape + (array.ndim() == 1 ? ",)" : ")"));
}

}  // namespace

DirectionPairs PairDirections(const DirectionArray& wi, const DirectionArray& wo) {
  DirectionPairs pairs;
  const py::ssize_t wi_rows = DirectionRows(wi, "wi", &pairs.wi_single);
  const py::ssize_t wo_rows = DirectionRows(wo, "wo", &pairs.wo_single);
  if (!pairs.wi_single && !pairs.wo_single && wi_rows != wo_rows) {
    throw UsageError("wi has " + std::to_string(wi_rows) + " rows and wo " +
                     std::to_string(wo_rows) + ": expected the same number (or one direction)");
  }
  pairs.rows = pairs.wi_single ? wo_rows : wi_rows;
  return pairs;
}

py::object JsonToPython(const nlohmann::json& value) {
  switch (value.type()) {
    case nlohmann::json::value_t::null:
      return py::none();
    case nlohmann::json::value_t::boolean:
      return py::bool_(value.get<bool>());
    case nlohmann::json::value_t::number_integer:
      return py::int_(value.get<int64_t>());
    case nlohmann::json::value_t::number_unsigned:
      return py::int_(value.get<uint64_t>());
    case nlohmann::json::value_t::number_float: {
      const double number = value.get<double>();
      if (!std::isfinite(number)) return py::none();
      return py::float_(number);
    }
    case nlohmann::json::value_t::string:
      return py::str(value.get_ref<const std::string&>());
    case nlohmann::json::value_t::array: {
      py::list list;
      for (const nlohmann::json& item : value) list.append(JsonToPython(item));
      return std::move(list);
    }
    case nlohmann::json::value_t::object: {
      py::dict dict;
      for (const auto& [key, item] : value.items()) dict[py::str(key)] = JsonToPython(item);
      return std::move(dict);
    }
    default:
      return py::none();
  }
}

py::dict StringMap(const std::map<std::string, std::string>& map) {
  py::dict dict;
  for (const auto& [key, text] : map) dict[py::str(key)] = py::str(text);
  return dict;
}

std::string NumberOrAuto(const py::object& value, const char* keyword) {
  if (value.is_none()) return "auto";
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value)) {
    return py::repr(py::float_(value)).cast<std::string>();
  }
  throw UsageError(std::string(keyword) + ": expected 'auto' or a number, got " +
                   py::repr(value).cast<std::string>());
}

std::vector<std::string> StringList(const py::object& value, const char* keyword) {
  if (value.is_none()) return {};
  if (py::isinstance<py::str>(value)) return {value.cast<std::string>()};
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    std::vector<std::string> items;
    for (const py::handle item : value) {
      if (!py::isinstance<py::str>(item)) {
        throw UsageError(std::string(keyword) + ": expected strings, got " +
                         py::repr(item).cast<std::string>());
      }
      items.push_back(item.cast<std::string>());
    }
    return items;
  }
  throw UsageError(std::string(keyword) + ": expected a string or a list of strings, got " +
                   py::repr(value).cast<std::string>());
}

}  // namespace brdf::python
