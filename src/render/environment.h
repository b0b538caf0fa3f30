// Distant environment lighting from an equirectangular (latitude-longitude) HDR image, with
// importance sampling proportional to luminance (DESIGN §8).
//
// Mapping (camera world frame: +z toward the viewer, +y up): image row r holds the polar angle
// theta_e = pi (r + 1/2) / H from +y (top row = up); column c the azimuth
// phi_e = 2 pi (c + 1/2) / W, direction (sin theta_e sin phi_e, cos theta_e,
// -sin theta_e cos phi_e). The middle column (phi_e = pi) is +z: the centre of the panorama
// lies behind the viewer and lights the visible side of the sphere.
//
// Sampling: pixel weights w(r, c) = Y(r, c) sin(theta_r) (the sine is the area of the row on
// the sphere); a pixel is drawn with probability w / sum w, then a uniform point inside it.
// This is the piecewise-constant 2D distribution of Pharr, Jakob & Humphreys (PBR, 4th ed.,
// §A.5, §12.5), drawn here in O(1) with an alias table (Walker 1977; Vose, "A linear
// algorithm for generating random numbers with a given distribution", IEEE TSE 1991) instead
// of two CDF searches, whose cache misses dominated the render. With (u, v) uniform in the
// pixel the density on the unit square is p(u, v) = W H w(r, c) / sum w, and on the sphere
//   pdf(omega) = p(u, v) / (2 pi^2 sin theta_e)   (dω = 2π² sinθ du dv).
#pragma once

#include <cstdint>
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
  // Radiance and pdf of one direction with a single pixel lookup.
  Rgb RadianceAndPdf(const Vec3& omega, double* pdf) const;

  struct Sample {
    Vec3 direction;  // world, unit
    Rgb radiance;
    double pdf = 0.0;  // per steradian
  };
  // Draws a direction with density pdf(omega) from two uniform numbers in [0, 1).
  Sample SampleDirection(double u1, double u2) const;
  double Pdf(const Vec3& omega) const;

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  // Pixel containing `omega`, and the sine of its polar angle.
  void Locate(const Vec3& omega, int* row, int* column, double* sin_theta) const;

  // Packed so that a lookup or a draw touches one cache line per table: the render is bound
  // by these random accesses.
  struct Texel {
    float rgb[3];
    float density_uv;  // p(u, v) = W H w(r, c) / sum w
  };
  struct AliasSlot {
    float keep = 1.0f;   // probability that slot i yields pixel i ...
    uint32_t alias = 0;  // ... and otherwise this pixel
  };
  int width_ = 0, height_ = 0;
  std::vector<Texel> texels_;
  std::vector<AliasSlot> slots_;
};

}  // namespace brdf
