// What the three targets (mitsuba3.cpp, pbrt_v4.cpp, gltf.cpp) share: the input of a mapping,
// the diffuse-plus-conductor blend that Mitsuba 3 and pbrt-v4 are given for a lobe over a diffuse
// base, and the measured differences of the microfacet terms that the notes report.
#pragma once

#include <string>
#include <vector>

#include "export/export.h"
#include "export/renderer_terms.h"

namespace brdf::exporters {

struct MappingInput {
  const MicrofacetSource& source;
  const Model& fit;
  // The samples parameters are chosen on (at most a few thousand of the request's) and the
  // fit's values there.
  const std::vector<fitters::FitSample>& samples;
  const std::vector<Rgb>& fit_values;
};

ExportedMaterial MapToMitsuba3(const MappingInput& input);
// A lobe-less fit as the renderers' `diffuse` material with reflectance rho_d: exact
// (f = reflectance / pi). Sets the material's name, parameters, note and evaluator.
void MapToExactDiffuse(const Rgb& rho_d, ExportedMaterial* material);
ExportedMaterial MapToPbrtV4(const MappingInput& input);
ExportedMaterial MapToGltf(const MappingInput& input);

// Weighted log-rmse of `renderer` against the fit's values on the mapping samples (the
// objective every parameter choice below minimises).
double MappingLogRmse(const std::function<Rgb(const Vec3&, const Vec3&)>& renderer,
                      const MappingInput& input);

// The diffuse reflectance R (per channel, clamped to [0, 1]) that makes R·a(wi, wo) + s(wi, wo)
// closest to the fit: weighted least squares on the linearised log loss, where a sample's
// residual is weighted by (cos_i / (1 + f cos_i))², the derivative of log(1 + f cos_i).
Rgb FitDiffuseScale(const MappingInput& input,
                    const std::function<double(const Vec3&, const Vec3&)>& diffuse_shape,
                    const std::function<Rgb(const Vec3&, const Vec3&)>& rest);

// The conductor (eta, k) whose exact Fresnel reflectance is closest, in relative terms, to
// scale · F_Schlick(f0) (clipped to 1) over cos theta_d in (0, 1], with the normal-incidence value
// matched exactly:
// ((eta − 1)² + k²) / ((eta + 1)² + k²) = scale · f0 leaves one free variable, eta in
// [1, (1 + √r)/(1 − √r)], searched on a grid and refined. eta = 1 is pbrt-v4's own map of a
// "reflectance" to k; k = 0 is a dielectric, whose Fresnel is what Schlick approximates.
struct ConductorIndex {
  double eta = 1, k = 0;
  double max_difference = 0;  // max |F_conductor − scale F_Schlick| on the grid
};
ConductorIndex FitConductorIndex(double f0, double scale);

// f = (1 − w) R/π + w s F_conductor(eta, k) D G / (4 cos_i cos_o): Mitsuba 3's blendbsdf of
// diffuse and roughconductor (whose specular_reflectance is s), pbrt-v4's mix of diffuse and
// conductor (s = 1); both document w as the weight of the second material. w = 1 is the
// conductor alone.
struct DiffuseConductorBlend {
  double weight = 1;
  Rgb reflectance = Rgb::Zero();  // of the diffuse material
  Rgb eta = Rgb::Ones();
  Rgb k = Rgb::Zero();
  double specular_scale = 1;  // s
  MicrofacetLobe lobe;

  Rgb Eval(const Vec3& wi, const Vec3& wo) const;
};
// With a specular scale (Mitsuba 3), s = 1/w makes the blend the fit's sum exactly but for the
// lobe's terms: w = min(1/2, 1 − max rho_d) keeps R = rho_d / (1 − w) <= 1. Without one
// (pbrt-v4), the conductor is fitted to F_Schlick / w, R follows the fit's diffuse floor, and w
// is the best of a grid on (max f0, 1]. Without a diffuse term, w = 1.
DiffuseConductorBlend FitDiffuseConductorBlend(const MappingInput& input,
                                               const MicrofacetLobe& lobe, bool has_specular_scale);

// Largest differences of the renderer's microfacet terms from ours on the mapping samples: the
// relative difference of G (and its sign: separable masking is never above height-correlated)
// and the absolute difference of the Fresnel factor, for the notes.
struct TermDifferences {
  double max_g_relative = 0;  // max |G_r − G_ours| / G_ours
  double max_fresnel = 0;     // max |F_r − F_Schlick| over channels
};
TermDifferences MeasureTermDifferences(
    const MappingInput& input, const MicrofacetLobe& renderer_lobe,
    const std::function<Rgb(double cos_theta_d)>& renderer_fresnel);

// "0.0123" style text for notes and files: 6 significant digits.
std::string Num(double value);

}  // namespace brdf::exporters
