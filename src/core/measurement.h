// The in-memory measurement every file format becomes (DESIGN §4): samples of
// (wi, wo, rgb, optional sigma, optional weight) plus metadata. Readers never guess silently:
// what they assume (units, illuminant, symmetry) is stated in the metadata.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/vec.h"

namespace brdf {

inline constexpr const char* kWeightingKey = "weighting";
inline constexpr const char* kEqualWeighting = "equal";

struct Sample {
  Vec3 wi;               // unit, toward the light (DESIGN §1)
  Vec3 wo;               // unit, toward the detector
  Rgb value;             // BRDF in sr^-1, no cosine factor
  bool missing = false;  // the instrument has no value here (e.g. MERL's negative entries)
};

// A reader's evaluator for dense tabulated data (MERL tables, RGL-EPFL tensors; DESIGN §4), or a
// model standing in for one (ModelAsMeasurement, models/model_source.h): a
// capability consumers ask for instead of testing format names. Energy, render, fit and convert
// use it when present; data without one go through scattered interpolation.
class TabulatedBrdf {
 public:
  virtual ~TabulatedBrdf() = default;
  // f(wi, wo) in sr^-1, no cosine factor (DESIGN §1); NaN where the table has no value (e.g.
  // a MERL cell marked missing). Consumers ask only above the horizon.
  virtual Rgb Eval(const Vec3& wi, const Vec3& wo) const = 0;
  // One line for reports: what the table is and how it is evaluated.
  virtual std::string Describe() const = 0;
  // Short name of the evaluation, e.g. "MERL table lookup", for a preview's summary line.
  virtual std::string LookupName() const = 0;
  // The evaluator a preview draws with, where it differs from this one (DESIGN §8): no holes (a
  // lookup on a cell without a value takes the nearest cell that has one, so that a sphere
  // shows no black spots) and values interpolated in the table's own coordinates. Null: this
  // one serves. Energy, fits and conversions keep Eval, whose NaN counts a hole as a hole.
  virtual std::shared_ptr<const TabulatedBrdf> PreviewEvaluator() const { return nullptr; }
};

// The measure dwi dwo (sr^2) of the table cell that a dense table's sample at (wi, wo) stands
// for: the solid-angle weight a fit gives it. A capability of its own beside the evaluator, set
// by the same readers: it needs the table's grid, not its values, so a consumer that only
// weighs the samples (a fit) can let the evaluator go and keep this.
class CellMeasure {
 public:
  virtual ~CellMeasure() = default;
  virtual double Measure(const Vec3& wi, const Vec3& wo) const = 0;
  // A few words saying what it is, for the fit report's weighting line.
  virtual std::string Name() const = 0;
};

struct Measurement {
  std::string format;  // the reader's name, e.g. "merl"
  std::string source;  // the path it was read from
  // Ordered key -> value metadata ("sample", "instrument", "illuminant", "units", ...).
  std::map<std::string, std::string> metadata;
  std::vector<Sample> samples;
  std::vector<Rgb> sigma;      // empty, or one standard deviation per sample
  std::vector<double> weight;  // empty, or one weight per sample
  // Set by readers of dense tables: evaluates between the samples (see TabulatedBrdf).
  std::shared_ptr<const TabulatedBrdf> tabulated;
  // Set with `tabulated`, by the same readers: the measure of each sample's cell.
  std::shared_ptr<const CellMeasure> cell_measure;

  bool has_sigma() const { return !sigma.empty(); }
  bool has_weight() const { return !weight.empty(); }
  // Metadata "weighting: equal": the geometries were chosen one by one (a designed schedule,
  // `brdf plan`), so a fit weighs the samples equally instead of by the solid angle each
  // stands for (fitters/fit_samples.h).
  bool equal_weighting() const;
  // The "sample" metadata, else the "description" (RGL-EPFL files), else the file name.
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
