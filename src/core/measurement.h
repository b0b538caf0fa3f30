// The in-memory measurement every file format becomes (DESIGN §4): samples of
// (wi, wo, rgb, optional sigma, optional weight) plus metadata. Readers never guess silently:
// what they assume (units, illuminant, symmetry) is stated in the metadata.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/vec.h"

namespace brdf {

struct Sample {
  Vec3 wi;               // unit, toward the light (DESIGN §1)
  Vec3 wo;               // unit, toward the detector
  Rgb value;             // BRDF in sr^-1, no cosine factor
  bool missing = false;  // the instrument has no value here (e.g. MERL's negative entries)
};

struct Measurement {
  std::string format;  // the reader's name, e.g. "merl"
  std::string source;  // the path it was read from
  // Ordered key -> value metadata ("sample", "instrument", "illuminant", "units", ...).
  std::map<std::string, std::string> metadata;
  std::vector<Sample> samples;
  std::vector<Rgb> sigma;      // empty, or one standard deviation per sample
  std::vector<double> weight;  // empty, or one weight per sample

  bool has_sigma() const { return !sigma.empty(); }
  bool has_weight() const { return !weight.empty(); }
  // The "sample" metadata, or the file name when there is none.
  std::string SampleName() const;
};

// What `brdf info` reports about a measurement.
struct MeasurementSummary {
  std::string format;
  std::string sample_name;
  size_t samples = 0;
  size_t missing = 0;              // samples flagged missing
  size_t negative = 0;             // present channel values < 0
  size_t nan = 0;                  // present channel values that are NaN or infinite
  double theta_i_deg[2] = {0, 0};  // min, max over present samples
  double theta_o_deg[2] = {0, 0};
  size_t incidence_directions = 0;  // distinct wi (to 1e-6 rad)
  Rgb min = Rgb::Zero();            // per channel, over finite present values
  Rgb max = Rgb::Zero();
};
MeasurementSummary Summarize(const Measurement& measurement);

}  // namespace brdf
