#include "fitters/fit_arguments.h"

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

void ApplyInstrument(const std::string& instrument, Measurement* measurement) {
  if (instrument.empty()) return;
  if (instrument == "none") {
    measurement->metadata.erase(kInstrumentKey);
    return;
  }
  measurement->metadata[kInstrumentKey] = gonio::ReadInstrument(instrument).ToJson();
}

}  // namespace brdf::fitters
