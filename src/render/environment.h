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

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/float_math.h"
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

  // The same distribution in single precision, for the renderer's hot loop (render/sphere.cpp),
  // split so that the caller can prefetch each table entry before it is read: the draws and
  // lookups of a pixel's samples are independent, and waiting on them one at a time was half of
  // a render.
  //
  // Each pixel's radiance, its density and its alias-table slot share one 24-byte entry, so that
  // a lookup touches one cache line and a draw one or two (the alias, when taken, is one of the
  // map's heavy pixels, which the many draws keep in cache).
  struct Texel {
    float rgb[3];
    float density_uv;    // p(u, v) = W H w(r, c) / sum w
    float keep = 1.0f;   // the probability that slot i yields pixel i ...
    uint32_t alias = 0;  // ... and otherwise this pixel
  };
  // The slot a 64-bit random word picks: its top 32 bits scaled to the pixel count.
  uint32_t SlotOf(uint64_t bits) const {
    return static_cast<uint32_t>(((bits >> 32) * static_cast<uint64_t>(texels_.size())) >> 32);
  }
  // The pixel that slot `slot` yields for the word `bits` (its low 24 bits, independent of the
  // top 32 that chose the slot, decide between the slot and its alias) and, in `*u` and `*v`,
  // the image coordinates in [0, 1] of the point drawn across it (`v_in_pixel` places it down
  // the pixel). The direction is then DirectionAt(u, v).
  uint32_t DrawFloat(uint32_t slot, uint64_t bits, float v_in_pixel, float* u, float* v) const;
  // World direction (x, y, z) at image coordinates (u, v) (theta = pi v, phi = 2 pi u), and the
  // sine of its polar angle. Inline, without branches, so that a loop over a batch vectorizes.
  static void DirectionAt(float u, float v, float* x, float* y, float* z, float* sin_theta) {
    float cos_theta, sin_phi, cos_phi;
    SinCosTurn(0.5f * v, sin_theta, &cos_theta);
    SinCosTurn(u, &sin_phi, &cos_phi);
    *x = *sin_theta * sin_phi;
    *y = cos_theta;
    *z = -*sin_theta * cos_phi;
  }
  // The pixel containing world direction (x, y, z) (unit), and the sine of its polar angle;
  // inline and without branches, likewise.
  uint32_t LocateFloat(float x, float y, float z, float* sin_theta) const {
    const float cos_theta = std::min(std::max(y, -1.0f), 1.0f);
    // (1 - c)(1 + c) keeps its digits near the poles, where 1 - c^2 would cancel.
    *sin_theta = std::sqrt((1.0f - cos_theta) * (1.0f + cos_theta));
    const float theta = Atan2(*sin_theta, cos_theta);
    float phi = Atan2(x, -z);
    phi += static_cast<float>(phi < 0.0f) * (2.0f * kPiF);
    const int row = std::min(std::max(static_cast<int>(theta * row_scale_), 0), height_ - 1);
    const int column = std::min(std::max(static_cast<int>(phi * column_scale_), 0), width_ - 1);
    return static_cast<uint32_t>(row * width_ + column);
  }
  const Texel& texel(uint32_t pixel) const { return texels_[pixel]; }
  // Both ends: an entry may straddle two cache lines.
  void Prefetch(uint32_t pixel) const {
    const char* entry = reinterpret_cast<const char*>(&texels_[pixel]);
    __builtin_prefetch(entry);
    __builtin_prefetch(entry + sizeof(Texel) - 1);
  }
  // pdf(omega) per steradian of a direction in `texel` at polar angle sine `sin_theta`.
  static float PdfFloat(const Texel& texel, float sin_theta) {
    return sin_theta > 0.0f ? texel.density_uv * kInverseTwoPiSquared / sin_theta : 0.0f;
  }

 private:
  static constexpr float kInverseTwoPiSquared = static_cast<float>(1.0 / (2.0 * kPi * kPi));

  // Pixel containing `omega`, and the sine of its polar angle.
  void Locate(const Vec3& omega, int* row, int* column, double* sin_theta) const;

  int width_ = 0, height_ = 0;
  float row_scale_ = 0.0f, column_scale_ = 0.0f;  // H / pi, W / (2 pi)
  std::vector<Texel> texels_;
};

}  // namespace brdf
