// glTF 2.0 material (glTF 2.0 specification, Appendix B "BRDF Implementation"; the ratified
// KHR_materials_specular extension's "Implementation" section):
//   specular_brdf = D G / (4 |N·L| |N·V|), GGX D with alpha = roughness², separable Smith
//                   G = G1(L) G1(V) with G1 = 2 |N·X| / (|N·X| + sqrt(α² + (1 − α²)(N·X)²)),
//                   which is 1 / (1 + Λ_GGX)
//   metal         F = baseColor + (1 − baseColor)(1 − V·H)^5;  f = F specular_brdf
//   dielectric    F = f0 + (f90 − f0)(1 − V·H)^5, f0 = min(0.04 specularColor, 1) specular,
//                 f90 = specular;  f = F specular_brdf + (1 − max(F)) baseColor / π
//   material      f = mix(dielectric, metal, metallic)
// Schlick's Fresnel is glTF's own, so F maps exactly; D maps exactly through roughness = sqrt(α).
// The file puts the material on a preview sphere (AddPreviewSphere): importers that make objects
// from a file (Blender) drop a material no mesh uses.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/angles.h"
#include "export/targets.h"
#include "models/microfacet.h"

namespace brdf::exporters {
namespace {

// The dielectric f0 of glTF's default index of refraction, 1.5: ((1.5 − 1)/(1.5 + 1))².
constexpr double kDefaultDielectricF0 = 0.04;

// A metallic-roughness material with the KHR_materials_specular factors.
struct GltfMaterial {
  Rgb base_color = Rgb::Ones();
  double metallic = 1, roughness = 1;
  double specular = 1;               // specularFactor
  Rgb specular_color = Rgb::Ones();  // specularColorFactor
  bool uses_specular_extension = false;

  double Alpha() const { return roughness * roughness; }
  MicrofacetLobe Lobe() const {
    MicrofacetLobe lobe;
    lobe.distribution = Distribution::kGgx;
    lobe.masking = Masking::kSeparable;
    lobe.alpha = Alpha();
    return lobe;
  }
  Rgb DielectricFresnel(double cos_d) const {
    const Rgb f0 = (kDefaultDielectricF0 * specular_color).min(1.0) * specular;
    return f0 + (specular - f0) * models::SchlickFresnel(cos_d, 0.0);
  }
  Rgb MetalFresnel(double cos_d) const {
    return base_color + (1.0 - base_color) * models::SchlickFresnel(cos_d, 0.0);
  }
  Rgb Eval(const Vec3& wi, const Vec3& wo) const {
    const HalfVectorGeometry g = Geometry(wi, wo);
    if (!g.above) return Rgb::Zero();
    // A roughness of 0 is a mirror, which no BRDF holds; the mapping never writes one.
    const double lobe = Lobe().Eval(g);
    Rgb f = Rgb::Zero();
    if (metallic < 1) {
      const Rgb fresnel = DielectricFresnel(g.cos_theta_d);
      f += (1.0 - metallic) * (fresnel * lobe + (1.0 - fresnel.maxCoeff()) * base_color * kInvPi);
    }
    if (metallic > 0) f += metallic * MetalFresnel(g.cos_theta_d) * lobe;
    return f;
  }
  nlohmann::json Json() const {
    nlohmann::json material;
    material["name"] = "brdfkit";
    material["pbrMetallicRoughness"] = {
        {"baseColorFactor", {base_color[0], base_color[1], base_color[2], 1.0}},
        {"metallicFactor", metallic},
        {"roughnessFactor", roughness}};
    if (uses_specular_extension) {
      material["extensions"]["KHR_materials_specular"] = {
          {"specularFactor", specular},
          {"specularColorFactor", {specular_color[0], specular_color[1], specular_color[2]}}};
    }
    return material;
  }
};

Rgb Clamp01(const Rgb& rgb) { return rgb.max(0.0).min(1.0); }

// The preview sphere's tessellation: rings from pole to pole and segments around, enough for a
// highlight to read as round in an importer's viewport, small enough to keep the file a few tens
// of kilobytes.
constexpr int kSphereRings = 16, kSphereSegments = 32;
// glTF's buffer-view targets (glTF 2.0 specification, 5.11 bufferView.target).
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
// glTF's component types (5.1.3 accessor.componentType).
constexpr int kFloat = 5126, kUnsignedShort = 5123;

// RFC 4648 base64, the encoding of glTF's data: URIs.
std::string Base64(const std::vector<uint8_t>& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string text;
  text.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t k = 0; k < bytes.size(); k += 3) {
    const uint32_t chunk = (uint32_t{bytes[k]} << 16) |
                           (k + 1 < bytes.size() ? uint32_t{bytes[k + 1]} << 8 : 0) |
                           (k + 2 < bytes.size() ? uint32_t{bytes[k + 2]} : 0);
    text += kAlphabet[(chunk >> 18) & 63];
    text += kAlphabet[(chunk >> 12) & 63];
    text += k + 1 < bytes.size() ? kAlphabet[(chunk >> 6) & 63] : '=';
    text += k + 2 < bytes.size() ? kAlphabet[chunk & 63] : '=';
  }
  return text;
}

template <typename T>
void AppendBytes(const std::vector<T>& values, std::vector<uint8_t>* bytes) {
  const auto* begin = reinterpret_cast<const uint8_t*>(values.data());
  bytes->insert(bytes->end(), begin, begin + values.size() * sizeof(T));
}

// A unit sphere wearing the material, as one mesh in one node of one scene: an importer that
// makes objects, not bare materials (Blender's), then keeps the material. Positions double as
// normals; triangles wind counter-clockwise seen from outside (glTF's front face); the poles'
// degenerate triangles are left out.
void AddPreviewSphere(nlohmann::json* document) {
  std::vector<float> positions;
  for (int ring = 0; ring <= kSphereRings; ++ring) {
    const double theta = kPi * ring / kSphereRings;
    for (int segment = 0; segment <= kSphereSegments; ++segment) {
      const double phi = 2.0 * kPi * segment / kSphereSegments;
      // glTF is +Y up.
      positions.push_back(static_cast<float>(std::sin(theta) * std::cos(phi)));
      positions.push_back(static_cast<float>(std::cos(theta)));
      positions.push_back(static_cast<float>(-std::sin(theta) * std::sin(phi)));
    }
  }
  std::vector<uint16_t> indices;
  auto vertex = [](int ring, int segment) {
    return static_cast<uint16_t>(ring * (kSphereSegments + 1) + segment);
  };
  for (int ring = 0; ring < kSphereRings; ++ring) {
    for (int segment = 0; segment < kSphereSegments; ++segment) {
      const uint16_t a = vertex(ring, segment), b = vertex(ring + 1, segment),
                     c = vertex(ring + 1, segment + 1), d = vertex(ring, segment + 1);
      if (ring > 0) indices.insert(indices.end(), {a, b, d});
      if (ring + 1 < kSphereRings) indices.insert(indices.end(), {b, c, d});
    }
  }
  std::vector<uint8_t> bytes;
  AppendBytes(positions, &bytes);
  const size_t vertex_bytes = bytes.size();
  AppendBytes(indices, &bytes);
  const size_t vertex_count = positions.size() / 3;
  (*document)["buffers"] = {{{"byteLength", bytes.size()},
                             {"uri", "data:application/octet-stream;base64," + Base64(bytes)}}};
  (*document)["bufferViews"] = {
      {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", vertex_bytes}, {"target", kArrayBuffer}},
      {{"buffer", 0},
       {"byteOffset", vertex_bytes},
       {"byteLength", bytes.size() - vertex_bytes},
       {"target", kElementArrayBuffer}}};
  (*document)["accessors"] = {{{"bufferView", 0},
                               {"componentType", kFloat},
                               {"count", vertex_count},
                               {"type", "VEC3"},
                               {"min", {-1.0, -1.0, -1.0}},
                               {"max", {1.0, 1.0, 1.0}}},
                              {{"bufferView", 1},
                               {"componentType", kUnsignedShort},
                               {"count", indices.size()},
                               {"type", "SCALAR"}}};
  (*document)["meshes"] = {
      {{"name", "brdfkit preview sphere"},
       {"primitives",
        {{{"attributes", {{"POSITION", 0}, {"NORMAL", 0}}}, {"indices", 1}, {"material", 0}}}}}};
  (*document)["nodes"] = {{{"name", "brdfkit preview sphere"}, {"mesh", 0}}};
  (*document)["scenes"] = {{{"nodes", {0}}}};
  (*document)["scene"] = 0;
}

// The glTF file of a material whose parameters are set, on the preview sphere.
ExportedMaterial GltfDocument(const GltfMaterial& chosen, ExportedMaterial material) {
  nlohmann::json document;
  document["asset"] = {{"version", "2.0"}, {"generator", "brdfkit export"}};
  if (chosen.uses_specular_extension) {
    document["extensionsUsed"] = {"KHR_materials_specular"};
  }
  document["materials"] = nlohmann::json::array({material.parameters});
  AddPreviewSphere(&document);
  material.text = document.dump(2) + "\n";
  return material;
}

// A Lambertian material: specularFactor 0 turns the dielectric's Fresnel off (f0 = f90 = 0),
// leaving f = baseColor/π. By the specification specularColorFactor and roughness then play no
// part; they are chosen for importers that read the material through a principled BSDF.
// Blender 3.4's importer takes its Specular from specularColorFactor alone (0: no lobe), and
// Disney's diffuse, whose grazing factor F_D90 = 0.5 + 2 roughness cos²θd, is Lambertian at
// roughness 0.25 where light and view coincide (θd = 0) and keeps F_D90 within 0.5…1 elsewhere,
// where roughness 1 reaches 2.5 (docs/export.md, "Rendered by Blender").
GltfMaterial DiffuseOnly(const Rgb& rho_d) {
  GltfMaterial material;
  material.base_color = Clamp01(rho_d);
  material.metallic = 0;
  material.roughness = 0.25;
  material.specular = 0;
  material.specular_color = Rgb::Zero();
  material.uses_specular_extension = true;
  return material;
}

}  // namespace

ExportedMaterial MapToGltf(const MappingInput& input) {
  const MicrofacetSource& source = input.source;
  ExportedMaterial material;
  material.target = Target::kGltf;
  GltfMaterial chosen;
  if (!source.has_lobe) {
    chosen = DiffuseOnly(source.rho_d);
    material.material = "pbrMetallicRoughness, metallic 0, KHR_materials_specular specularFactor 0";
    material.exact = (chosen.base_color == source.rho_d).all();
    material.notes.push_back(
        "baseColor = rho_d with specularFactor 0 (no specular reflection): exact, f = "
        "baseColor/pi");
    if (!material.exact) material.notes.push_back("rho_d above 1 was clamped to baseColor 1");
  } else {
    const double roughness = std::sqrt(std::min(source.alpha, 1.0));
    // Metal: F = Schlick(baseColor = f0) exactly, no diffuse term.
    GltfMaterial metal;
    metal.base_color = Clamp01(source.f0);
    metal.metallic = 1;
    metal.roughness = roughness;
    // Dielectric: specularColor = f0 / 0.04 with specular 1 makes f0 and f90 = 1 Schlick's;
    // the diffuse term is weighted by 1 − max(F), so baseColor is fitted to the fit's floor.
    GltfMaterial dielectric;
    dielectric.metallic = 0;
    dielectric.roughness = roughness;
    dielectric.specular = 1;
    dielectric.specular_color = source.f0 / kDefaultDielectricF0;
    dielectric.uses_specular_extension = true;
    dielectric.base_color = Rgb::Zero();
    const GltfMaterial lobe_only = dielectric;
    dielectric.base_color = FitDiffuseScale(
        input,
        [&](const Vec3& wi, const Vec3& wo) {
          const HalfVectorGeometry g = Geometry(wi, wo);
          if (!g.above) return 0.0;
          return (1.0 - lobe_only.DielectricFresnel(g.cos_theta_d).maxCoeff()) * kInvPi;
        },
        [&](const Vec3& wi, const Vec3& wo) { return lobe_only.Eval(wi, wo); });
    auto error_of = [&](const GltfMaterial& candidate) {
      return MappingLogRmse([&](const Vec3& wi, const Vec3& wo) { return candidate.Eval(wi, wo); },
                            input);
    };
    // Diffuse alone (specularFactor 0): glTF's Fresnel rises to f90 = 1 at grazing in both of the
    // others, which a lobe of small f0 (a refit of a broad lobe) does not; then this is closer.
    const GltfMaterial diffuse_only = DiffuseOnly(source.rho_d);
    const bool use_metal = source.rho_d.maxCoeff() <= 0 || error_of(metal) <= error_of(dielectric);
    chosen = use_metal ? metal : dielectric;
    if (source.rho_d.maxCoeff() > 0 && error_of(diffuse_only) < error_of(chosen)) {
      material.material =
          "pbrMetallicRoughness, metallic 0, KHR_materials_specular specularFactor 0";
      material.notes.push_back(
          "the fit's lobe is left out (specularFactor 0, baseColor = rho_d): glTF's Fresnel rises "
          "to 1 at grazing, and with it the lobe followed the fit less closely");
      material.parameters = diffuse_only.Json();
      material.eval = [diffuse_only](const Vec3& wi, const Vec3& wo) {
        return diffuse_only.Eval(wi, wo);
      };
      return GltfDocument(diffuse_only, std::move(material));
    }
    const TermDifferences terms = MeasureTermDifferences(input, chosen.Lobe(), [&](double cos_d) {
      return use_metal ? chosen.MetalFresnel(cos_d) : chosen.DielectricFresnel(cos_d);
    });
    material.material = use_metal ? "pbrMetallicRoughness, metallic 1"
                                  : "pbrMetallicRoughness, metallic 0, KHR_materials_specular";
    material.notes.push_back("D: exact (GGX; roughness = sqrt(alpha), glTF's alpha = roughness^2)" +
                             std::string(source.alpha > 1 ? "; alpha above 1 clamped to 1" : ""));
    material.notes.push_back(
        "F: exact (glTF's Fresnel is Schlick's" +
        std::string(use_metal ? ", f0 = baseColor" : ", f0 = 0.04 specularColorFactor, f90 = 1") +
        "; |F - F_Schlick| <= " + Num(terms.max_fresnel) + " on these samples)");
    material.notes.push_back(
        "G: glTF multiplies G1(L) G1(V); ours is height-correlated: G differs by up to " +
        Num(100 * terms.max_g_relative) + " % on these samples");
    if (use_metal && source.rho_d.maxCoeff() > 0) {
      material.notes.push_back(
          "the fit's diffuse term is left out: metallic 1 followed the fit "
          "more closely than the dielectric's coupled diffuse");
    }
    if (!use_metal) {
      material.notes.push_back("diffuse: glTF weights baseColor/pi by 1 - max(F); baseColor " +
                               Num(chosen.base_color[0]) + ", " + Num(chosen.base_color[1]) + ", " +
                               Num(chosen.base_color[2]) +
                               " chosen to follow the fit's diffuse floor");
    }
  }
  material.parameters = chosen.Json();
  material.eval = [chosen](const Vec3& wi, const Vec3& wo) { return chosen.Eval(wi, wo); };
  return GltfDocument(chosen, std::move(material));
}

}  // namespace brdf::exporters
