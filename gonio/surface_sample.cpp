#include "gonio/surface_sample.h"

#include <filesystem>

#include "core/errors.h"
#include "core/text.h"
#include "gonio/aperture.h"
#include "gonio/json_fields.h"
#include "gonio/model_sample.h"
#include "gonio/sampling.h"
#include "gonio/traced_surface.h"

namespace brdf::gonio {
namespace {

// Surface descriptions are small; anything larger is not one.
constexpr int64_t kMaxSurfaceBytes = int64_t{1} << 20;

}  // namespace

SurfaceSpec ReadSurfaceSpec(const std::string& path) {
  const nlohmann::json json =
      ParseJsonText(ReadFileBytes(path, kMaxSurfaceBytes), path, "a surface description");
  SurfaceSpec spec;
  JsonFields top(json, "", path);
  top.Object("heightfield", [&](JsonFields& field) {
    field.Text("kind", &spec.heightfield.kind);
    field.Number("rms_slope", &spec.heightfield.rms_slope);
    field.Number("rms_slope_y", &spec.heightfield.rms_slope_y);
    field.Integer("resolution", &spec.heightfield.resolution);
    field.Integer("seed", &spec.heightfield.seed);
    field.Number("correlation", &spec.heightfield.correlation);
    field.Integer("period", &spec.heightfield.period);
    field.Text("path", &spec.heightfield.path);
  });
  top.Text("base", &spec.base);
  top.Integer("bounces", &spec.bounces);
  top.Integer("rays_per_incidence", &spec.rays_per_incidence);
  top.RejectUnknown();
  if (spec.heightfield.kind != "v-grooves") spec.heightfield.period = 2;  // unused: any valid
  spec.heightfield.Validate(path);
  if (spec.bounces < 1 || spec.bounces > 64) {
    top.Fail("bounces", "must be in [1, 64], got " + std::to_string(spec.bounces));
  }
  if (spec.rays_per_incidence < 1000 || spec.rays_per_incidence > 2000000000) {
    top.Fail("rays_per_incidence", "must be in [1000, 2e9]");
  }
  if (!spec.heightfield.path.empty() &&
      std::filesystem::path(spec.heightfield.path).is_relative()) {
    spec.heightfield.path =
        (std::filesystem::path(path).parent_path() / spec.heightfield.path).string();
  }
  try {
    FacetMaterial::Parse(spec.base);
  } catch (const UsageError& error) {
    top.Fail("base", error.what());
  }
  return spec;
}

std::unique_ptr<GonioSample> MakeSurfaceSample(const SurfaceSpec& spec,
                                               const Instrument& instrument) {
  FacetMaterial material = FacetMaterial::Parse(spec.base);
  if (spec.heightfield.kind == "flat") {
    if (material.specular()) return std::make_unique<FlatSpecularSample>(material, instrument);
    return std::make_unique<ModelSample>(*material.model(), instrument);
  }
  return std::make_unique<TracedSurfaceSample>(MakeHeightField(spec.heightfield), material, spec);
}

std::unique_ptr<GonioSample> MakeSurfaceSample(const std::string& path,
                                               const Instrument& instrument) {
  return MakeSurfaceSample(ReadSurfaceSpec(path), instrument);
}

FlatSpecularSample::FlatSpecularSample(FacetMaterial material, const Instrument& instrument)
    : material_(std::move(material)) {
  // A mirror's lobe is a delta: the source cone needs the finest quadrature the rule allows.
  source_quadrature_ = ApertureQuadrature(instrument.SourceAngularRadius(), 0.0);
}

std::string FlatSpecularSample::Modelled() const {
  return "flat smooth " + material_.ToString() +
         " (exact Fresnel), measured analytically: " + std::to_string(source_quadrature_.size()) +
         " source points, no ray tracing, no BVH";
}

Readings FlatSpecularSample::Measure(const Instrument& instrument, const Vec3& wi,
                                     const std::vector<Vec3>& detectors, uint64_t /*seed*/,
                                     uint64_t /*incidence_index*/) const {
  // Reading = (1/Ω) · (power fraction into the detector): each source direction reflects
  // F(theta_i') of its power into its mirror direction.
  const double cos_detector = instrument.DetectorCosHalfAngle();
  const double solid_angle = instrument.detector_solid_angle_sr;
  std::vector<Rgb> readings(detectors.size(), Rgb::Zero());
  const double weight_sum = ForEachSourceDirection(
      instrument, wi, source_quadrature_, [&](const Vec3& wi_source, double weight) {
        const Vec3 mirror = MirrorDirection(wi_source);
        const Rgb reflected = weight * material_.Fresnel(wi_source.z());
        for (size_t k = 0; k < detectors.size(); ++k) {
          if (mirror.dot(detectors[k]) >= cos_detector) readings[k] += reflected;
        }
      });
  for (Rgb& reading : readings) reading /= weight_sum * solid_angle;
  return {readings, {}};
}

}  // namespace brdf::gonio
