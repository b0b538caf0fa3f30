// Distant environment lighting from an equirectangular (latitude-longitude) HDR image, with
// importance sampling proportional to luminance (DESIGN §8).
//
// Mapping (camera world frame: +z toward the viewer, +y up): image row r holds the polar angle
// theta_e = pi (r + 1/2) / H from +y (top row = up); column c the azimuth
// phi_e = 2 pi (c + 1/2) / W, direction (sin theta_e sin phi_e, cos theta_e,
// -sin theta_e cos phi_e). The middle column (phi_e = pi) is +z: the centre of the panorama
// lies behind the viewer and lights the visible side of the sphere.
//
// Sampling (pbrt's piecewise-constant 2D distribution, Pharr, Jakob & Humphreys, PBR 4th ed.,
// §A.5 and §12.5): pixel weights w(r, c) = Y(r, c) sin(theta_r) (the sine is the area of the
// row on the sphere); a row from the marginal CDF, a column from that row's conditional CDF,
// a uniform point inside the pixel. With (u, v) uniform in the pixel the density on the unit
// square is p(u, v) = W H w(r, c) / sum w, and on the sphere
//   pdf(omega) = p(u, v) / (2 pi^2 sin theta_e)   (dω = 2π² sinθ du dv).
#pragma once

#include <string>
#include <vector>

#include "core/vec.h"
#include "hdr/image.h"

namespace brdf {

class Environment {
 public:
  explicit Environment(Image image);
  // A constant radiance L in every direction (the white furnace).
  static Environment Uniform(const Rgb& radiance);
  // "uniform:L" (grey) or "uniform:R,G,B", else an OpenEXR/Radiance file; NaN/Inf pixels are
  // made black and counted in `*non_finite` when given. Throws UsageError / InputError.
  static Environment Load(const std::string& spec, int64_t* non_finite = nullptr);

  // Radiance arriving from world direction `omega` (unit), the pixel it falls in.
  Rgb Radiance(const Vec3& omega) const;

  struct Sample {
    Vec3 direction;  // world, unit
    Rgb radiance;
    double pdf = 0.0;  // per steradian
  };
  // Draws a direction with density pdf(omega) from two uniform numbers in [0, 1).
  Sample SampleDirection(double u1, double u2) const;
  double Pdf(const Vec3& omega) const;

  int width() const { return image_.width; }
  int height() const { return image_.height; }

 private:
  // Pixel containing `omega`, and the sine of its polar angle.
  void Locate(const Vec3& omega, int* row, int* column, double* sin_theta) const;

  Image image_;
  std::vector<double> marginal_cdf_;       // height + 1 entries, 0 .. 1
  std::vector<double> conditional_cdf_;    // height rows of width + 1 entries, 0 .. 1
  std::vector<double> pixel_probability_;  // w(r, c) / sum w
};

}  // namespace brdf
