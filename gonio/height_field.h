// Periodic micro-geometry height fields for the ray-traced sample (DESIGN §5). Heights are in
// units of the grid spacing on an n × n periodic grid, so slopes are plain differences.
//   flat       — all zero (measured analytically: no BVH, surface_sample.h);
//   gaussian   — white noise smoothed by a periodic Gaussian of `correlation` cells, scaled so
//                the rms slope sqrt(<|∇h|²>) of the facets over both axes is `rms_slope`
//                (each axis: rms_slope/√2), which is Beckmann's alpha (DESIGN §2);
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
  int resolution = 256;
  int seed = 1;
  double correlation = 4.0;  // gaussian: smoothing radius (cells, one standard deviation)
  int period = 16;           // v-grooves: cells per groove
  std::string path;          // file: the EXR height map

  void Validate(const std::string& origin) const;  // throws InputError naming origin
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
