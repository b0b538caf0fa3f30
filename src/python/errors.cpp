#include "python/errors.h"

#include <string>

#include "core/errors.h"

namespace brdf::python {
namespace {

namespace py = pybind11;

// The classes live as long as the interpreter (the module holds them too); plain handles
// avoid running Python code from static destructors.
struct ExceptionClasses {
  py::handle error, usage, input, output, computation, convergence;
};
ExceptionClasses classes;

py::handle NewClass(py::module_& module, const char* name, const char* doc, py::handle bases) {
  const std::string qualified = std::string("brdfkit.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (type == nullptr) throw py::error_already_set();
  module.add_object(name, py::handle(type));  // steals nothing: add_object increfs
  return py::handle(type);
}

// Raises `type(message)` with extra attributes set on the instance.
void Raise(py::handle type, const char* message, const py::dict& attributes) {
  py::object instance = py::reinterpret_borrow<py::object>(type)(message);
  for (const auto& [key, value] : attributes) {
    instance.attr(key) = value;
  }
  PyErr_SetObject(type.ptr(), instance.ptr());
}

}  // namespace

void RegisterErrors(py::module_& module) {
  classes.error =
      NewClass(module, "Error", "Base class of every brdfkit error.", py::handle(PyExc_Exception));
  classes.usage =
      NewClass(module, "UsageError",
               "A bad argument: an unknown model or option value, an array of the wrong shape (a "
               "ValueError; the CLI's exit status 2).",
               py::make_tuple(classes.error, py::handle(PyExc_ValueError)).release());
  classes.input = NewClass(
      module, "InputError",
      "A file that cannot be read or is not what it claims to be. Attributes: path (the file), "
      "line (1-based, text files) and byte (0-based offset, binary files), None where the error "
      "has no position.",
      classes.error);
  classes.output = NewClass(module, "OutputError",
                            "An output that cannot be written. Attribute: path.", classes.error);
  classes.computation =
      NewClass(module, "ComputationError", "A computation that failed (the CLI's exit status 3).",
               classes.error);
  classes.convergence = NewClass(
      module, "ConvergenceWarning",
      "Warned by fit() when the fit did not converge; the FitResult says so (converged is False) "
      "and keeps the report, as `brdf fit` does.",
      py::handle(PyExc_RuntimeWarning));

  py::register_exception_translator([](std::exception_ptr pointer) {
    try {
      if (pointer) std::rethrow_exception(pointer);
    } catch (const ParseError& error) {
      Raise(classes.input, error.what(),
            py::dict(py::arg("path") = error.path(), py::arg("line") = error.line(),
                     py::arg("byte") = py::none()));
    } catch (const ByteError& error) {
      Raise(classes.input, error.what(),
            py::dict(py::arg("path") = error.path(), py::arg("line") = py::none(),
                     py::arg("byte") = error.offset()));
    } catch (const InputError& error) {
      Raise(classes.input, error.what(),
            py::dict(py::arg("path") = error.path(), py::arg("line") = py::none(),
                     py::arg("byte") = py::none()));
    } catch (const OutputError& error) {
      Raise(classes.output, error.what(), py::dict(py::arg("path") = error.path()));
    } catch (const UsageError& error) {
      Raise(classes.usage, error.what(), py::dict());
    } catch (const ComputeError& error) {
      Raise(classes.computation, error.what(), py::dict());
    } catch (const Error& error) {
      Raise(classes.error, error.what(), py::dict());
    }
  });
}

py::handle ConvergenceWarning() { return classes.convergence; }

void Warn(const std::string& message) {
  if (PyErr_WarnEx(PyExc_UserWarning, message.c_str(), 1) != 0) throw py::error_already_set();
}

}  // namespace brdf::python
