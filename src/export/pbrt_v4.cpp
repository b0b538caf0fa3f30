// pbrt-v4 scene text (pbrt-v4 file format documentation, "Materials": diffuse, conductor, mix):
//   diffuse    f = reflectance / π
//   conductor  f = FrComplex(cos_d, eta + i k) D G / (4 cos_i cos_o) with the Trowbridge-Reitz
//              (GGX) distribution and the height-correlated Smith G = 1 / (1 + Λ(wi) + Λ(wo))
//              (src/pbrt/util/scattering.h, TrowbridgeReitzDistribution); "roughness" is alpha
//              when "remaproughness" is false. pbrt-v4 has no Beckmann distribution, and it
//              treats alpha < 1e-3 as a perfect mirror (EffectivelySmooth).
//   mix        chooses the second of two named materials with probability "amount" at each
//              intersection: on average f = (1 − amount) f_first + amount f_second.
// coateddiffuse is not used: it is a stochastic layered model (a random walk between a rough
// dielectric and a diffuse base, with an absorbing layer of default thickness 0.01) whose value
// our evaluator could only estimate, so its error against the fit could not be measured.
#include <string>

#include "core/text.h"
#include "export/targets.h"

namespace brdf::exporters {
namespace {

// pbrt-v4 treats a Trowbridge-Reitz alpha below this as a perfectly smooth surface.
constexpr double kPbrtSmoothAlpha = 1e-3;

std::string RgbList(const Rgb& rgb) {
  return "[ " + FormatNumber(rgb[0]) + " " + FormatNumber(rgb[1]) + " " + FormatNumber(rgb[2]) +
         " ]";
}

std::string DiffuseText(const std::string& name, const Rgb& reflectance) {
  return "MakeNamedMaterial \"" + name + "\"\n    \"string type\" [ \"diffuse\" ]\n" +
         "    \"rgb reflectance\" " + RgbList(reflectance) + "\n";
}

std::string ConductorText(const std::string& name, const DiffuseConductorBlend& blend) {
  return "MakeNamedMaterial \"" + name + "\"\n    \"string type\" [ \"conductor\" ]\n" +
         "    \"rgb eta\" " + RgbList(blend.eta) + "\n    \"rgb k\" " + RgbList(blend.k) +
         "\n    \"float roughness\" [ " + FormatNumber(blend.lobe.alpha) + " ]\n" +
         "    \"bool remaproughness\" [ false ]\n";
}

}  // namespace

ExportedMaterial MapToPbrtV4(const MappingInput& input) {
  const MicrofacetSource& source = input.source;
  ExportedMaterial material;
  material.target = Target::kPbrtV4;
  if (!source.has_lobe) {
    MapToExactDiffuse(source.rho_d, &material);
    material.text = DiffuseText("brdfkit", source.rho_d);
    return material;
  }
  MicrofacetLobe lobe;
  lobe.distribution = Distribution::kGgx;
  lobe.masking = Masking::kHeightCorrelated;
  lobe.alpha = source.alpha;
  const DiffuseConductorBlend blend =
      FitDiffuseConductorBlend(input, lobe, /*has_specular_scale=*/false);
  const TermDifferences terms = MeasureTermDifferences(input, lobe, [&](double cos_d) {
    return Rgb(blend.weight * blend.specular_scale * ConductorFresnel(cos_d, blend.eta, blend.k));
  });
  material.eval = [blend](const Vec3& wi, const Vec3& wo) { return blend.Eval(wi, wo); };
  material.notes.push_back(
      "D and G: exact (Trowbridge-Reitz with height-correlated Smith masking, roughness = the "
      "fit's alpha with remaproughness false)");
  material.notes.push_back(
      "F: conductor takes eta and k, not Schlick's f0; eta and k per channel fitted to "
      "Schlick's curve (over the mix amount), f0 exact at normal incidence: |F - F_Schlick| <= " +
      Num(terms.max_fresnel) + " on these samples");
  material.notes.push_back(
      "pbrt-v4 renders spectrally: the RGB values are turned into spectra, so colours match "
      "only as far as that upsampling preserves them");
  if (source.alpha < kPbrtSmoothAlpha) {
    material.notes.push_back("alpha " + Num(source.alpha) +
                             " is below 0.001, which pbrt-v4 renders as a perfect mirror");
  }
  const nlohmann::json conductor = {{"type", "conductor"},
                                    {"eta", {blend.eta[0], blend.eta[1], blend.eta[2]}},
                                    {"k", {blend.k[0], blend.k[1], blend.k[2]}},
                                    {"roughness", blend.lobe.alpha},
                                    {"remaproughness", false}};
  if (blend.weight >= 1) {
    material.material = "conductor";
    material.parameters = conductor;
    if (source.rho_d.maxCoeff() > 0) {
      material.notes.push_back(
          "the fit's diffuse term is left out: a mix with a diffuse "
          "material followed the fit less closely");
    }
    material.text = ConductorText("brdfkit", blend);
    return material;
  }
  material.material = "mix of diffuse and conductor";
  material.parameters = {
      {"type", "mix"},
      {"amount", blend.weight},
      {"materials",
       {{{"type", "diffuse"},
         {"reflectance", {blend.reflectance[0], blend.reflectance[1], blend.reflectance[2]}}},
        conductor}}};
  material.notes.push_back(
      "diffuse + lobe as mix: amount " + Num(blend.weight) +
      " on the conductor, diffuse "
      "reflectance " +
      RgbList(blend.reflectance) +
      " chosen to follow the fit's diffuse floor; "
      "pbrt-v4 picks one of the two per intersection, so the blend holds on average");
  material.text = DiffuseText("brdfkit-diffuse", blend.reflectance) +
                  ConductorText("brdfkit-conductor", blend) +
                  "MakeNamedMaterial \"brdfkit\"\n    \"string type\" [ \"mix\" ]\n" +
                  "    \"string materials\" [ \"brdfkit-diffuse\" \"brdfkit-conductor\" ]\n" +
                  "    \"float amount\" [ " + FormatNumber(blend.weight) + " ]\n";
  return material;
}

}  // namespace brdf::exporters
