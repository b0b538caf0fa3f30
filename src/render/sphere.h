// The preview sphere (DESIGN §8): a unit sphere of one material seen by an orthographic camera
// along -z, filling the image; each pixel's radiance in W/(m^2 sr) in a float RGBA buffer
// (alpha 1 on the sphere, 0 around it).
//
// Pixel (x, y) of an N x N image looks at (u, v) = ((2x + 1)/N - 1, 1 - (2y + 1)/N); on the
// sphere (u^2 + v^2 < 1) the normal is n = (u, v, sqrt(1 - u^2 - v^2)) and wo = +z.
//
//   Lo = sum over directional lights of f(wi, wo) E cos(theta_i)          (exact, no noise)
//      + integral of f(wi, wo) L_env(wi) cos(theta_i) dwi                  (Monte Carlo)
// The environment integral takes, per pixel, `spp` directions from the environment's
// luminance distribution, `spp` from the cosine distribution and, where the material's lobe is
// narrower than the cosine resolves (its peak density of wi above eight times the cosine's),
// `spp` from the lobe (for dense tables, which have no lobe formula, `spp` from a sampler built
// from the table, Material::MakeSampler), combined by multiple importance sampling with the power
// heuristic (Veach & Guibas, "Optimally combining sampling techniques for Monte Carlo rendering",
// SIGGRAPH 1995). The convex sphere never shadows itself, so no visibility term is needed.
// The estimate runs in single precision (core/float_math.h, lobe_sampler.h); the directional
// lights in double.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hdr/image.h"
#include "render/environment.h"
#include "render/lights.h"
#include "render/material.h"

namespace brdf {

class Progress;

struct RenderOptions {
  static constexpr int kMaxSize = 16384;   // px
  static constexpr int kMaxSpp = 1 << 20;  // samples per pixel
  int size = 512;                          // image width = height, px, in 1..kMaxSize
  int spp = 64;       // environment samples per pixel and per technique, in 1..kMaxSpp
  uint64_t seed = 0;  // the same seed gives the same image whatever the thread count

  // Throws UsageError naming the option.
  void Validate() const;
};

struct RenderResult {
  Image radiance;
  // Per pixel, the standard error of the Monte Carlo estimate of the luminance (0 where there
  // is no environment or no sphere).
  std::vector<float> luminance_std_error;
  int64_t sphere_pixels = 0;
  int64_t missing_lookups = 0;  // measured data without a value (rendered black)
  std::string Summary() const;
};

RenderResult RenderSphere(const Material& material, const std::vector<DirectionalLight>& lights,
                          const Environment* environment, const RenderOptions& options,
                          Progress* progress = nullptr);

// The surface normal under pixel (x, y), or nullopt off the sphere.
std::optional<Vec3> SphereNormal(int x, int y, int size);

}  // namespace brdf
