// The record both Cornell layouts share (ASTM E1392 in astm.cpp, pbrt-v2 `.brdf` in
// pbrt_brdf.cpp): four angles in radians (theta_i, phi_i, theta_s, phi_s) followed by one BRDF
// value in sr^-1 per wavelength. This turns such records into Samples, with the same angle
// checks and the same spectral -> RGB conversion (DESIGN §1) for both files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/colour.h"
#include "core/measurement.h"

namespace brdf {

// Checks that `wavelengths_nm` can drive a spectral -> RGB conversion: at least two, finite,
// positive, strictly increasing. Throws ParseError at `line` of `path` otherwise.
void CheckWavelengths(const std::string& path, int64_t line,
                      const std::vector<double>& wavelengths_nm);

class SpectralRecords {
 public:
  // Field positions in a record (theta from the normal, phi from +x; DESIGN §1).
  static constexpr int kThetaI = 0, kPhiI = 1, kThetaS = 2, kPhiS = 3, kFirstSpectral = 4;

  // `wavelengths_nm` must have passed CheckWavelengths.
  SpectralRecords(std::vector<double> wavelengths_nm, Illuminant illuminant);

  // Values per record: the four angles and one per wavelength.
  size_t record_size() const { return kFirstSpectral + wavelengths_nm_.size(); }

  // Checks the angles of `record` (record_size() finite values) and appends its sample to
  // `measurement`. Angle errors are reported at `line` of `path`.
  void Add(const std::string& path, int64_t line, const double* record, Measurement* measurement);

  // States what the conversion assumed ("illuminant", "spectral", "units") and what it saw
  // ("negative_spectral_values") in the metadata.
  void Describe(Measurement* measurement) const;

 private:
  std::vector<double> wavelengths_nm_;
  SpectrumToRgb to_rgb_;
  int64_t negative_values_ = 0;
};

}  // namespace brdf
