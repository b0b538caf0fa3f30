// The base material carried by every facet of a micro-geometry sample (DESIGN §5):
//   a model string or FIT.json (e.g. `lambert:rho_d=0.8`) — the facet scatters diffusely: a
//     cosine-weighted direction with weight f·π (exactly rho_d for lambert);
//   `conductor:ior=N:k=K` — a smooth metal, mirror reflection weighted by the exact complex
//     Fresnel reflectance (models/microfacet.h, shared with the microfacet models); N and K are one
//     value or three (RGB);
//   `dielectric:ior=N` — a smooth opaque dielectric (e.g. a black glossy paint): mirror
//     reflection weighted by the exact Fresnel reflectance; the refracted part is absorbed.
#pragma once

#include <optional>
#include <string>

#include "core/vec.h"
#include "models/registry.h"

namespace brdf::gonio {

class FacetMaterial {
 public:
  // Throws UsageError naming the spec.
  static FacetMaterial Parse(const std::string& spec);

  bool specular() const { return !model_.has_value(); }
  const std::optional<Model>& model() const { return model_; }
  // Fresnel reflectance per channel at a facet for the cosine of the incidence angle.
  Rgb Fresnel(double cos_theta) const;
  // Scatters light arriving from facet-local direction `wi` (z = facet normal, pointing away):
  // returns the facet-local outgoing direction and multiplies `throughput` by its weight.
  Vec3 Scatter(const Vec3& wi, double u1, double u2, Rgb* throughput) const;
  std::string ToString() const { return spec_; }

 private:
  std::string spec_;
  std::optional<Model> model_;
  Rgb ior_ = Rgb::Ones(), extinction_ = Rgb::Zero();
};

}  // namespace brdf::gonio
