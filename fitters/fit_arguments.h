// The fit's options as a user gives them, by name (DESIGN §3, §6): `--model`, `--loss`, ... of
// `brdf fit` and `brdf batch`, and the keywords of brdfkit.fit. One parse and one validation
// for all of them.
#pragma once

#include <cstdint>
#include <string>

#include "fitters/fit.h"
#include "io/formats.h"

namespace brdf::fitters {

struct FitArguments {
  std::string model = "auto";
  // By the data (fit_samples.h: ResolveLoss): `image` for tables that can be rendered (it wins
  // the MERL benchmark in image space, docs/real-data.md), `l2` for readings that state their
  // noise, `sqrt` otherwise.
  std::string loss = "auto";
  std::string robust = "none";
  size_t max_samples = FitOptions{}.max_samples;
  uint64_t seed = 1;
  int max_iterations = FitOptions{}.max_iterations;
  bool grey_specular = false;
  std::string illuminant = "D65";
  bool reciprocal = false;  // RGL-EPFL files: the reciprocal reading (ReadOptions::reciprocal)

  bool Automatic() const { return model == "auto"; }
  // Whether the fit renders a measurement that has an evaluator (Measurement::tabulated): the
  // image loss fits the pixels of its rendered spheres, and `auto` chooses by its image error
  // (select.h).
  bool UsesEvaluator() const;
  // Checks the model name (a usage error names the known ones) and the numbers.
  FitOptions ToFitOptions(int threads) const;
  brdf::ReadOptions ToReadOptions() const;
};

// Reads a measurement for a fit with `arguments` (`brdf fit`, `brdf batch`, brdfkit.fit). Its table
// evaluator (Measurement:: tabulated, a second 35 MB copy of a MERL table's values) is kept only
// when the fit renders the measurement (FitArguments::UsesEvaluator: the image loss, `auto`'s
// image-space choice); otherwise it is let go before the fit's peak of memory. Its samples are not
// made when the fit never reads them: under the image loss it fits the evaluator's rendered
// spheres, so a format that can hand out its evaluator alone (io/formats.h: ReadEvaluator; a MERL
// table) is asked for just that, unless the caller wants the samples too (`fit --plot` draws them).
Measurement ReadForFit(const std::string& path, const FitArguments& arguments,
                       bool samples_wanted = false);

// `brdf fit --instrument`, the instrument the readings are fitted through (DESIGN §6): ""
// leaves the one the measurement records, if any; "none" removes it (the model at the nominal
// directions); a JSON file is recorded in the measurement (fit_samples.h: kInstrumentKey).
// Throws InputError naming a bad instrument file.
void ApplyInstrument(const std::string& instrument, Measurement* measurement);

}  // namespace brdf::fitters
