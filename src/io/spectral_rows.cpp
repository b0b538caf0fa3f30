#include "io/spectral_rows.h"

#include <algorithm>
#include <cmath>

#include "core/angles.h"
#include "core/errors.h"
#include "core/format.h"

namespace brdf {
namespace {

// Angles are printed with six decimals in the Cornell files, so pi/2 appears as 1.570796 (just
// below) and could appear rounded up as 1.570797: allow that much.
constexpr double kAngleSlack = 1e-6;

// The polar angle of a direction above the surface, clamped into [0, pi/2] once it is known to
// be within the slack, so that wo.z >= 0 exactly (a BRDF is zero below the horizon, DESIGN §1).
double CheckedTheta(const std::string& path, int64_t line, const char* name, double theta) {
  if (theta < -kAngleSlack || theta > kPi / 2 + kAngleSlack) {
    throw ParseError(path, line,
                     std::string(name) + " = " + Format("%.9g", theta) + " rad (" +
                         Format("%.4g", RadToDeg(theta)) +
                         " deg) is outside [0, pi/2]: not a direction above the surface");
  }
  return std::clamp(theta, 0.0, kPi / 2);
}

double CheckedPhi(const std::string& path, int64_t line, const char* name, double phi) {
  if (std::abs(phi) > 2 * kPi + kAngleSlack) {
    throw ParseError(path, line,
                     std::string(name) + " = " + Format("%.9g", phi) +
                         " rad is outside [-2 pi, 2 pi]: are the angles in degrees?");
  }
  return phi;
}

}  // namespace

void CheckNextWavelength(const LineReader& reader, const std::vector<double>& previous_nm,
                         double wavelength_nm) {
  const std::string ordinal = "wavelength #" + std::to_string(previous_nm.size() + 1);
  if (!std::isfinite(wavelength_nm) || wavelength_nm <= 0) {
    reader.Fail(ordinal + " = " + Format("%g", wavelength_nm) + " nm is not a positive number");
  }
  if (!previous_nm.empty() && !(wavelength_nm > previous_nm.back())) {
    reader.Fail("wavelengths must increase, but " + ordinal + " (" + Format("%g", wavelength_nm) +
                " nm) follows " + Format("%g", previous_nm.back()) + " nm");
  }
}

SpectralRecords::SpectralRecords(std::vector<double> wavelengths_nm, Illuminant illuminant)
    : wavelengths_nm_(wavelengths_nm), to_rgb_(std::move(wavelengths_nm), illuminant) {}

void SpectralRecords::Add(const std::string& path, int64_t line, const double* record,
                          Measurement* measurement) {
  const double theta_i = CheckedTheta(path, line, "theta_i", record[kThetaI]);
  const double phi_i = CheckedPhi(path, line, "phi_i", record[kPhiI]);
  const double theta_s = CheckedTheta(path, line, "theta_s", record[kThetaS]);
  const double phi_s = CheckedPhi(path, line, "phi_s", record[kPhiS]);
  const double* spectrum = record + kFirstSpectral;
  // Negative BRDF values are noise in a measurement, not a format error: keep them, count them
  // (brdf info reports the negative RGB channels they lead to).
  const auto negative = std::count_if(spectrum, spectrum + wavelengths_nm_.size(),
                                      [](double value) { return value < 0; });
  negative_values_ += negative;
  Sample sample;
  sample.wi = SphericalDirection(theta_i, phi_i);
  sample.wo = SphericalDirection(theta_s, phi_s);
  sample.value = to_rgb_(spectrum);
  // Saturated colours (the Cornell blues and reds) lie outside the sRGB gamut: a non-negative
  // spectrum then has a negative linear-sRGB channel. Said in the metadata, so that the
  // negative counts of `brdf info` are not mistaken for bad data.
  if (negative == 0 && (sample.value < 0).any()) ++out_of_gamut_;
  measurement->samples.push_back(sample);
}

void SpectralRecords::Describe(Measurement* measurement) const {
  auto& metadata = measurement->metadata;
  metadata["illuminant"] = IlluminantName(to_rgb_.illuminant());
  metadata["spectral"] = std::to_string(wavelengths_nm_.size()) + " bands " +
                         Format("%g", wavelengths_nm_.front()) + "-" +
                         Format("%g", wavelengths_nm_.back()) + " nm -> RGB via CIE 1931 2deg";
  metadata["units"] = "sr^-1";
  metadata["negative_spectral_values"] = std::to_string(negative_values_);
  metadata["rgb_out_of_gamut"] =
      std::to_string(out_of_gamut_) + " of " + std::to_string(measurement->samples.size()) +
      " samples have a negative linear-sRGB channel from a non-negative spectrum (a colour "
      "outside the sRGB gamut)";
}

}  // namespace brdf
