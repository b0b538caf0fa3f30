// brdf export (src/export/): where a renderer's model is the fit's, the exported material
// evaluates to the fit; where it is not, the difference is exactly the term that differs, and it
// is measured. Values are read back from the written files, not from the mapping's structs.
#include "export/export.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "core/angles.h"
#include "export/renderer_terms.h"
#include "fitters/fit.h"
#include "models/microfacet.h"
#include "models/model_string.h"
#include "synthetic_measurement.h"
#include "test_util.h"

namespace brdf::exporters {
namespace {

using testing::RunBrdf;
using testing::ScratchDir;

// Directions over the hemisphere, in and out of the plane of incidence.
std::vector<std::pair<Vec3, Vec3>> DirectionPairs() {
  std::vector<std::pair<Vec3, Vec3>> pairs;
  for (double theta_i : {0.0, 10.0, 35.0, 60.0, 80.0}) {
    for (double theta_o : {0.0, 20.0, 45.0, 70.0, 85.0}) {
      for (double phi_o : {0.0, 60.0, 180.0}) {
        pairs.push_back({SphericalDirection(DegToRad(theta_i), 0.0),
                         SphericalDirection(DegToRad(theta_o), DegToRad(phi_o))});
      }
    }
  }
  return pairs;
}

ExportedMaterial Export(const std::string& model, Target target) {
  ExportRequest request;
  request.fit = ParseModel(model);
  request.samples = HemisphereGridSamples(10.0);
  return ExportMaterial(request, target);
}

// The first "value" of <rgb name="NAME" value="..."/> in Mitsuba XML.
Rgb MitsubaRgb(const std::string& xml, const std::string& name) {
  std::smatch match;
  const std::regex pattern("<rgb name=\"" + name + "\" value=\"([^,]+), ([^,]+), ([^\"]+)\"/>");
  EXPECT_TRUE(std::regex_search(xml, match, pattern)) << name << " in\n" << xml;
  return Rgb(std::stod(match[1]), std::stod(match[2]), std::stod(match[3]));
}

// The first "rgb NAME" [ r g b ] of pbrt-v4 scene text.
Rgb PbrtRgb(const std::string& text, const std::string& name) {
  std::smatch match;
  const std::regex pattern("\"rgb " + name + "\" \\[ (\\S+) (\\S+) (\\S+) \\]");
  EXPECT_TRUE(std::regex_search(text, match, pattern)) << name << " in\n" << text;
  return Rgb(std::stod(match[1]), std::stod(match[2]), std::stod(match[3]));
}

// Smith Λ of GGX, written here from Walter et al. 2007 (eq. 34 with a = 1/(α tan θ)).
double GgxLambda(double cos_theta, double alpha) {
  const double tan2 = (1.0 - cos_theta * cos_theta) / (cos_theta * cos_theta);
  return (std::sqrt(1.0 + alpha * alpha * tan2) - 1.0) / 2.0;
}

TEST(Export, LambertIsExactInEveryRenderer) {
  const std::string fit = "lambert:rho_d=0.71,0.283,0.0417";
  const Model model = ParseModel(fit);
  for (Target target : AllTargets()) {
    const ExportedMaterial material = Export(fit, target);
    EXPECT_TRUE(material.exact) << TargetName(target);
    EXPECT_LT(material.error.log_rmse, 1e-12) << TargetName(target);
    EXPECT_LT(material.error.max_relative, 1e-12) << TargetName(target);
    // The file holds the reflectance that, as the renderer's f = R/π, is the fit.
    Rgb reflectance;
    if (target == Target::kMitsuba3) reflectance = MitsubaRgb(material.text, "reflectance");
    if (target == Target::kPbrtV4) reflectance = PbrtRgb(material.text, "reflectance");
    if (target == Target::kGltf) {
      const nlohmann::json gltf = nlohmann::json::parse(material.text);
      const nlohmann::json& pbr = gltf["materials"][0]["pbrMetallicRoughness"];
      for (int c = 0; c < 3; ++c) reflectance[c] = pbr["baseColorFactor"][c].get<double>();
      const nlohmann::json& specular = gltf["materials"][0]["extensions"]["KHR_materials_specular"];
      EXPECT_EQ(specular["specularFactor"], 0);
      // The same material by the specification; importers that read the specular colour alone
      // (Blender 3.4) then make no lobe either.
      for (int c = 0; c < 3; ++c) EXPECT_EQ(specular["specularColorFactor"][c], 0);
    }
    for (const auto& [wi, wo] : DirectionPairs()) {
      const Rgb expected = model.Eval(wi, wo);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(reflectance[c] / kPi, expected[c], 1e-6 * expected[c]) << TargetName(target);
        EXPECT_NEAR(material.eval(wi, wo)[c], expected[c], 1e-12) << TargetName(target);
      }
    }
  }
}

// glTF's metal: D (roughness² = alpha) and F (Schlick's, f0 = baseColor) are ours, so the glTF
// BRDF is the fit times G_separable / G_height-correlated = (1 + Λi + Λo) / ((1 + Λi)(1 + Λo)):
// equal where Λ(wi) or Λ(wo) is 0 (either direction at the normal), lower everywhere else.
TEST(Export, GgxToGltfMetalDiffersOnlyByTheSeparableMasking) {
  const double alpha = 0.3;
  const std::string fit = "ggx:rho_d=0:f0=0.95,0.64,0.54:alpha=0.3";
  const Model model = ParseModel(fit);
  const ExportedMaterial material = Export(fit, Target::kGltf);
  EXPECT_FALSE(material.exact);
  const nlohmann::json pbr =
      nlohmann::json::parse(material.text)["materials"][0]["pbrMetallicRoughness"];
  EXPECT_EQ(pbr["metallicFactor"], 1.0);
  EXPECT_NEAR(std::pow(pbr["roughnessFactor"].get<double>(), 2), alpha, 1e-15);
  for (const auto& [wi, wo] : DirectionPairs()) {
    const double li = GgxLambda(wi.z(), alpha), lo = GgxLambda(wo.z(), alpha);
    const double g_ratio = (1.0 + li + lo) / ((1.0 + li) * (1.0 + lo));
    const Rgb ours = model.Eval(wi, wo), gltf = material.eval(wi, wo);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(gltf[c], ours[c] * g_ratio, 1e-12 * ours[c]);
      EXPECT_LE(gltf[c], ours[c] * (1 + 1e-12));
      if (wi.z() == 1.0 || wo.z() == 1.0) {
        EXPECT_NEAR(gltf[c], ours[c], 1e-12 * ours[c]);
      }
    }
  }
  // The measured error is that masking difference, and it is not negligible at alpha 0.3.
  EXPECT_GT(material.error.max_relative, 0.01);
}

// pbrt-v4's conductor: D and G are ours (Trowbridge-Reitz, height-correlated Smith); only the
// Fresnel factor differs, exact conductor Fresnel with the file's eta and k against Schlick's.
TEST(Export, GgxToPbrtConductorDiffersOnlyByFresnel) {
  const std::string fit = "ggx:rho_d=0:f0=0.9,0.6,0.3:alpha=0.2";
  const Model model = ParseModel(fit);
  const ExportedMaterial material = Export(fit, Target::kPbrtV4);
  EXPECT_EQ(material.material, "conductor");
  EXPECT_NE(material.text.find("\"bool remaproughness\" [ false ]"), std::string::npos);
  const Rgb eta = PbrtRgb(material.text, "eta"), k = PbrtRgb(material.text, "k");
  for (const auto& [wi, wo] : DirectionPairs()) {
    const Rgb ours = model.Eval(wi, wo), pbrt = material.eval(wi, wo);
    const Vec3 half_vector = (wi + wo).normalized();
    const double cos_d = wi.dot(half_vector);
    for (int c = 0; c < 3; ++c) {
      const double schlick = models::SchlickFresnel(cos_d, model.Param("f0", c));
      const double conductor = models::FresnelReflectance(cos_d, eta[c], k[c]);
      EXPECT_NEAR(pbrt[c], ours[c] * conductor / schlick, 1e-9 * ours[c]);
    }
  }
  // At the specular peak seen head on (wi = wo: cos_d = 1) the conductor's reflectance is f0:
  // there the export is the fit.
  for (double theta : {0.0, 30.0, 60.0}) {
    const Vec3 w = SphericalDirection(DegToRad(theta), 0.4);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(material.eval(w, w)[c], model.Eval(w, w)[c], 1e-6 * model.Eval(w, w)[c]);
    }
  }
}

// Mitsuba 3 (roughconductor, ggx): D exact; G separable, F conductor. At the normal both
// differences vanish.
TEST(Export, GgxToMitsubaIsTheFitAtNormalIncidenceAndView) {
  const std::string fit = "ggx:rho_d=0:f0=0.7:alpha=0.15";
  const Model model = ParseModel(fit);
  const ExportedMaterial material = Export(fit, Target::kMitsuba3);
  EXPECT_NE(material.text.find("<string name=\"distribution\" value=\"ggx\"/>"), std::string::npos);
  const Vec3 normal(0, 0, 1);
  EXPECT_NEAR(material.eval(normal, normal)[0], model.Eval(normal, normal)[0],
              1e-6 * model.Eval(normal, normal)[0]);
}

// Walter et al. 2007 give their rational Beckmann G1 (which Mitsuba 3 evaluates) as within
// 0.35 % of the exact 1 / (1 + Λ).
TEST(Export, MitsubaBeckmannMaskingIsWithinWaltersStatedError) {
  double worst = 0;
  for (double alpha : {0.05, 0.2, 0.5, 1.0}) {
    for (double theta = 1; theta < 89.5; theta += 0.5) {
      const double cos_theta = std::cos(DegToRad(theta));
      const double exact = 1.0 / (1.0 + models::BeckmannLobe::Lambda<double>(cos_theta, alpha));
      worst = std::max(worst, std::abs(BeckmannG1Rational(cos_theta, alpha) - exact) / exact);
    }
  }
  EXPECT_LT(worst, 0.0035);
  EXPECT_GT(worst, 0.0);
}

// A lobe over a diffuse base becomes a blend of diffuse and conductor in Mitsuba 3 and pbrt-v4:
// far from the highlight it must still show the fit's diffuse floor.
TEST(Export, DiffusePlusLobeKeepsTheDiffuseFloor) {
  const std::string fit = "ggx:rho_d=0.4,0.2,0.1:f0=0.04:alpha=0.1";
  const Model model = ParseModel(fit);
  for (Target target : {Target::kMitsuba3, Target::kPbrtV4, Target::kGltf}) {
    const ExportedMaterial material = Export(fit, target);
    EXPECT_FALSE(material.exact);
    // Off the peak (wi at 30°, wo at 40° on the same side) the lobe is negligible.
    const Vec3 wi = SphericalDirection(DegToRad(30), 0), wo = SphericalDirection(DegToRad(40), 0);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(material.eval(wi, wo)[c], model.Eval(wi, wo)[c], 0.05 * model.Eval(wi, wo)[c])
          << TargetName(target) << " " << material.material;
    }
    EXPECT_LT(material.error.log_rmse, 0.05) << TargetName(target);
  }
}

// A power-cosine lobe is no renderer's: it is refitted as ggx, and the error is measured.
TEST(Export, BlinnPhongIsRefittedAsGgxAndMeasured) {
  const ExportedMaterial material = Export("blinn-phong:rho_d=0.3:rho_s=0.2:m=150", Target::kGltf);
  EXPECT_FALSE(material.exact);
  EXPECT_EQ(material.source.model, "ggx");
  EXPECT_NE(material.source.via.find("ggx"), std::string::npos);
  EXPECT_GT(material.error.log_rmse, 0.0);
  EXPECT_LT(material.error.log_rmse, 0.1);
}

// The renderers hold our lambert and ggx terms (and beckmann in Mitsuba 3): a composition of
// those is exported as it is, under its own name; any other term (the rough diffuse eon, a
// retro lobe, a second lobe, beckmann outside Mitsuba 3) makes the material a ggx refit.
TEST(Export, OnlyCompositionsOfHeldTermsAreExportedAsTheyAre) {
  const auto source_of = [](const std::string& model, Target target) {
    ExportRequest request;
    request.fit = ParseModel(model);
    request.samples = HemisphereGridSamples(10.0);
    return ExportMaterial(request, target).source;
  };
  const MicrofacetSource beckmann =
      source_of("beckmann:rho_d=0.3:f0=0.04:alpha=0.2", Target::kMitsuba3);
  EXPECT_TRUE(beckmann.via.empty()) << beckmann.via;
  EXPECT_EQ(beckmann.distribution, Distribution::kBeckmann);
  for (const char* model : {"eon:rho_d=0.5:sigma=0.6", "lambert+retro:rho_d=0.3:rho_r=0.2:n_r=20",
                            "lambert+ggx+ggx:rho_d=0.3:f0=0.04:alpha=0.3:f0_2=0.02:alpha_2=0.05",
                            "beckmann:rho_d=0.3:f0=0.04:alpha=0.2"}) {
    const MicrofacetSource source = source_of(model, Target::kGltf);
    EXPECT_EQ(source.model, "ggx") << model;
    EXPECT_EQ(source.distribution, Distribution::kGgx) << model;
    EXPECT_FALSE(source.via.empty()) << model;
  }
}

// A refit keeps each channel's colour in both terms: the diffuse reflectance and the lobe's f0
// keep the fit's order and roughly its ratios (2 : 1 between red and green, 6 and 5 : 1 between
// green and blue), whichever of the two ggx candidates (export.cpp) follows the fit more closely.
TEST(Export, RefitKeepsEveryChannelsColour) {
  const Model fit = ParseModel("blinn-phong:rho_d=0.6,0.3,0.05:rho_s=0.3,0.15,0.03:m=150");
  for (Target target : AllTargets()) {
    ExportRequest request;
    request.fit = fit;
    request.samples = HemisphereGridSamples(5.0);
    const ExportedMaterial material = ExportMaterial(request, target);
    const MicrofacetSource& source = material.source;
    EXPECT_EQ(source.model, "ggx");
    EXPECT_NEAR(source.rho_d[0] / source.rho_d[1], 2.0, 0.5) << source.via;
    EXPECT_GT(source.rho_d[1], 3.0 * source.rho_d[2]) << source.via;
    EXPECT_NEAR(source.f0[0] / source.f0[1], 2.0, 0.5) << source.via;
    EXPECT_GT(source.f0[1], 3.0 * source.f0[2]) << source.via;
  }
}

// The thresholds of export.h, each from both sides.
TEST(Export, WarningsFireOnlyPastTheirThresholds) {
  ExportError error;
  error.log_rmse = 0.05;
  error.max_relative = 9.9;
  EXPECT_TRUE(ExportWarnings(error, 0.03).empty());  // 0.05 < 2 × 0.03
  error.max_relative = 10.1;
  ASSERT_EQ(ExportWarnings(error, 0.03).size(), 1u);
  EXPECT_NE(ExportWarnings(error, 0.03)[0].find("10.1 times"), std::string::npos);
  error.max_relative = 1;
  ASSERT_EQ(ExportWarnings(error, 0.024).size(), 1u);  // 0.05 > 2 × 0.024
  EXPECT_NE(ExportWarnings(error, 0.024)[0].find("(0.024)"), std::string::npos);
  // A noise-free fit (own log-rmse ~0) is held to the floor, 0.02, not to twice nothing.
  error.log_rmse = 0.019;
  EXPECT_TRUE(ExportWarnings(error, 1e-9).empty());
  EXPECT_TRUE(ExportWarnings(error, -1).empty());  // without data: the floor alone
  error.log_rmse = 0.021;
  EXPECT_EQ(ExportWarnings(error, 1e-9).size(), 1u);
  EXPECT_EQ(ExportWarnings(error, -1).size(), 1u);
  // The highlight: the renderer's value there within a factor 2 of the fit's, either way.
  error.log_rmse = 0.01;
  error.highlight_fit = 100;
  for (double renderer : {51.0, 100.0, 199.0}) {
    error.highlight_renderer = renderer;
    EXPECT_TRUE(ExportWarnings(error, 0.03).empty()) << renderer;
  }
  error.highlight_renderer = 49;
  ASSERT_EQ(ExportWarnings(error, 0.03).size(), 1u);
  EXPECT_NE(ExportWarnings(error, 0.03)[0].find("loses the fitted highlight"), std::string::npos);
  error.highlight_renderer = 201;
  ASSERT_EQ(ExportWarnings(error, 0.03).size(), 1u);
  EXPECT_NE(ExportWarnings(error, 0.03)[0].find("brighter than fitted"), std::string::npos);
}

// Data made by a ggx model and fitted with ggx: every target holds the fit (ggx D, Schlick's or
// a conductor's F, separable or height-correlated G), so no export warns, and the highlight,
// looked for within 60 deg of the normal where those terms agree with ours, keeps its
// brightness well inside the warning's factor 2 (1.16 in pbrt-v4, 1.26 in Mitsuba 3).
TEST(Export, HealthyGgxExportKeepsTheHighlightAndDoesNotWarn) {
  const Model truth = ParseModel("ggx:rho_d=0.5,0.3,0.1:f0=0.04,0.05,0.06:alpha=0.08");
  testing::SyntheticOptions options;
  options.theta_step_deg = 10;
  const Measurement measurement = testing::SynthesizeOnHemisphere(truth, options);
  ExportRequest request;
  request.fit = fitters::FitModel(measurement, "ggx", fitters::FitOptions{}).model;
  request.samples = SamplesForExport(measurement);
  for (Target target : AllTargets()) {
    const ExportedMaterial material = ExportMaterial(request, target);
    EXPECT_TRUE(material.warnings.empty())
        << TargetName(target) << ": " << (material.warnings.empty() ? "" : material.warnings[0]);
    const double ratio = material.error.highlight_renderer / material.error.highlight_fit;
    EXPECT_GT(ratio, 1.0 / 1.5) << TargetName(target);
    EXPECT_LT(ratio, 1.5) << TargetName(target);
    // The lobe's peak: at the mirror direction, at an incidence of at most 60 deg.
    EXPECT_LE(std::acos(material.error.highlight_wi.z()), DegToRad(60.0) + 1e-9);
    EXPECT_NEAR(material.error.highlight_fit,
                truth.Eval(material.error.highlight_wi, material.error.highlight_wo).maxCoeff(),
                0.05 * material.error.highlight_fit);
  }
}

TEST(Export, MitsubaXmlIsWellFormed) {
  ScratchDir dir;
  for (const std::string fit :
       {"lambert:rho_d=0.5", "ggx:rho_d=0:f0=0.9:alpha=0.2", "ggx:rho_d=0.3:f0=0.04:alpha=0.1",
        "beckmann:rho_d=0.2:f0=0.05:alpha=0.3"}) {
    const std::string path = dir.Write("material.xml", Export(fit, Target::kMitsuba3).text);
    const testing::CommandResult parsed = testing::RunCommand(
        "/usr/bin/python3 -c 'import sys, xml.dom.minidom as m; d = m.parse(sys.argv[1]); "
        "print(d.documentElement.tagName, len(d.getElementsByTagName(\"bsdf\")))' " +
        path);
    EXPECT_EQ(parsed.exit_status, 0) << fit << "\n" << parsed.err;
    EXPECT_EQ(parsed.out.substr(0, 6), "scene ") << fit;
  }
}

// The glTF file carries the material on a mesh (a unit sphere in the default scene), so that an
// importer which makes objects keeps it. Read back by Python's base64 and struct: every vertex
// on the unit sphere, every triangle facing outward (counter-clockwise from outside).
TEST(Export, GltfCarriesThePreviewSphere) {
  ScratchDir dir;
  const std::string path =
      dir.Write("m.gltf", Export("ggx:rho_d=0.3:f0=0.04:alpha=0.1", Target::kGltf).text);
  const nlohmann::json document = nlohmann::json::parse(testing::ReadFileText(path));
  EXPECT_EQ(document["scene"], 0);
  EXPECT_EQ(document["scenes"][0]["nodes"][0], 0);
  EXPECT_EQ(document["nodes"][0]["mesh"], 0);
  EXPECT_EQ(document["meshes"][0]["primitives"][0]["material"], 0);
  const testing::CommandResult checked = testing::RunCommand(
      "/usr/bin/python3 -c '"
      "import base64, json, struct, sys\n"
      "d = json.load(open(sys.argv[1])); a = d[\"accessors\"]; v = d[\"bufferViews\"]\n"
      "data = base64.b64decode(d[\"buffers\"][0][\"uri\"].split(\",\")[1])\n"
      "n = a[0][\"count\"]; m = a[1][\"count\"]\n"
      "p = struct.unpack_from(\"<%df\" % (3 * n), data, v[0][\"byteOffset\"])\n"
      "i = struct.unpack_from(\"<%dH\" % m, data, v[1][\"byteOffset\"])\n"
      "P = [p[3 * k:3 * k + 3] for k in range(n)]\n"
      "print(n, m // 3, max(abs(sum(c * c for c in q) - 1) for q in P), end=\" \")\n"
      "sub = lambda x, y: [x[k] - y[k] for k in range(3)]\n"
      "out = 0\n"
      "for t in range(0, m, 3):\n"
      "  A, B, C = P[i[t]], P[i[t + 1]], P[i[t + 2]]; u = sub(B, A); w = sub(C, A)\n"
      "  x = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]\n"
      "  out += sum(x[k] * (A[k] + B[k] + C[k]) for k in range(3)) > 0\n"
      "print(out)' " +
      path);
  ASSERT_EQ(checked.exit_status, 0) << checked.err;
  // 17 rings of 33 vertices; 16 x 32 quads of two triangles less the 2 x 32 at the poles.
  std::istringstream numbers(checked.out);
  int vertices = 0, triangles = 0, outward = 0;
  double largest_norm_error = 1;
  numbers >> vertices >> triangles >> largest_norm_error >> outward;
  EXPECT_EQ(vertices, 17 * 33);
  EXPECT_EQ(triangles, 16 * 32 * 2 - 2 * 32);
  EXPECT_LT(largest_norm_error, 1e-6);
  EXPECT_EQ(outward, triangles);
}

TEST(ExportCli, WritesTheFileAndReportsTheError) {
  ScratchDir dir;
  const std::string fit = dir.Write("fit.json", R"({"model": "lambert",
      "params": {"rho_d": [0.5, 0.4, 0.3]}, "source": "absent.csv"})");
  const testing::CommandResult result =
      RunBrdf("export " + fit + " --to pbrt-v4 --out " + dir.File("m.pbrt") + " --json");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["target"], "pbrt-v4");
  EXPECT_EQ(report["exact"], true);
  EXPECT_LT(report["error"]["max_relative"].get<double>(), 1e-12);
  EXPECT_NE(report["error"]["samples_origin"].get<std::string>().find("grid"), std::string::npos);
  EXPECT_NE(testing::ReadFileText(dir.File("m.pbrt")).find("\"string type\" [ \"diffuse\" ]"),
            std::string::npos);
}

// RGL cg_sunflower fitted with blinn-phong (l2): a lobe of exponent ~5e4, far narrower than the
// samples are spaced, over a yellow diffuse term. No ggx lobe follows it on the samples, so every
// target's material keeps the yellow but loses the highlight (at normal incidence the fit gives
// ~370 sr^-1, the renderers ~0.002), though in Mitsuba 3 and pbrt-v4 the log-rmse stays under
// twice the fit's own: the CLI says so on stderr and in the JSON, exit status 0. glTF also
// overshoots at grazing, where its Fresnel rises to 1 and the fit has no lobe. A ggx fit of the
// same file exports to every target without a warning.
TEST(ExportCli, WarnsWhenTheRendererLosesTheFitAndOnlyThen) {
  ScratchDir dir;
  const std::string data = testing::DataPath("rgl-bsdf/cg_sunflower_rgb.bsdf");
  for (const char* model : {"blinn-phong", "ggx"}) {
    const std::string fit = dir.File(std::string(model) + ".json");
    const testing::CommandResult fitted =
        RunBrdf("fit '" + data + "' --model " + model + " --loss l2 --quiet --out " + fit);
    ASSERT_EQ(fitted.exit_status, 0) << fitted.err;
    for (Target target : AllTargets()) {
      const std::string name = TargetName(target);
      const testing::CommandResult exported =
          RunBrdf("export " + fit + " --to " + name + " --json --out " + dir.File("m" + name));
      ASSERT_EQ(exported.exit_status, 0) << exported.err;
      const nlohmann::json report = nlohmann::json::parse(exported.out);
      const nlohmann::json& rho_d = report["mapped_from"]["rho_d"];
      // Yellow: red well above green, green well above blue, whichever model.
      EXPECT_GT(rho_d[0].get<double>(), 1.5 * rho_d[1].get<double>()) << name << rho_d;
      EXPECT_GT(rho_d[1].get<double>(), 10 * rho_d[2].get<double>()) << name << rho_d;
      const nlohmann::json& highlight = report["error"]["highlight"];
      const double ratio = highlight["renderer"].get<double>() / highlight["fit"].get<double>();
      if (std::string(model) == "blinn-phong") {
        EXPECT_GT(highlight["fit"].get<double>(), 100.0) << name;
        EXPECT_LT(ratio, 1e-3) << name;
        ASSERT_FALSE(report["warnings"].empty()) << name << report.dump(2);
        EXPECT_NE(exported.err.find("brdf export: warning: at the fit's highlight (theta_i 0 "
                                    "deg, theta_o 0 deg)"),
                  std::string::npos)
            << name << exported.err;
        EXPECT_NE(exported.err.find("it loses the fitted highlight"), std::string::npos)
            << name << exported.err;
        if (target == Target::kGltf) {
          EXPECT_GT(report["error"]["max_relative"].get<double>(), kMaxRelativeWarning);
        }
      } else {
        EXPECT_NEAR(ratio, 1.0, 0.25) << name;
        EXPECT_LT(report["error"]["max_relative"].get<double>(), 1.0) << name;
        EXPECT_TRUE(report["warnings"].empty()) << name << report["warnings"];
        EXPECT_EQ(exported.err, "") << name;
      }
    }
  }
}

// The error is measured on the fit's own samples: its "source", found beside the report or one
// directory up (brdf demo's fits/ next to its measurements).
TEST(ExportCli, MeasuresOnTheFitsSourceFoundBesideTheReport) {
  ScratchDir dir;
  dir.Write("cayman.astm", testing::ReadFileText(testing::DataPath("cornell-astm/cayman.astm")));
  std::filesystem::create_directories(dir.File("fits"));
  const std::string fit = dir.Write("fits/fit.json", R"({"model": "lambert",
      "params": {"rho_d": [0.05, 0.02, 0.01]}, "source": "cayman.astm"})");
  const testing::CommandResult result =
      RunBrdf("export " + fit + " --to gltf --out " + dir.File("m.gltf") + " --json");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  const std::string origin = report["error"]["samples_origin"];
  EXPECT_NE(origin.find("cayman.astm"), std::string::npos) << origin;
  EXPECT_EQ(origin.find("grid"), std::string::npos) << origin;
  EXPECT_GT(report["error"]["samples"].get<int>(), 100);
}

TEST(ExportCli, BadInputIsOneLineAndExitTwo) {
  ScratchDir dir;
  const std::string not_a_fit = dir.Write("data.json", R"({"rows": [1, 2, 3]})");
  const std::string fit =
      dir.Write("fit.json", R"({"model": "lambert", "params": {"rho_d": 0.5}})");
  const testing::CommandResult wrong_file =
      RunBrdf("export " + not_a_fit + " --to gltf --out " + dir.File("a.gltf"));
  EXPECT_EQ(wrong_file.exit_status, 2);
  EXPECT_NE(wrong_file.err.find(not_a_fit), std::string::npos) << wrong_file.err;
  EXPECT_EQ(testing::CountLines(wrong_file.err), 1) << wrong_file.err;
  const testing::CommandResult wrong_target =
      RunBrdf("export " + fit + " --to blender --out " + dir.File("b.blend"));
  EXPECT_EQ(wrong_target.exit_status, 2);
  EXPECT_NE(wrong_target.err.find("(known: mitsuba3, pbrt-v4, gltf)"), std::string::npos)
      << wrong_target.err;
  EXPECT_EQ(RunBrdf("export " + fit + " --out " + dir.File("c.xml")).exit_status, 2);
  // Nothing written: the three inputs above (data.json, fit.json) only.
  EXPECT_EQ(dir.CountEntries(), 2);
}

}  // namespace
}  // namespace brdf::exporters
