#include "gonio/measure.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/angles.h"
#include "core/errors.h"
#include "core/parallel_ranks.h"
#include "core/text.h"
#include "gonio/model_sample.h"
#include "gonio/rng.h"
#include "gonio/sampling.h"
#include "gonio/sphere_acquisition.h"
#include "gonio/surface_sample.h"
#include "models/model_source.h"

namespace brdf::gonio {
namespace {

constexpr const char* kSampleKinds = "model:MODEL, surface:FILE.json or sphere:MODEL";

Model LoadSampleModel(const std::string& spec, const std::string& model_spec) {
  if (model_spec.empty()) throw UsageError("sample '" + spec + "': no model after the colon");
  return LoadModel(model_spec);
}

std::string InstrumentSummary(const Instrument& instrument) {
  std::string text = instrument.source_kind == Instrument::SourceKind::kCollimated
                         ? "collimated source, angular radius " +
                               FormatNumber(instrument.source_angular_radius_deg) + " deg"
                         : "point source at " + FormatNumber(instrument.source_distance_m) +
                               " m, spot radius " + FormatNumber(instrument.spot_radius_mm) + " mm";
  text += "; detector " + FormatNumber(instrument.detector_solid_angle_sr) + " sr";
  text += "; jitter " + FormatNumber(instrument.jitter_deg) + " deg";
  if (instrument.photons > 0) {
    text += "; shot noise (" + FormatNumber(instrument.photons) +
            " reference counts), read noise " + FormatNumber(instrument.read_noise) + " counts";
  } else {
    text += "; ideal detector (no shot or read noise)";
  }
  text += "; stray light " + FormatNumber(instrument.stray_light);
  text +=
      "; calibrated against a Lambertian reference rho=" + FormatNumber(instrument.reference_rho) +
      " at " + FormatNumber(instrument.reference_theta_i_deg) + "/" +
      FormatNumber(instrument.reference_theta_o_deg) + " deg (" +
      std::to_string(instrument.reference_readings) + " readings)";
  return text;
}

}  // namespace

double ReferenceReading(const Instrument& instrument) {
  const ModelSample reference(LambertReference(instrument.reference_rho), instrument);
  return reference
      .Reading(instrument, SphericalDirection(DegToRad(instrument.reference_theta_i_deg), 0),
               SphericalDirection(DegToRad(instrument.reference_theta_o_deg), kPi))
      .mean();
}

Rgb PositioningSigma(const GonioSample& sample, const Instrument& instrument, const Vec3& wi,
                     const Vec3& wo, const Rgb& reading, bool light_arm) {
  const double jitter = DegToRad(instrument.jitter_deg);
  if (jitter <= 0) return Rgb::Zero();
  if (!sample.HasExpectedReading()) {
    // Only the detector's cosine is known without the sample's own slope: R ∝ cos(theta_o').
    const Rgb per_cosine = reading / std::max(wo.z(), 1e-12);
    return JitterSigma(wo, jitter, [&](const Vec3& d) -> Rgb { return per_cosine * d.z(); });
  }
  const auto at = [&](const Vec3& light, const Vec3& detector) -> Rgb {
    if (light.z() <= 0 || detector.z() <= 0) return Rgb::Zero();
    return sample.ExpectedReading(instrument, light, detector);
  };
  // The two arms move independently (instrument.h), so their variances add.
  const Rgb detector_arm = JitterSigma(wo, jitter, [&](const Vec3& d) { return at(wi, d); });
  if (!light_arm) return detector_arm;
  const Rgb light = JitterSigma(wi, jitter, [&](const Vec3& d) { return at(d, wo); });
  return (light.square() + detector_arm.square()).sqrt();
}

namespace {

// Photon counts with shot noise plus Gaussian read noise. Above kPoissonLimit counts the
// Poisson law is replaced by its normal approximation, and the two independent Gaussians by one
// of the summed variance (one random draw instead of two).
constexpr double kPoissonLimit = 30;

double NoisyCounts(double expected, double read_variance, Rng* rng) {
  if (expected > kPoissonLimit)
    return expected + std::sqrt(expected + read_variance) * rng->Normal();
  return rng->Poisson(expected) + std::sqrt(read_variance) * rng->Normal();
}

}  // namespace

Calibration::Calibration(const Instrument& instrument, double reference_reading, uint64_t seed)
    : instrument_(instrument),
      seed_(seed),
      ideal_reference_reading_(instrument.reference_rho * kInvPi *
                               std::cos(DegToRad(instrument.reference_theta_o_deg))) {
  const double expected = ExpectedCounts(reference_reading);
  reference_expected_counts_ = expected;
  if (instrument.photons <= 0) {
    reference_counts_ = expected;
    reference_counts_variance_ = 0;
    return;
  }
  double sum = 0;
  for (int r = 0; r < instrument.reference_readings; ++r) {
    Rng rng = StreamRng(seed, Stream::kReferenceNoise, r);
    sum += NoisyCounts(expected, instrument.read_noise * instrument.read_noise, &rng);
  }
  reference_counts_ = sum / instrument.reference_readings;
  reference_counts_variance_ =
      (expected + instrument.read_noise * instrument.read_noise) / instrument.reference_readings;
}

double Calibration::ExpectedCounts(double reading) const {
  // Stray light is lamp light too: it scales with the lamp, so lamp power still cancels.
  const double relative = (reading + instrument_.stray_light * ideal_reference_reading_) /
                          ideal_reference_reading_ * instrument_.lamp_power;
  return instrument_.photons > 0 ? instrument_.photons * relative : relative;
}

double Calibration::Slope(double cos_theta_o) const {
  const double counts_per_reading = ExpectedCounts(1.0) - ExpectedCounts(0.0);
  return counts_per_reading / reference_counts_ * ideal_reference_reading_ / cos_theta_o;
}

Rgb Calibration::ExpectedSigma(const Rgb& reading, double cos_theta_o,
                               bool include_reference) const {
  if (instrument_.photons <= 0) return Rgb::Zero();
  const double read_variance = instrument_.read_noise * instrument_.read_noise;
  const double reference_variance = include_reference ? reference_counts_variance_ : 0.0;
  Rgb sigma;
  for (int c = 0; c < 3; ++c) {
    const double expected = ExpectedCounts(reading[c]);
    const double ratio = expected / reference_expected_counts_;
    sigma[c] = std::sqrt(expected + read_variance + ratio * ratio * reference_variance) /
               reference_expected_counts_;
  }
  return sigma * ideal_reference_reading_ / cos_theta_o;
}

double Calibration::ReferenceRelativeVariance() const {
  return reference_counts_variance_ / (reference_expected_counts_ * reference_expected_counts_);
}

void Calibration::Calibrate(const Rgb& reading, double cos_theta_o, uint64_t rng_index, Rgb* value,
                            Rgb* sigma) const {
  Ratio(reading, nullptr, rng_index, value, sigma);
  *value *= ideal_reference_reading_ / cos_theta_o;
  *sigma *= ideal_reference_reading_ / cos_theta_o;
}

void Calibration::CalibrateRatio(const Rgb& reading, const Rgb& reference_reading,
                                 uint64_t rng_index, Rgb* value, Rgb* sigma) const {
  Ratio(reading, &reference_reading, rng_index, value, sigma);
  *value *= instrument_.reference_rho * kInvPi;
  *sigma *= instrument_.reference_rho * kInvPi;
}

void Calibration::Ratio(const Rgb& reading, const Rgb* reference_reading, uint64_t rng_index,
                        Rgb* ratio, Rgb* sigma) const {
  Rng rng = StreamRng(seed_, Stream::kReadingNoise, rng_index);
  const double read_variance = instrument_.read_noise * instrument_.read_noise;
  const bool noisy = instrument_.photons > 0;
  for (int c = 0; c < 3; ++c) {
    const double expected = ExpectedCounts(reading[c]);
    const double counts = noisy ? NoisyCounts(expected, read_variance, &rng) : expected;
    const double variance = noisy ? expected + read_variance : 0;
    // The run's reference, or a reference read at this same geometry with its own noise.
    double reference_counts = reference_counts_, reference_variance = reference_counts_variance_;
    if (reference_reading != nullptr) {
      const double reference_expected = ExpectedCounts((*reference_reading)[c]);
      reference_counts =
          noisy ? NoisyCounts(reference_expected, read_variance, &rng) : reference_expected;
      reference_variance = noisy ? reference_expected + read_variance : 0;
    }
    if (reference_counts <= 0) {
      throw ComputeError("the reference reading has no signal: nothing to calibrate against");
    }
    (*ratio)[c] = counts / reference_counts;
    // First-order propagation of the two independent count errors through the ratio.
    (*sigma)[c] =
        std::sqrt(variance + (*ratio)[c] * (*ratio)[c] * reference_variance) / reference_counts;
  }
}

Rgb CombinedSigma(const Rgb& calibration_sigma, const Rgb& sample_error, const Rgb& positioning,
                  double slope) {
  // Calibration is linear in the reading, so its slope carries a reading's error over; a
  // traced sample's Monte Carlo error is independent of the detector noise.
  return (calibration_sigma.square() + (slope * sample_error).square() +
          (slope * positioning).square())
      .sqrt();
}

NoiseModel::NoiseModel(const GonioSample& sample, const Instrument& instrument)
    : sample_(sample),
      instrument_(instrument),
      calibration_(instrument, ReferenceReading(instrument), /*seed=*/1) {
  if (!sample.HasExpectedReading()) {
    throw UsageError("the noise model needs a sample with an expected reading (model:MODEL)");
  }
}

Rgb NoiseModel::Sigma(const Vec3& wi, const Vec3& wo) const { return SigmaOf(wi, wo, true); }

Rgb NoiseModel::IndependentSigma(const Vec3& wi, const Vec3& wo) const {
  return SigmaOf(wi, wo, /*include_common=*/false);
}

Rgb NoiseModel::CountSigma(const Vec3& wi, const Vec3& wo) const {
  const Rgb reading = sample_.ExpectedReading(instrument_, wi, wo);
  return calibration_.ExpectedSigma(reading, wo.z(), /*include_reference=*/false);
}

double NoiseModel::LightArmVariance() const {
  const double jitter = DegToRad(instrument_.jitter_deg);
  return jitter * jitter;
}

Rgb NoiseModel::SigmaOf(const Vec3& wi, const Vec3& wo, bool include_common) const {
  const Rgb reading = sample_.ExpectedReading(instrument_, wi, wo);
  return CombinedSigma(calibration_.ExpectedSigma(reading, wo.z(), include_common), Rgb::Zero(),
                       PositioningSigma(sample_, instrument_, wi, wo, reading, include_common),
                       calibration_.Slope(wo.z()));
}

std::unique_ptr<GonioSample> MakeSample(const std::string& spec, const Instrument& instrument) {
  const size_t colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string rest = colon == std::string::npos ? "" : spec.substr(colon + 1);
  if (kind == "model") {
    return std::make_unique<ModelSample>(LoadSampleModel(spec, rest), instrument);
  }
  if (kind == "surface") {
    if (rest.empty()) throw UsageError("sample '" + spec + "': expected surface:FILE.json");
    return MakeSurfaceSample(rest, instrument);
  }
  throw UsageError("sample '" + spec + "': unknown kind (known: " + kSampleKinds + ")");
}

int64_t CountReadings(const MeasureOptions& options, const Schedule& schedule) {
  if (StartsWith(options.sample, "sphere:")) {
    return static_cast<int64_t>(SphereLightThetas(schedule).size());
  }
  return static_cast<int64_t>(schedule.CountGeometries());
}

Measurement Measure(const MeasureOptions& options, const Schedule& schedule) {
  const Instrument& instrument = options.instrument;
  instrument.Validate();
  Measurement measurement;
  measurement.metadata["sample"] = options.sample;
  measurement.metadata["schedule"] = schedule.spec;
  measurement.metadata["seed"] = std::to_string(options.seed);
  measurement.metadata["instrument"] = options.instrument_name;
  measurement.metadata["instrument_json"] = instrument.ToJson();
  measurement.metadata["units"] = "BRDF in sr^-1, angles in degrees";
  measurement.metadata["producer"] = "brdf measure (virtual gonioreflectometer)";
  if (schedule.designed) measurement.metadata[kWeightingKey] = kEqualWeighting;

  if (StartsWith(options.sample, "sphere:")) {
    const SphereAcquisition acquisition(LoadSampleModel(options.sample, options.sample.substr(7)),
                                        instrument);
    acquisition.Acquire(schedule, options.seed, options.advance, &measurement);
    measurement.metadata["modelled"] =
        acquisition.Modelled() + "; " + InstrumentSummary(instrument);
    return measurement;
  }
  if (StartsWith(options.sample, "surface:") && schedule.kind == "merl") {
    // Every MERL cell has its own incidence; tracing each separately would take days.
    throw UsageError("schedule 'merl' visits " + std::to_string(schedule.incidences.size()) +
                     " incidences, each traced separately for a surface sample: use "
                     "hemisphere, equal-area or adaptive, or the sphere sample");
  }
  std::unique_ptr<GonioSample> sample;
  std::unique_ptr<Calibration> calibration;

  // Offsets of each incidence's readings in the global reading index (the RNG stream index).
  std::vector<size_t> offsets(schedule.incidences.size() + 1, 0);
  for (size_t g = 0; g < schedule.incidences.size(); ++g) {
    offsets[g + 1] = offsets[g] + schedule.incidences[g].detectors.size();
  }
  const size_t total = offsets.back();
  // The readings of the whole run, gathered on rank 0 only (core/parallel_ranks.h).
  const size_t kept = ranks::IsRoot() ? total : 0;
  std::vector<Rgb> values(kept, Rgb::Zero()), sigmas(kept, Rgb::Zero());
  std::vector<char> blocked(kept, 0);
  const double cos_blocked = std::cos(DegToRad(instrument.blocked_within_deg));
  const double jitter = DegToRad(instrument.jitter_deg);

  // One incidence's readings, per detector: blocked flag, value (RGB), sigma (RGB). Every random
  // number comes from streams of (seed, incidence or reading index): no rank or thread shows.
  constexpr size_t kDoubles = 7;
  auto measure_incidence = [&](size_t g) {
    const Incidence& incidence = schedule.incidences[g];
    std::vector<double> packed(incidence.detectors.size() * kDoubles, 0.0);
    Rng incidence_rng = StreamRng(options.seed, Stream::kIncidenceJitter, g);
    const double g1 = incidence_rng.Normal(), g2 = incidence_rng.Normal();
    const Vec3 wi = PerturbDirection(incidence.wi, jitter, g1, g2);
    std::vector<Vec3> detectors;
    std::vector<size_t> indices;
    for (size_t k = 0; k < incidence.detectors.size(); ++k) {
      const size_t index = offsets[g] + k;
      const Vec3& wo = incidence.detectors[k].wo;
      if (incidence.wi.dot(wo) > cos_blocked) {
        packed[k * kDoubles] = 1;
        continue;
      }
      Rng detector_rng = StreamRng(options.seed, Stream::kDetectorJitter, index);
      const double h1 = detector_rng.Normal(), h2 = detector_rng.Normal();
      detectors.push_back(PerturbDirection(wo, jitter, h1, h2));
      indices.push_back(index);
    }
    const Readings readings =
        sample->Measure(instrument, wi, detectors, options.seed, static_cast<uint64_t>(g));
    tbb::parallel_for(size_t{0}, indices.size(), [&](size_t j) {
      const size_t index = indices[j], k = index - offsets[g];
      const Vec3& wo = incidence.detectors[k].wo;
      Rgb value, sigma;
      calibration->Calibrate(readings.value[j], wo.z(), index, &value, &sigma);
      // Calibration is linear in the reading, so its slope carries a reading's error over.
      sigma = CombinedSigma(
          sigma, readings.standard_error.empty() ? Rgb::Zero() : readings.standard_error[j],
          PositioningSigma(*sample, instrument, incidence.wi, wo, readings.value[j]),
          calibration->Slope(wo.z()));
      for (int c = 0; c < 3; ++c) {
        packed[k * kDoubles + 1 + c] = value[c];
        packed[k * kDoubles + 4 + c] = sigma[c];
      }
    });
    std::string bytes;
    ranks::AppendBytes(&bytes, packed.data(), packed.size());
    return bytes;
  };
  auto collect_incidence = [&](size_t g, int rank, std::string&& bytes) {
    const size_t count = schedule.incidences[g].detectors.size();
    const std::vector<double> packed = ranks::ReadValues<double>(bytes);
    if (packed.size() != count * kDoubles) {
      throw ComputeError("rank " + std::to_string(rank) + " returned " +
                         std::to_string(packed.size()) + " numbers for incidence " +
                         std::to_string(g) + "; expected " + std::to_string(count * kDoubles));
    }
    for (size_t k = 0; k < count; ++k) {
      const double* p = &packed[k * kDoubles];
      blocked[offsets[g] + k] = p[0] != 0;
      values[offsets[g] + k] = Rgb(p[1], p[2], p[3]);
      sigmas[offsets[g] + k] = Rgb(p[4], p[5], p[6]);
    }
    if (options.advance) options.advance(static_cast<int64_t>(count));
  };
  ranks::Distribute(
      ranks::RoundRobin(schedule.incidences.size()),
      [&]() {
        sample = MakeSample(options.sample, instrument);
        calibration =
            std::make_unique<Calibration>(instrument, ReferenceReading(instrument), options.seed);
      },
      measure_incidence, collect_incidence);
  if (!ranks::IsRoot()) return measurement;

  size_t skipped = 0;
  for (size_t g = 0; g < schedule.incidences.size(); ++g) {
    const Incidence& incidence = schedule.incidences[g];
    for (size_t k = 0; k < incidence.detectors.size(); ++k) {
      const size_t index = offsets[g] + k;
      if (blocked[index]) {
        ++skipped;
        continue;
      }
      measurement.samples.push_back(
          {incidence.wi, incidence.detectors[k].wo, values[index], false});
      measurement.sigma.push_back(sigmas[index]);
      if (schedule.has_weight) measurement.weight.push_back(incidence.detectors[k].weight);
    }
  }
  measurement.metadata["modelled"] = sample->Modelled() + "; " + InstrumentSummary(instrument);
  measurement.metadata["skipped"] = std::to_string(skipped) +
                                    " geometries where the detector arm shadows the beam (within " +
                                    FormatNumber(instrument.blocked_within_deg) + " deg)";
  return measurement;
}

}  // namespace brdf::gonio
