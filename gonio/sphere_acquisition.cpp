#include "gonio/sphere_acquisition.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <string>

#include "core/angles.h"
#include "core/parallel_ranks.h"
#include "core/text.h"
#include "gonio/measure.h"
#include "gonio/rng.h"
#include "gonio/sampling.h"

namespace brdf::gonio {
namespace {

Vec3 ToVec3(const glm::dvec3& v) { return Vec3(v.x, v.y, v.z); }

// Where the camera ray meets the unit sphere (nearest hit), or false.
bool HitSphere(const glm::dvec3& origin, const glm::dvec3& direction, glm::dvec3* point) {
  const double b = glm::dot(origin, direction);
  const double discriminant = b * b - (glm::dot(origin, origin) - 1.0);
  if (discriminant <= 0) return false;
  *point = origin + (-b - std::sqrt(discriminant)) * direction;
  return true;
}

// wi and wo in the local frame of `normal` with the tangent along wi's projection, so that
// phi_i = 0 (the materials are isotropic, DESIGN §2).
void ToLocal(const Vec3& normal, const Vec3& wi, const Vec3& wo, Vec3* wi_local, Vec3* wo_local) {
  Vec3 tangent = wi - wi.dot(normal) * normal;
  if (tangent.squaredNorm() < 1e-20) tangent = Frame::FromZ(normal).x;
  tangent.normalize();
  const Vec3 bitangent = normal.cross(tangent);
  *wi_local = Vec3(wi.dot(tangent), wi.dot(bitangent), wi.dot(normal));
  *wo_local = Vec3(wo.dot(tangent), wo.dot(bitangent), wo.dot(normal));
}

}  // namespace

std::vector<double> SphereLightThetas(const Schedule& schedule) {
  if (schedule.kind != "merl") return schedule.IncidenceThetas();
  std::vector<double> thetas;
  for (int k = 0; k < 18; ++k) thetas.push_back(DegToRad(5.0 * k));
  return thetas;
}

SphereAcquisition::SphereAcquisition(Model model, const Instrument& instrument)
    : model_(std::move(model)), instrument_(instrument) {
  camera_.eye = glm::dvec3(0, 0, instrument.camera_distance);
  camera_.resolution = instrument.camera_resolution;
  // Frame the sphere with a 2% margin: its silhouette subtends asin(1/d).
  camera_.vertical_fov = 2.0 * std::asin(1.0 / instrument.camera_distance) * 1.02;
  mesh_ = MakeUvSphere(instrument.sphere_segments);
}

std::string SphereAcquisition::Modelled() const {
  return "image-based acquisition of a sphere of " + model_.ToString() + ": UV-sphere mesh of " +
         std::to_string(mesh_.triangles.size()) + " triangles rasterized at " +
         std::to_string(camera_.resolution) + "x" + std::to_string(camera_.resolution) +
         " (z-buffer, perspective-correct normals), camera at " +
         FormatNumber(instrument_.camera_distance) + " radii; samples up to theta " +
         FormatNumber(instrument_.camera_max_theta_deg) +
         " deg; pixel geometry from the ideal sphere; light as a distant point (source and "
         "pixel footprints not integrated); per-pixel calibration against a Lambertian sphere";
}

SphereAcquisition::View SphereAcquisition::Shade(const GBuffer& gbuffer, double light_angle,
                                                 uint64_t seed, uint64_t view_index) const {
  const int n = gbuffer.resolution;
  // The light arm's positioning error, once per view; the acquisition assumes the nominal.
  Rng jitter_rng = StreamRng(seed, Stream::kIncidenceJitter, view_index);
  const double g1 = jitter_rng.Normal(), g2 = jitter_rng.Normal();
  const Vec3 light_nominal(std::sin(light_angle), 0, std::cos(light_angle));
  const double jitter = DegToRad(instrument_.jitter_deg);
  const Vec3 light = PerturbDirection(light_nominal, jitter, g1, g2);
  const Calibration calibration(instrument_, instrument_.reference_rho * kInvPi, seed);
  const double reference_scale = instrument_.reference_rho * kInvPi;
  // One list per row (only covered pixels), joined in row order afterwards.
  std::vector<std::vector<Sample>> row_samples(n);
  std::vector<std::vector<Rgb>> row_sigma(n);
  const glm::dvec3 eye = camera_.eye;
  const PinholeCamera::Basis basis = camera_.MakeBasis();
  const double cos_max_theta = std::cos(DegToRad(instrument_.camera_max_theta_deg));
  tbb::parallel_for(0, n, [&](int y) {
    for (int x = 0; x < n; ++x) {
      const size_t pixel = size_t(y) * n + x;
      if (!gbuffer.covered(pixel)) continue;
      // Rendered: the mesh with its interpolated normal.
      const Vec3 mesh_normal = ToVec3(gbuffer.normal[pixel]);
      const Vec3 mesh_wo = ToVec3(glm::normalize(eye - gbuffer.position[pixel]));
      const double cos_light = mesh_normal.dot(light);
      // Known geometry: the ideal sphere along the pixel's ray.
      glm::dvec3 point;
      if (!HitSphere(eye, camera_.PixelRay(basis, x, y), &point)) continue;
      const Vec3 normal = ToVec3(point);
      const Vec3 wo = ToVec3(glm::normalize(eye - point));
      if (normal.dot(light_nominal) <= cos_max_theta || normal.dot(wo) <= cos_max_theta ||
          cos_light <= 0) {
        continue;
      }
      Vec3 wi_local, wo_local, mesh_wi_local, mesh_wo_local;
      ToLocal(mesh_normal, light, mesh_wo, &mesh_wi_local, &mesh_wo_local);
      const Rgb radiance = model_.Eval(mesh_wi_local, mesh_wo_local) * cos_light;
      const Rgb reference_radiance = Rgb::Constant(reference_scale * cos_light);
      Rgb value, value_sigma;
      calibration.CalibrateRatio(radiance, reference_radiance, view_index * n * n + pixel, &value,
                                 &value_sigma);
      // The light arm's jitter, which the acquisition does not know, moves the value along the
      // BRDF's slope in the light direction (the cosine cancels against the reference's).
      const Rgb jitter_sigma = JitterSigma(light, jitter, [&](const Vec3& moved_light) -> Rgb {
        if (mesh_normal.dot(moved_light) <= 0) return Rgb::Zero();
        Vec3 moved_wi_local, moved_wo_local;
        ToLocal(mesh_normal, moved_light, mesh_wo, &moved_wi_local, &moved_wo_local);
        return model_.Eval(moved_wi_local, moved_wo_local);
      });
      value_sigma = (value_sigma.square() + jitter_sigma.square()).sqrt();
      ToLocal(normal, light_nominal, wo, &wi_local, &wo_local);
      row_samples[y].push_back({wi_local, wo_local, value, false});
      row_sigma[y].push_back(value_sigma);
    }
  });
  View view;
  for (int y = 0; y < n; ++y) {
    view.samples.insert(view.samples.end(), row_samples[y].begin(), row_samples[y].end());
    view.sigma.insert(view.sigma.end(), row_sigma[y].begin(), row_sigma[y].end());
  }
  return view;
}

void SphereAcquisition::Acquire(const Schedule& schedule, uint64_t seed,
                                const std::function<void(int64_t)>& advance,
                                Measurement* measurement) const {
  const std::vector<double> thetas = SphereLightThetas(schedule);
  GBuffer gbuffer;
  // Per sample: wi, wo, value, sigma (12 doubles); the views are split across MPI ranks.
  constexpr size_t kDoubles = 12;
  std::map<size_t, std::string> early;  // views that arrived before one they follow (rank 0)
  size_t next_view = 0;
  auto append = [&](const std::string& bytes) {
    const std::vector<double> numbers = ranks::ReadValues<double>(bytes);
    const size_t count = numbers.size() / kDoubles;
    for (size_t k = 0; k < count; ++k) {
      const double* p = &numbers[k * kDoubles];
      measurement->samples.push_back(
          {Vec3(p[0], p[1], p[2]), Vec3(p[3], p[4], p[5]), Rgb(p[6], p[7], p[8]), false});
      measurement->sigma.push_back(Rgb(p[9], p[10], p[11]));
    }
  };
  ranks::Distribute(
      ranks::RoundRobin(thetas.size()), [&]() { gbuffer = Rasterize(mesh_, camera_); },
      [&](size_t v) {
        const View view = Shade(gbuffer, 2.0 * thetas[v], seed, v);
        std::string bytes;
        bytes.reserve(view.samples.size() * kDoubles * sizeof(double));
        for (size_t k = 0; k < view.samples.size(); ++k) {
          const Sample& sample = view.samples[k];
          ranks::AppendBytes(&bytes, sample.wi.data(), 3);
          ranks::AppendBytes(&bytes, sample.wo.data(), 3);
          ranks::AppendBytes(&bytes, sample.value.data(), 3);
          ranks::AppendBytes(&bytes, view.sigma[k].data(), 3);
        }
        return bytes;
      },
      [&](size_t v, int /*rank*/, std::string&& bytes) {
        early.emplace(v, std::move(bytes));
        for (auto found = early.find(next_view); found != early.end();
             found = early.find(next_view)) {
          append(found->second);
          early.erase(found);
          ++next_view;
        }
        if (advance) advance(1);
      });
}

}  // namespace brdf::gonio
