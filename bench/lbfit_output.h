// Reads what lbfit prints on stdout: one block per model,
//
//   [Unreal Engine 4]
//   Base color: 0.0148152 0.0388612 0.107134
//   Metallic: 0
//   ...
//   Error: 0.0156313
//
// a heading in brackets, `Name: value(s)` lines (a colour is three numbers), lbfit's own error
// last, blank lines between blocks. Every block must be one of lbfit_models.h's kinds with all
// its parameters; anything else is a ParseError naming the file and line.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "lbfit_models.h"

namespace brdf::lbfit {

struct PrintedFit {
  const ModelKind* kind;
  PrintedParameters parameters;  // without "Error"
  double lbfit_error;            // lbfit's own error (its SpecularCoordinatesBrdf comparison)
};

// `path` names the text in error messages.
std::vector<PrintedFit> ParseLbfitOutput(const std::string& path, std::string_view text);
std::vector<PrintedFit> ReadLbfitOutput(const std::string& path);

}  // namespace brdf::lbfit
