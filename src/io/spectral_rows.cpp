#include "io/spectral_rows.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/angles.h"
#include "core/errors.h"

namespace brdf {
namespace {

// Angles are printed with six decimals in the Cornell files, so pi/2 appears as 1.570796 (just
// below) and could appear rounded up as 1.570797: allow that much.
constexpr double kAngleSlack = 1e-6;

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

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

void CheckWavelengths(const std::string& path, int64_t line,
                      const std::vector<double>& wavelengths_nm) {
  if (wavelengths_nm.size() < 2) {
    throw ParseError(path, line,
                     "a spectrum needs at least 2 wavelengths, found " +
                         std::to_string(wavelengths_nm.size()));
  }
  for (size_t k = 0; k < wavelengths_nm.size(); ++k) {
    const double lambda = wavelengths_nm[k];
    if (!std::isfinite(lambda) || lambda <= 0) {
      throw ParseError(path, line,
                       "wavelength #" + std::to_string(k + 1) + " = " + Format("%g", lambda) +
                           " nm is not a positive number");
    }
    if (k > 0 && !(lambda > wavelengths_nm[k - 1])) {
      throw ParseError(path, line,
                       "wavelengths must increase, but #" + std::to_string(k + 1) + " (" +
                           Format("%g", lambda) + " nm) follows " +
                           Format("%g", wavelengths_nm[k - 1]) + " nm");
    }
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
  negative_values_ += std::count_if(spectrum, spectrum + wavelengths_nm_.size(),
                                    [](double value) { return value < 0; });
  Sample sample;
  sample.wi = SphericalDirection(theta_i, phi_i);
  sample.wo = SphericalDirection(theta_s, phi_s);
  sample.value = to_rgb_(spectrum);
  measurement->samples.push_back(sample);
}

void SpectralRecords::Describe(Measurement* measurement) const {
  auto& metadata = measurement->metadata;
  metadata["illuminant"] = IlluminantName(to_rgb_.illuminant());
  metadata["spectral"] = std::to_string(wavelengths_nm_.size()) + " bands " +
                         Format("%g", wavelengths_nm_.front()) + "-" +
                         Format("%g", wavelengths_nm_.back()) +
                         " nm -> RGB via CIE 1931 2deg";
  metadata["units"] = "sr^-1";
  metadata["negative_spectral_values"] = std::to_string(negative_values_);
}

}  // namespace brdf
