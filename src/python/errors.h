// brdfkit's exceptions (DESIGN §10) and the translation of the library's typed errors
// (core/errors.h) into them, at the module boundary:
//   UsageError   -> brdfkit.UsageError (a ValueError)
//   InputError   -> brdfkit.InputError, with .path and .line (ParseError) or .byte (ByteError)
//   OutputError  -> brdfkit.OutputError, with .path
//   ComputeError -> brdfkit.ComputationError
// All derive from brdfkit.Error. A fit that did not converge is not an exception (its result
// says so, as the CLI's report does): it warns with brdfkit.ConvergenceWarning.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

namespace brdf::python {

void RegisterErrors(pybind11::module_& module);

// The warning category of a fit that did not converge.
pybind11::handle ConvergenceWarning();

// Issues a UserWarning (Python's warnings module): a finding the caller should see, not an error.
void Warn(const std::string& message);

}  // namespace brdf::python
