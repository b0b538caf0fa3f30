// Colour and photometry (DESIGN §1): linear Rec.709/sRGB primaries, D65 white; spectral data
// become RGB through the CIE 1931 2-degree colour matching functions under a named illuminant.
#pragma once

#include <string>
#include <vector>

#include "core/vec.h"

namespace brdf {

// Rec.709 luminance weights (ITU-R BT.709).
inline constexpr double kLuminanceWeights[3] = {0.2126, 0.7152, 0.0722};
inline double Luminance(const Rgb& rgb) {
  return kLuminanceWeights[0] * rgb[0] + kLuminanceWeights[1] * rgb[1] +
         kLuminanceWeights[2] * rgb[2];
}

// Photometric constants: the luminous efficacy of 555 nm radiation (CIE), lux = lm/m^2.
inline constexpr double kLumensPerWattAt555nm = 683.0;
// Luminance in cd/m² (nits) of the luminance Y of a radiance in W/(m² sr): the same 683 lm/W
// that turns lux into irradiance (render/lights.h), so a scene lit by L lux reads back in units
// of that light.
inline double RadianceToNits(double luminance) { return luminance * kLumensPerWattAt555nm; }

enum class Illuminant { kD65, kE };
// "D65" or "E" (case-insensitive); throws UsageError for anything else.
Illuminant ParseIlluminant(const std::string& name);
const char* IlluminantName(Illuminant illuminant);

// CIE XYZ -> linear sRGB (Rec.709 primaries, D65 white; IEC 61966-2-1).
Rgb XyzToLinearSrgb(const Vec3& xyz);

// CIE 1931 2-degree colour matching functions and illuminant spectra, tabulated every 5 nm
// from 360 to 830 nm (see cie_tables.cpp for the source of the numbers).
struct CieTables {
  static constexpr double kFirstNm = 360.0;
  static constexpr double kStepNm = 5.0;
  static constexpr int kCount = 95;
  static const double kXBar[kCount];
  static const double kYBar[kCount];
  static const double kZBar[kCount];
  static const double kD65[kCount];  // relative spectral power, 100 at 560 nm
};

// Converts a reflectance-like spectrum (a ratio such as a BRDF in sr^-1, sampled at
// `wavelengths_nm`, increasing) to linear sRGB as seen under `illuminant`:
//   XYZ = sum f(l) S(l) cmf(l) / sum S(l) ybar(l),
// so a spectrally flat value v becomes (v, v, v) under either illuminant: the illuminant's
// white is carried to the sRGB D65 white by the Bradford transform (for E a real change; for
// D65 a ~1e-4 correction, since the 5 nm table's white is not exactly sRGB's). Outside the
// sampled range the spectrum is held at its end values; inside it is interpolated linearly.
class SpectrumToRgb {
 public:
  SpectrumToRgb(std::vector<double> wavelengths_nm, Illuminant illuminant);
  Rgb operator()(const double* values) const;
  Illuminant illuminant() const { return illuminant_; }

 private:
  Illuminant illuminant_;
  std::vector<double> wavelengths_nm_;
  // Per input wavelength, its (linear-interpolation) weight in the X, Y, Z sums; precomputed
  // so converting one spectrum is a small matrix product.
  std::vector<Vec3> xyz_weights_;
  Eigen::Matrix3d xyz_to_rgb_;
};

}  // namespace brdf
