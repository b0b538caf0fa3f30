// The tone options as a user types them (`brdf tonemap`/`brdf render` options, the keywords of
// the Python module's tonemap and render), and their one conversion to ToneOptions (DESIGN §8).
#pragma once

#include <string>

#include "hdr/pipeline.h"

namespace brdf {

// As typed; Resolve() parses and validates.
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

  // Throws UsageError naming the option (by its command-line spelling) that is wrong.
  ToneOptions Resolve() const;
};

}  // namespace brdf
