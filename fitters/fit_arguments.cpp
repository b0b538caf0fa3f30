#include "fitters/fit_arguments.h"

#include "fitters/fit_samples.h"
#include "gonio/instrument.h"
#include "models/registry.h"

namespace brdf::fitters {

FitOptions FitArguments::ToFitOptions(int threads) const {
  if (!Automatic()) FindModel(model);  // a bad name fails here, before any file is read
  FitOptions options;
  options.loss = ParseLoss(loss);
  options.robust = ParseRobust(robust);
  options.max_samples = max_samples;
  options.seed = seed;
  options.threads = threads;
  options.max_iterations = max_iterations;
  options.grey_specular = grey_specular;
  options.Validate();
  return options;
}

bool FitArguments::UsesEvaluator() const {
  const Loss parsed = ParseLoss(loss);
  return Automatic() || parsed == Loss::kImage || parsed == Loss::kAuto;
}

brdf::ReadOptions FitArguments::ToReadOptions() const {
  brdf::ReadOptions options;
  options.illuminant = ParseIlluminant(illuminant);
  options.reciprocal = reciprocal;
  return options;
}

Measurement ReadForFit(const std::string& path, const FitArguments& arguments,
                       bool samples_wanted) {
  const ReadOptions read_options = arguments.ToReadOptions();
  const Loss loss = ParseLoss(arguments.loss);
  // Only `image`, or `auto` on data with an evaluator, fits the rendered spheres alone.
  if (!samples_wanted && (loss == Loss::kImage || loss == Loss::kAuto)) {
    std::optional<Measurement> table = ReadEvaluator(path, read_options);
    if (table && ResolveLoss(loss, *table) == Loss::kImage) {
      return std::move(*table);
    }
  }
  Measurement measurement = ReadMeasurement(path, read_options);
  if (!arguments.UsesEvaluator()) measurement.tabulated.reset();
  return measurement;
}

void ApplyInstrument(const std::string& instrument, Measurement* measurement) {
  if (instrument.empty()) return;
  if (instrument == "none") {
    measurement->metadata.erase(kInstrumentKey);
    return;
  }
  measurement->metadata[kInstrumentKey] = gonio::ReadInstrument(instrument).ToJson();
}

}  // namespace brdf::fitters
