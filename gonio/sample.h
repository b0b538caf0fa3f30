// What the instrument measures: a sample answers, for one incidence and a set of detector
// positions, how much of the incident power reaches each detector.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/vec.h"
#include "gonio/instrument.h"

namespace brdf::gonio {

// Readings of one incidence, one per detector (sr^-1), and for Monte Carlo samples the standard
// error of each (empty for deterministic samples).
struct Readings {
  std::vector<Rgb> value;
  std::vector<Rgb> standard_error;
};

class GonioSample {
 public:
  virtual ~GonioSample() = default;

  // What was modelled, in one line, for the measurement's metadata ("model no more than the
  // sample needs": a flat analytic sample says so, a traced one names bounces and rays).
  virtual std::string Modelled() const = 0;

  // For the incidence `wi` (already jittered) and each detector direction, the reading
  //   R = (1/Ω) ∫_detector f(wi', wo) cos(theta_o) dwo   (sr^-1),
  // averaged over the source's incidence directions wi' weighted by their irradiance
  // (Instrument::SourceDirection). Monte Carlo samples draw their random numbers from streams
  // derived from (seed, incidence_index) only, so results do not depend on threads.
  virtual Readings Measure(const Instrument& instrument, const Vec3& wi,
                           const std::vector<Vec3>& detectors, uint64_t seed,
                           uint64_t incidence_index) const = 0;

  // The noise-free reading R at exactly (wi, wo), for samples that have a cheap deterministic
  // one (HasExpectedReading; a traced surface is Monte Carlo and has none). Measure uses it to
  // carry the instrument's positioning jitter into the stated sigma (PositioningSigma in
  // measure.h).
  virtual bool HasExpectedReading() const { return false; }
  virtual Rgb ExpectedReading(const Instrument& /*instrument*/, const Vec3& /*wi*/,
                              const Vec3& /*wo*/) const {
    return Rgb::Constant(std::numeric_limits<double>::quiet_NaN());
  }
};

}  // namespace brdf::gonio
