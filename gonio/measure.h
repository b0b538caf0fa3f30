// The virtual gonioreflectometer's run (DESIGN §5): a sample, a schedule and an instrument in,
// a calibrated Measurement out (BRDF in sr^-1 with one-sigma noise per reading and metadata
// saying what was modelled). Deterministic for a seed whatever the thread count: every random
// number comes from a stream derived from (seed, purpose, index) (rng.h).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "core/measurement.h"
#include "gonio/instrument.h"
#include "gonio/sample.h"
#include "gonio/schedule.h"

namespace brdf::gonio {

struct MeasureOptions {
  std::string sample = "model:lambert";  // model:MODEL | surface:FILE.json | sphere:MODEL
  std::string schedule = "hemisphere";
  Instrument instrument;
  std::string instrument_name = "default";  // the file it came from, for the metadata
  uint64_t seed = 1;
  // Called with the number of finished readings (or views) on rank 0's main thread; may be empty.
  std::function<void(int64_t)> advance;
};

// Builds the sample of `spec` (model: or surface:); sphere: is an acquisition of its own.
// Throws UsageError / InputError naming the spec or file.
std::unique_ptr<GonioSample> MakeSample(const std::string& spec, const Instrument& instrument);

// Readings a run will make (for a progress bar's total).
int64_t CountReadings(const MeasureOptions& options, const Schedule& schedule);

// Under mpirun the incidences (the sphere's light positions) are split across the ranks
// (core/parallel_ranks.h); the returned Measurement is complete on rank 0 and holds only the
// metadata on the others. `advance` is called on rank 0 for every rank's finished readings.
Measurement Measure(const MeasureOptions& options, const Schedule& schedule);

// One standard deviation of the reading at nominal (wi, wo) caused by the arms' positioning
// jitter (Instrument::jitter_deg), propagated to first order through the sample's own
// noise-free reading (GonioSample::ExpectedReading); a sample without one gets the detector
// cosine's share only, a lower bound. `reading` is the measured R, used by that fallback.
// Without this term the stated sigma leaves out an error that grows as tan(theta_o) toward
// grazing and along a lobe's flanks (docs/gonio.md).
// Without `light_arm`, the detector arm's share alone (the light arm moves once per incidence,
// so its share is common to the incidence's readings).
Rgb PositioningSigma(const GonioSample& sample, const Instrument& instrument, const Vec3& wi,
                     const Vec3& wo, const Rgb& reading, bool light_arm = true);

// The noise-free reading R of the instrument's Lambertian reference at its reference geometry,
// through the instrument's apertures: what every calibrated value is divided by.
double ReferenceReading(const Instrument& instrument);

// Converts expected detector readings into calibrated BRDF values the way the instrument does
// (instrument.h): photon counts with shot and read noise, divided by the reference's counts.
class Calibration {
 public:
  // `reference_reading` is R of the Lambertian reference at the reference geometry, measured
  // with the same instrument; its `readings` noisy counts are averaged once per run.
  Calibration(const Instrument& instrument, double reference_reading, uint64_t seed);

  // BRDF value and one-sigma uncertainty for reading R at nominal detector polar cosine
  // `cos_theta_o`, drawing noise from `rng_index`'s stream.
  void Calibrate(const Rgb& reading, double cos_theta_o, uint64_t rng_index, Rgb* value,
                 Rgb* sigma) const;
  // The same for a ratio to a reference reading taken at the same geometry (the image-based
  // acquisition images a reference sphere): value = counts/counts_ref · rho/π.
  void CalibrateRatio(const Rgb& reading, const Rgb& reference_reading, uint64_t rng_index,
                      Rgb* value, Rgb* sigma) const;

  double reference_counts() const { return reference_counts_; }
  // The one-sigma uncertainty Calibrate states for reading R, before any noise is drawn (the
  // expected counts in place of noisy ones): the noise model a plan is designed against. The
  // stated sigma includes the run reference's error, ratio · sigma_ref, which is the same for
  // every reading of the run; without `include_reference` it is left out, leaving the part that
  // is independent from one reading to the next.
  Rgb ExpectedSigma(const Rgb& reading, double cos_theta_o, bool include_reference = true) const;
  // Relative variance of the run's reference (the mean of its readings): an error common to
  // every calibrated value of the run, which no choice of geometries averages away.
  double ReferenceRelativeVariance() const;
  // d(value)/d(reading) of Calibrate: how an error of the reading becomes an error of the BRDF.
  double Slope(double cos_theta_o) const;

 private:
  double ExpectedCounts(double reading) const;
  // counts / counts_ref and its one-sigma uncertainty; the reference is the run's, or read at
  // the same geometry when `reference_reading` is given.
  void Ratio(const Rgb& reading, const Rgb* reference_reading, uint64_t rng_index, Rgb* ratio,
             Rgb* sigma) const;

  const Instrument& instrument_;
  uint64_t seed_;
  double ideal_reference_reading_;    // R_norm = (rho_ref/π) cos(theta_o,ref)
  double reference_counts_;           // mean of the reference readings
  double reference_expected_counts_;  // their expectation
  double reference_counts_variance_;
};

// The variance `Measure` states for one reading: the calibration's (detector noise), a traced
// sample's Monte Carlo error and the positioning term, the last two carried over by the
// calibration's slope. Every sigma of the instrument is combined here.
Rgb CombinedSigma(const Rgb& calibration_sigma, const Rgb& sample_error, const Rgb& positioning,
                  double slope);

// The sigma `Measure` will state for each reading of `sample` at nominal (wi, wo), known before
// the measurement (the sample's noise-free reading in place of a noisy one): what `brdf plan`
// weights the Fisher information by. Needs a sample with an expected reading (model:).
class NoiseModel {
 public:
  // Throws UsageError when the sample has no expected reading.
  NoiseModel(const GonioSample& sample, const Instrument& instrument);
  Rgb Sigma(const Vec3& wi, const Vec3& wo) const;
  // The part of Sigma that is independent from reading to reading: all of it but the run
  // reference's error, which is common to every reading (CommonScaleVariance), and the light
  // arm's jitter, common to the readings of one incidence (LightArmVariance). At a bright peak
  // those common parts dominate the stated sigma (the reference's variance grows as the square
  // of the reading, the counts' own as the reading), so a fit's scatter follows this, not Sigma.
  Rgb IndependentSigma(const Vec3& wi, const Vec3& wo) const;
  // The detector's own noise (shot and read), independent per reading and per channel: the
  // IndependentSigma without the detector arm's jitter, which moves a reading's three
  // channels together (DetectorArmVariance).
  Rgb CountSigma(const Vec3& wi, const Vec3& wo) const;
  // Variance (radians², per axis) of the detector arm's jitter, drawn once per reading: the
  // instrument's one jitter, as the light arm's.
  double DetectorArmVariance() const { return LightArmVariance(); }
  // Relative variance of the scale error common to every value of a run (the reference).
  double CommonScaleVariance() const { return calibration_.ReferenceRelativeVariance(); }
  // Variance (radians², per axis) of the light arm's jitter, common to an incidence's readings.
  double LightArmVariance() const;

 private:
  Rgb SigmaOf(const Vec3& wi, const Vec3& wo, bool include_common) const;

  const GonioSample& sample_;
  const Instrument& instrument_;
  Calibration calibration_;
};

}  // namespace brdf::gonio
