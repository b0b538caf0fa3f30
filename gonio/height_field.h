// Periodic micro-geometry height fields for the ray-traced sample (DESIGN §5). Heights are in
// units of the grid spacing on an n × n periodic grid, so slopes are plain differences.
//   flat       — all zero (measured analytically: no BVH, surface_sample.h);
//   gaussian   — white noise smoothed by a periodic Gaussian of `correlation` cells, scaled so
//                the rms slope sqrt(<|∇h|²>) of the facets over both axes is `rms_slope`
//                (each axis: rms_slope/√2), which is Beckmann's alpha (DESIGN §2). With
//                `rms_slope_y` the field is anisotropic: ∂h/∂x has standard deviation
//                rms_slope/√2 and ∂h/∂y rms_slope_y/√2, Beckmann's alpha_x and alpha_y (the
//                anisotropic Beckmann D of Heitz 2014, eq. 79, with the slopes' axes x and y),
//                and sqrt(<|∇h|²>) = sqrt((rms_slope² + rms_slope_y²) / 2). The smoothing is
//                longer along the smoother axis (`correlation` along the rougher one);
//   v-grooves  — symmetric V grooves along y, `period` cells wide, facet slope `rms_slope`
//                (the geometry of Torrance & Sparrow 1967);
//   file       — heights from the first channel of an OpenEXR image (square, in spacing units).
#pragma once

#include <string>
#include <vector>

namespace brdf::gonio {

struct HeightFieldSpec {
  std::string kind = "gaussian";
  double rms_slope = 0.3;
  double rms_slope_y = 0.0;  // gaussian: the slope along y, as rms_slope along x; 0: isotropic
  int resolution = 256;
  int seed = 1;
  double correlation = 4.0;  // gaussian: smoothing radius (cells, one standard deviation)
  int period = 16;           // v-grooves: cells per groove
  std::string path;          // file: the EXR height map

  void Validate(const std::string& origin) const;  // throws InputError naming origin
  // gaussian: the slope parameter along x and along y (rms_slope both, unless rms_slope_y).
  double SlopeX() const { return rms_slope; }
  double SlopeY() const { return rms_slope_y > 0 ? rms_slope_y : rms_slope; }
  // gaussian: the smoothing radius along x and along y (cells): `correlation` along the rougher
  // axis, longer along the smoother one so that their expected slope variances have the ratio
  // the slopes ask for.
  double CorrelationX() const;
  double CorrelationY() const;
};

struct HeightField {
  int resolution = 0;          // n: n × n cells, periodic
  std::vector<float> heights;  // n × n, row-major (x fastest)

  float At(int x, int y) const {
    const int n = resolution;
    return heights[((y % n + n) % n) * n + ((x % n + n) % n)];
  }
  float MinHeight() const;
  float MaxHeight() const;
  // sqrt(<|∇h|²>) over the triangle facets (forward differences).
  double RmsSlope() const;
};

HeightField MakeHeightField(const HeightFieldSpec& spec);

}  // namespace brdf::gonio
