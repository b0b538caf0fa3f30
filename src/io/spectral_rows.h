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
#include "core/text.h"

namespace brdf {

// A spectrum -> RGB conversion needs at least two wavelengths (core/colour.h).
inline constexpr int64_t kMinWavelengths = 2;

// Checks the next wavelength of a list against those before it: finite, positive and larger
// than the last (SpectrumToRgb interpolates on a strictly increasing grid). Throws ParseError at
// the reader's current line, so the message points at the offending value.
void CheckNextWavelength(const LineReader& reader, const std::vector<double>& previous_nm,
                         double wavelength_nm);

class SpectralRecords {
 public:
  // Field positions in a record (theta from the normal, phi from +x; DESIGN §1).
  static constexpr int kThetaI = 0, kPhiI = 1, kThetaS = 2, kPhiS = 3, kFirstSpectral = 4;

  // `wavelengths_nm`: at least kMinWavelengths, each checked by CheckNextWavelength.
  SpectralRecords(std::vector<double> wavelengths_nm, Illuminant illuminant);

  // Values per record: the four angles and one per wavelength.
  size_t record_size() const { return kFirstSpectral + wavelengths_nm_.size(); }

  // Checks the angles of `record` (record_size() finite values) and appends its sample to
  // `measurement`. Angle errors are reported at `line` of `path`.
  void Add(const std::string& path, int64_t line, const double* record, Measurement* measurement);

  // States what the conversion assumed ("illuminant", "spectral", "units") and what it saw
  // ("negative_spectral_values", "rgb_out_of_gamut") in the metadata.
  void Describe(Measurement* measurement) const;

 private:
  std::vector<double> wavelengths_nm_;
  SpectrumToRgb to_rgb_;
  int64_t negative_values_ = 0;
  int64_t out_of_gamut_ = 0;  // samples with a negative RGB channel from a non-negative spectrum
};

}  // namespace brdf
