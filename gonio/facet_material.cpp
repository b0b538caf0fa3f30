#include "gonio/facet_material.h"

#include <charconv>
#include <cmath>

#include "core/errors.h"
#include "core/text.h"
#include "gonio/sampling.h"
#include "models/microfacet.h"
#include "models/model_source.h"

namespace brdf::gonio {
namespace {

[[noreturn]] void Fail(const std::string& spec, const std::string& what) {
  throw UsageError("base material '" + spec + "': " + what);
}

Rgb ParseRgb(const std::string& spec, const std::string& key, const std::string& text) {
  std::vector<double> values;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find(',', start), text.size());
    double value = 0;
    const auto [ptr, error] = std::from_chars(text.data() + start, text.data() + end, value);
    if (error != std::errc() || ptr != text.data() + end || !std::isfinite(value) || value < 0) {
      Fail(spec, key + " needs one or three non-negative numbers, found '" + text + "'");
    }
    values.push_back(value);
    start = end + 1;
  }
  if (values.size() == 1) return Rgb::Constant(values[0]);
  if (values.size() != 3) Fail(spec, key + " needs one or three numbers");
  return Rgb(values[0], values[1], values[2]);
}

}  // namespace

FacetMaterial FacetMaterial::Parse(const std::string& spec) {
  FacetMaterial material;
  material.spec_ = spec;
  const std::string kind = spec.substr(0, spec.find(':'));
  if (kind != "conductor" && kind != "dielectric") {
    material.model_ = LoadModel(spec);
    return material;
  }
  bool has_ior = false, has_k = false;
  size_t start = spec.find(':');
  while (start != std::string::npos) {
    const size_t end = spec.find(':', start + 1);
    const std::string part =
        spec.substr(start + 1, end == std::string::npos ? std::string::npos : end - start - 1);
    const size_t equals = part.find('=');
    const std::string key = part.substr(0, equals);
    if (equals == std::string::npos) Fail(spec, "expected key=value, found '" + part + "'");
    if (key == "ior") {
      material.ior_ = ParseRgb(spec, key, part.substr(equals + 1));
      has_ior = true;
    } else if (key == "k" && kind == "conductor") {
      material.extinction_ = ParseRgb(spec, key, part.substr(equals + 1));
      has_k = true;
    } else {
      Fail(spec, "unknown parameter '" + key + "' (" + kind + " takes ior" +
                     (kind == "conductor" ? " and k)" : ")"));
    }
    start = end;
  }
  if (!has_ior) Fail(spec, "needs ior=N");
  if (kind == "conductor" && !has_k) Fail(spec, "needs k=K (extinction coefficient)");
  if ((material.ior_ <= 0).any()) Fail(spec, "ior must be positive");
  return material;
}

Rgb FacetMaterial::Fresnel(double cos_theta) const {
  Rgb reflectance;
  for (int c = 0; c < 3; ++c)
    reflectance[c] = models::FresnelReflectance(cos_theta, ior_[c], extinction_[c]);
  return reflectance;
}

Vec3 FacetMaterial::Scatter(const Vec3& wi, double u1, double u2, Rgb* throughput) const {
  if (model_) {
    // Cosine-weighted sampling: pdf = cos/π, so the weight f cos / pdf = π f.
    const Vec3 wo = SampleCosineHemisphere(Point2(u1, u2));
    *throughput *= kPi * model_->Eval(wi, wo);
    return wo;
  }
  *throughput *= Fresnel(wi.z());
  return MirrorDirection(wi);
}

}  // namespace brdf::gonio
