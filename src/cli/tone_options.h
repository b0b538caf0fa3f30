// The tone options shared by `brdf tonemap` and `brdf render` (DESIGN §8), defined once: the
// command-line spelling, the help text with defaults, and the conversion to ToneOptions.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "hdr/pipeline.h"

namespace brdf::cli {

// As typed on the command line; Resolve() parses and validates.
struct ToneArguments {
  std::string tone_operator = "reinhard-extended";
  std::string exposure = "auto";
  double ev = 0.0;
  bool ev_given = false;
  double key = 0.18;
  std::string white = "auto";
  std::string bloom = "none";
  double bloom_threshold = 1.0;
  double bloom_strength = 0.1;
  double bloom_sigma = 13.0;
  std::string gamma = "srgb";

  ToneOptions Resolve() const;
};

// Registers --operator, --exposure, --ev, --key, --white, --bloom, --bloom-threshold,
// --bloom-strength, --bloom-sigma and --gamma on `app`.
void AddToneOptions(CLI::App* app, ToneArguments* arguments);

}  // namespace brdf::cli
