#include "lbfit_models.h"

#include <algorithm>
#include <cmath>

#include "core/angles.h"

namespace brdf::lbfit {
namespace {

// libbsdf's Ggx::computeD, with alpha_sq = alpha^2.
double GgxD(double cos_theta_h, double alpha_sq) {
  const double d = cos_theta_h * cos_theta_h * (alpha_sq - 1.0) + 1.0;
  return alpha_sq / (kPi * d * d);
}

// libbsdf's Ggx::computeG1: the separable Smith masking of one direction.
double GgxG1(double cos_theta, double alpha_sq) {
  const double tan_sq = 1.0 / (cos_theta * cos_theta) - 1.0;
  return 2.0 / (1.0 + std::sqrt(1.0 + alpha_sq * tan_sq));
}

// libbsdf's computeSchlickFresnel(dotLH, color); dotLH clamped as Ggx::clampDotLH does.
Rgb SchlickFresnel(double cos_theta_d, const Rgb& f0) {
  const double c = std::clamp(cos_theta_d, -1.0, 1.0);
  return f0 + (1.0 - f0) * std::pow(1.0 - c, 5.0);
}

Rgb Colour(const std::vector<double>& values) { return Rgb(values[0], values[1], values[2]); }

}  // namespace

Rgb EvalUe4(const Ue4Parameters& p, const Vec3& wi, const Vec3& wo) {
  const double cos_i = wi.z(), cos_o = wo.z();
  const Vec3 h = (wi + wo).normalized();
  const double alpha = p.roughness * p.roughness;
  const Rgb f0 = Rgb::Constant(0.08 * p.specular) +
                 (p.base_color - Rgb::Constant(0.08 * p.specular)) * p.metallic;
  // UE4's "anything below 2 % is a shadow" clamp of the grazing term, on F0's green.
  const double fc = std::pow(1.0 - wo.dot(h), 5.0);
  const Rgb fresnel = Rgb::Constant(std::min(50.0 * f0[1], 1.0) * fc) + (1.0 - fc) * f0;
  const double vis =
      0.5 / (cos_i * (cos_o * (1.0 - alpha) + alpha) + cos_o * (cos_i * (1.0 - alpha) + alpha));
  return p.base_color * kInvPi * (1.0 - p.metallic) + fresnel * GgxD(h.z(), alpha * alpha) * vis;
}

Rgb EvalGgx(const GgxParameters& p, const Vec3& wi, const Vec3& wo) {
  const double cos_i = wi.z(), cos_o = wo.z();
  const Vec3 h = (wi + wo).normalized();
  const double alpha = p.roughness * p.roughness;
  const double alpha_sq = alpha * alpha;
  const double g = GgxG1(cos_i, alpha_sq) * GgxG1(cos_o, alpha_sq);
  return SchlickFresnel(wi.dot(h), p.color) * g * GgxD(h.z(), alpha_sq) / (4.0 * cos_i * cos_o);
}

Rgb EvalAnisotropicGgx(const AnisotropicGgxParameters& p, const Vec3& wi, const Vec3& wo) {
  const double cos_i = wi.z(), cos_o = wo.z();
  const Vec3 h = (wi + wo).normalized();
  const double alpha_x = p.roughness_x * p.roughness_x;
  const double alpha_y = p.roughness_y * p.roughness_y;
  const double alpha_xy = alpha_x * alpha_y;
  const double g = GgxG1(cos_i, alpha_xy) * GgxG1(cos_o, alpha_xy);
  // GTR with gamma 2 (Burley 2012); t = (1, 0, 0), b = (0, -1, 0), so t.h = h.x, b.h = -h.y.
  const double d =
      h.x() * h.x() / (alpha_x * alpha_x) + h.y() * h.y() / (alpha_y * alpha_y) + h.z() * h.z();
  const double distribution = 1.0 / (kPi * alpha_xy * d * d);
  return SchlickFresnel(wi.dot(h), p.color) * g * distribution / (4.0 * cos_i * cos_o);
}

Rgb EvalLambertian(const Rgb& color) { return color * kInvPi; }

const std::vector<ModelKind>& ModelKinds() {
  static const std::vector<ModelKind> kinds = {
      {"Unreal Engine 4",
       "ue4",
       {{"Base color", 3}, {"Metallic", 1}, {"Specular", 1}, {"Roughness", 1}},
       [](const PrintedParameters& printed) -> Evaluator {
         const Ue4Parameters p{Colour(printed.at("Base color")), printed.at("Metallic")[0],
                               printed.at("Specular")[0], printed.at("Roughness")[0]};
         return [p](const Vec3& wi, const Vec3& wo) { return EvalUe4(p, wi, wo); };
       }},
      {"GGX (isotropic, no refractive index)",
       "ggx",
       {{"Color", 3}, {"Roughness", 1}},
       [](const PrintedParameters& printed) -> Evaluator {
         const GgxParameters p{Colour(printed.at("Color")), printed.at("Roughness")[0]};
         return [p](const Vec3& wi, const Vec3& wo) { return EvalGgx(p, wi, wo); };
       }},
      {"GGX (anisotropic, no refractive index)",
       "ggx_aniso",
       {{"Color", 3}, {"Roughness X", 1}, {"Roughness Y", 1}},
       [](const PrintedParameters& printed) -> Evaluator {
         const AnisotropicGgxParameters p{Colour(printed.at("Color")), printed.at("Roughness X")[0],
                                          printed.at("Roughness Y")[0]};
         return [p](const Vec3& wi, const Vec3& wo) { return EvalAnisotropicGgx(p, wi, wo); };
       }},
      {"Lambertian",
       "lambert",
       {{"Color", 3}},
       [](const PrintedParameters& printed) -> Evaluator {
         const Rgb f = EvalLambertian(Colour(printed.at("Color")));
         return [f](const Vec3&, const Vec3&) { return f; };
       }},
  };
  return kinds;
}

}  // namespace brdf::lbfit
