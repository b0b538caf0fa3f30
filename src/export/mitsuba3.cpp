// Mitsuba 3 scene XML (mitsuba3 documentation, "BSDFs": diffuse, roughconductor, blendbsdf):
//   diffuse         f = reflectance / π                                  (src/bsdfs/diffuse.cpp)
//   roughconductor  f = F_conductor(eta, k) D G / (4 cos_i cos_o) with distribution "ggx" or
//                   "beckmann", the same alpha as ours (not squared), and the separable Smith
//                   G = G1(wi) G1(wo) (include/mitsuba/render/microfacet.h; for Beckmann G1 is
//                   Walter et al.'s rational fit)
//   blendbsdf       f = (1 − weight) f_first + weight f_second
// roughplastic is not used: its diffuse term is coupled to the coating through rough-interface
// transmittance tables the plugin integrates at load time, which our evaluator would only imitate.
#include <string>

#include "core/text.h"
#include "export/targets.h"

namespace brdf::exporters {
namespace {

std::string RgbValue(const Rgb& rgb) {
  return FormatNumber(rgb[0]) + ", " + FormatNumber(rgb[1]) + ", " + FormatNumber(rgb[2]);
}

std::string DiffuseXml(const Rgb& reflectance, const std::string& indent, const std::string& id) {
  return indent + "<bsdf type=\"diffuse\"" + (id.empty() ? "" : " id=\"" + id + "\"") + ">\n" +
         indent + "    <rgb name=\"reflectance\" value=\"" + RgbValue(reflectance) + "\"/>\n" +
         indent + "</bsdf>\n";
}

std::string ConductorXml(const DiffuseConductorBlend& blend, const std::string& distribution,
                         const std::string& indent, const std::string& id) {
  return indent + "<bsdf type=\"roughconductor\"" + (id.empty() ? "" : " id=\"" + id + "\"") +
         ">\n" + indent + "    <string name=\"distribution\" value=\"" + distribution + "\"/>\n" +
         indent + "    <float name=\"alpha\" value=\"" + FormatNumber(blend.lobe.alpha) + "\"/>\n" +
         indent + "    <rgb name=\"eta\" value=\"" + RgbValue(blend.eta) + "\"/>\n" + indent +
         "    <rgb name=\"k\" value=\"" + RgbValue(blend.k) + "\"/>\n" +
         (blend.specular_scale != 1.0
              ? indent + "    <float name=\"specular_reflectance\" value=\"" +
                    FormatNumber(blend.specular_scale) + "\"/>\n"
              : std::string()) +
         indent + "</bsdf>\n";
}

}  // namespace

ExportedMaterial MapToMitsuba3(const MappingInput& input) {
  const MicrofacetSource& source = input.source;
  ExportedMaterial material;
  material.target = Target::kMitsuba3;
  std::string body;
  if (!source.has_lobe) {
    MapToExactDiffuse(source.rho_d, &material);
    body = DiffuseXml(source.rho_d, "    ", "brdfkit");
  } else {
    const bool beckmann = source.distribution == Distribution::kBeckmann;
    const std::string distribution = beckmann ? "beckmann" : "ggx";
    MicrofacetLobe lobe;
    lobe.distribution = beckmann ? Distribution::kBeckmann : Distribution::kGgx;
    lobe.masking = beckmann ? Masking::kSeparableRational : Masking::kSeparable;
    lobe.alpha = source.alpha;
    const DiffuseConductorBlend blend =
        FitDiffuseConductorBlend(input, lobe, /*has_specular_scale=*/true);
    const TermDifferences terms = MeasureTermDifferences(input, lobe, [&](double cos_d) {
      return Rgb(blend.weight * blend.specular_scale * ConductorFresnel(cos_d, blend.eta, blend.k));
    });
    material.eval = [blend](const Vec3& wi, const Vec3& wo) { return blend.Eval(wi, wo); };
    nlohmann::json conductor = {{"type", "roughconductor"},
                                {"distribution", distribution},
                                {"alpha", blend.lobe.alpha},
                                {"eta", {blend.eta[0], blend.eta[1], blend.eta[2]}},
                                {"k", {blend.k[0], blend.k[1], blend.k[2]}},
                                {"specular_reflectance", blend.specular_scale}};
    material.notes.push_back("D: exact (distribution=\"" + distribution +
                             "\", alpha = the fit's alpha, the same convention)");
    material.notes.push_back(std::string("G: Mitsuba 3 multiplies G1(wi) G1(wo)") +
                             (beckmann ? " with Walter et al.'s rational Beckmann G1" : "") +
                             "; ours is height-correlated: G differs by up to " +
                             Num(100 * terms.max_g_relative) + " % on these samples");
    material.notes.push_back(
        "F: roughconductor takes a conductor's eta and k, not Schlick's f0; eta and k per "
        "channel fitted to Schlick's curve, f0 exact at normal incidence: |F - F_Schlick| <= " +
        Num(terms.max_fresnel) + " on these samples");
    if (blend.weight >= 1) {
      material.material = "roughconductor (" + distribution + ")";
      material.parameters = conductor;
      if (source.rho_d.maxCoeff() > 0) {
        material.notes.push_back(
            "the fit's diffuse term is left out: a blend with a diffuse "
            "material followed the fit less closely");
      }
      body = ConductorXml(blend, distribution, "    ", "brdfkit");
    } else {
      material.material = "blendbsdf of diffuse and roughconductor (" + distribution + ")";
      material.parameters = {
          {"type", "blendbsdf"},
          {"weight", blend.weight},
          {"bsdfs",
           {{{"type", "diffuse"},
             {"reflectance", {blend.reflectance[0], blend.reflectance[1], blend.reflectance[2]}}},
            conductor}}};
      material.notes.push_back(
          "diffuse + lobe as blendbsdf: weight " + Num(blend.weight) +
          " on the conductor, whose specular_reflectance " + Num(blend.specular_scale) +
          " undoes it, and diffuse reflectance rho_d / (1 - weight): the sum of the fit, exact "
          "but for the lobe's G and F" +
          ((blend.reflectance * (1.0 - blend.weight) - source.rho_d).abs().maxCoeff() > 1e-12
               ? " (rho_d clamped)"
               : ""));
      body =
          "    <bsdf type=\"blendbsdf\" id=\"brdfkit\">\n        <float name=\"weight\" value=\"" +
          FormatNumber(blend.weight) + "\"/>\n" + DiffuseXml(blend.reflectance, "        ", "") +
          ConductorXml(blend, distribution, "        ", "") + "    </bsdf>\n";
    }
  }
  material.text = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<scene version=\"3.0.0\">\n" + body +
                  "</scene>\n";
  return material;
}

}  // namespace brdf::exporters
