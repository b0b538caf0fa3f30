#include "core/colour.h"

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <utility>

#include "core/enum_names.h"
#include "core/errors.h"

namespace brdf {
namespace {

// CIE names, matched without regard to case ("d65" is D65).
constexpr EnumName<Illuminant> kIlluminantNames[] = {
    {Illuminant::kD65, "D65"},
    {Illuminant::kE, "E"},
};

// XYZ of a chromaticity (x, y) scaled to Y = 1.
Vec3 XyzOfChromaticity(double x, double y) { return Vec3(x / y, 1.0, (1.0 - x - y) / y); }

// The sRGB white, D65 as IEC 61966-2-1 gives it: (x, y) = (0.3127, 0.3290), Y = 1.
Vec3 SrgbWhiteXyz() { return XyzOfChromaticity(0.3127, 0.3290); }

// IEC 61966-2-1 defines sRGB by its primaries' and white's chromaticities; the 4-decimal matrix
// it prints is a rounding of the matrix derived here. Deriving it in double precision makes the
// sRGB white map to RGB (1, 1, 1) to rounding error rather than to ~1e-4.
Eigen::Matrix3d DeriveSrgbRgbToXyz() {
  const Vec3 red = XyzOfChromaticity(0.64, 0.33);
  const Vec3 green = XyzOfChromaticity(0.30, 0.60);
  const Vec3 blue = XyzOfChromaticity(0.15, 0.06);
  Eigen::Matrix3d primaries;
  primaries << red, green, blue;
  // Scale each primary so that RGB (1, 1, 1) is the white.
  const Vec3 scale = primaries.partialPivLu().solve(SrgbWhiteXyz());
  return primaries * scale.asDiagonal();
}

const Eigen::Matrix3d& SrgbXyzToRgb() {
  static const Eigen::Matrix3d matrix = DeriveSrgbRgbToXyz().inverse();
  return matrix;
}

// Bradford chromatic adaptation (Lam 1985; as in CIE 159:2004 / ICC v4 Annex E): scales the
// Bradford cone responses so that `source_white` lands exactly on `target_white`.
Eigen::Matrix3d BradfordAdaptation(const Vec3& source_white, const Vec3& target_white) {
  Eigen::Matrix3d cone;
  cone << 0.8951, 0.2664, -0.1614,  //
      -0.7502, 1.7135, 0.0367,      //
      0.0389, -0.0685, 1.0296;
  const Vec3 gain = (cone * target_white).cwiseQuotient(cone * source_white);
  return cone.inverse() * gain.asDiagonal() * cone;
}

double IlluminantPower(Illuminant illuminant, int k) {
  return illuminant == Illuminant::kD65 ? CieTables::kD65[k] : 1.0;  // E: equal energy
}

}  // namespace

Illuminant ParseIlluminant(const std::string& name) {
  return ParseEnum(kIlluminantNames, name, "illuminant", NameCase::kIgnore);
}

const char* IlluminantName(Illuminant illuminant) { return NameOf(kIlluminantNames, illuminant); }

Rgb XyzToLinearSrgb(const Vec3& xyz) { return (SrgbXyzToRgb() * xyz).array(); }

SpectrumToRgb::SpectrumToRgb(std::vector<double> wavelengths_nm, Illuminant illuminant)
    : illuminant_(illuminant), wavelengths_nm_(std::move(wavelengths_nm)) {
  const size_t n = wavelengths_nm_.size();
  if (n < 2) {
    throw UsageError("a spectrum needs at least 2 wavelengths, got " + std::to_string(n));
  }
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(wavelengths_nm_[i])) {
      throw UsageError("spectrum wavelength #" + std::to_string(i + 1) + " is not finite");
    }
    if (i > 0 && !(wavelengths_nm_[i] > wavelengths_nm_[i - 1])) {
      throw UsageError("spectrum wavelengths must increase strictly, but #" +
                       std::to_string(i + 1) + " (" + std::to_string(wavelengths_nm_[i]) +
                       " nm) follows " + std::to_string(wavelengths_nm_[i - 1]) + " nm");
    }
  }

  // At every CIE grid wavelength l_k the input is f(l_k) = (1 - t) f_j + t f_{j+1} (or an end
  // value outside the sampled range), so grid term k hands the share (1 - t) of its weight
  // S(l_k) cmf(l_k) to input j and t to input j + 1. The shares sum to 1 at every k, hence a
  // flat input v yields exactly v * white below.
  xyz_weights_.assign(n, Vec3::Zero());
  double luminance_norm = 0.0;  // sum S(l) ybar(l)
  size_t j = 0;                 // wavelengths_nm_[j] <= l < wavelengths_nm_[j + 1]
  for (int k = 0; k < CieTables::kCount; ++k) {
    const double lambda = CieTables::kFirstNm + CieTables::kStepNm * k;
    const double power = IlluminantPower(illuminant, k);
    const Vec3 term = power * Vec3(CieTables::kXBar[k], CieTables::kYBar[k], CieTables::kZBar[k]);
    luminance_norm += term.y();
    if (lambda <= wavelengths_nm_.front()) {
      xyz_weights_.front() += term;
    } else if (lambda >= wavelengths_nm_.back()) {
      xyz_weights_.back() += term;
    } else {
      while (wavelengths_nm_[j + 1] <= lambda) ++j;
      const double t =
          (lambda - wavelengths_nm_[j]) / (wavelengths_nm_[j + 1] - wavelengths_nm_[j]);
      xyz_weights_[j] += (1.0 - t) * term;
      xyz_weights_[j + 1] += t * term;
    }
  }
  for (Vec3& weight : xyz_weights_) weight /= luminance_norm;

  // The white of `illuminant` as these tables see it: (0.95047, 1, 1.08897) for D65 (the 5 nm
  // sum differs from the sRGB white by ~1e-4), (1.00008, 1, 1.00034) for E. Bradford carries
  // it onto the sRGB (D65) white, so a flat spectrum is neutral, RGB (v, v, v), under either.
  Vec3 white = Vec3::Zero();
  for (const Vec3& weight : xyz_weights_) white += weight;
  xyz_to_rgb_ = SrgbXyzToRgb() * BradfordAdaptation(white, SrgbWhiteXyz());
}

Rgb SpectrumToRgb::operator()(const double* values) const {
  Vec3 xyz = Vec3::Zero();
  for (size_t i = 0; i < xyz_weights_.size(); ++i) xyz += values[i] * xyz_weights_[i];
  return (xyz_to_rgb_ * xyz).array();
}

}  // namespace brdf
