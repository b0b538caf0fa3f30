// The reflectance models of the peer lbfit (libbsdf 2022-2023, applications/lbfit), evaluated with
// the peer's own conventions so that its fits can be scored in brdfkit's image space
// (bench/lbfit_score.cpp). Bench-only: these are libbsdf's conventions, not brdfkit models, and
// they live nowhere else. Read from libbsdf's headers include/libbsdf/ReflectanceModel/
// {UnrealEngine4,SimpleGgx,SimpleAnisotropicGgx,Ggx,Fresnel,Lambertian}.h:
//
// - every roughness r maps to alpha = r^2 (lbfit prints r, bounded to [0.01, 1]);
// - GGX D(h) = alpha^2 / (pi (cos^2 theta_h (alpha^2 - 1) + 1)^2);
// - the two "GGX (no refractive index)" models: f = F G D / (4 cos theta_i cos theta_o), with
//   Schlick's F = c + (1 - c)(1 - l.h)^5 on the fitted colour c, and the separable Smith
//   G = G1(wi) G1(wo), G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2 theta));
// - the anisotropic one: D = 1 / (pi ax ay ((t.h / ax)^2 + (b.h / ay)^2 + (n.h)^2)^2) with the
//   tangent t = (1, 0, 0) and bitangent b = (0, -1, 0) of the local frame, and G1 with
//   alpha^2 replaced by ax ay;
// - Unreal Engine 4 (Karis 2013): f = base / pi (1 - metallic) + F D Vis with
//   F0 = lerp(0.08 specular, base, metallic), F = min(50 F0.g, 1) Fc + (1 - Fc) F0,
//   Fc = (1 - v.h)^5, and Heitz's joint Smith approximation
//   Vis = 0.5 / (cos_i (cos_o (1 - alpha) + alpha) + cos_o (cos_i (1 - alpha) + alpha));
// - Lambertian: f = c / pi (its getBrdfValue; its getValue is c cos theta_i, a radiance).
//
// f in 1/sr, no cosine factor; wi, wo in the local frame, z the normal (DESIGN §1), both above
// the surface.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/vec.h"

namespace brdf::lbfit {

struct Ue4Parameters {
  Rgb base_color;
  double metallic, specular, roughness;
};
Rgb EvalUe4(const Ue4Parameters& p, const Vec3& wi, const Vec3& wo);

struct GgxParameters {
  Rgb color;  // Schlick's F0
  double roughness;
};
Rgb EvalGgx(const GgxParameters& p, const Vec3& wi, const Vec3& wo);

struct AnisotropicGgxParameters {
  Rgb color;  // Schlick's F0
  double roughness_x, roughness_y;
};
Rgb EvalAnisotropicGgx(const AnisotropicGgxParameters& p, const Vec3& wi, const Vec3& wo);

Rgb EvalLambertian(const Rgb& color);

// A model's parameters as lbfit prints them: name -> values (3 for a colour, 1 for a scalar).
using PrintedParameters = std::map<std::string, std::vector<double>>;
using Evaluator = std::function<Rgb(const Vec3& wi, const Vec3& wo)>;

// One model lbfit fits and prints, as the list entry the output reader and the scorer ask.
struct ModelKind {
  std::string heading;  // the block's heading without brackets, as lbfit prints it
  std::string key;      // short name for CSV columns: ue4, ggx, ggx_aniso, lambert
  // The printed parameters (lbfit's own "Error" line aside), each with its value count.
  std::vector<std::pair<std::string, int>> parameters;
  // The evaluator of a fit; `printed` holds every entry of `parameters`, checked by the reader.
  std::function<Evaluator(const PrintedParameters& printed)> make_evaluator;
};

// The four models lbfit prints, in its order.
const std::vector<ModelKind>& ModelKinds();

}  // namespace brdf::lbfit
