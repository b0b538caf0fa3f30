#include "gonio/instrument.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/angles.h"
#include "core/enum_names.h"
#include "core/errors.h"
#include "core/text.h"
#include "gonio/json_fields.h"
#include "gonio/sampling.h"

namespace brdf::gonio {
namespace {

// Instrument files are a few hundred bytes; anything larger is not one.
constexpr int64_t kMaxInstrumentBytes = int64_t{1} << 20;

// The names of source.kind in an instrument file.
constexpr EnumName<Instrument::SourceKind> kSourceKindNames[] = {
    {Instrument::SourceKind::kCollimated, "collimated"},
    {Instrument::SourceKind::kPoint, "point"},
};

void Require(bool ok, const std::string& field, const std::string& range, double value) {
  if (!ok) {
    throw UsageError("instrument " + field + " must be " + range + ", got " + FormatNumber(value));
  }
}

}  // namespace

void Instrument::Validate() const {
  Require(source_angular_radius_deg >= 0 && source_angular_radius_deg <= 10,
          "source.angular_radius_deg", "in [0, 10]", source_angular_radius_deg);
  Require(source_distance_m > 0.01, "source.distance_m", "> 0.01", source_distance_m);
  Require(spot_radius_mm >= 0 && spot_radius_mm * 1e-3 < 0.2 * source_distance_m,
          "source.spot_radius_mm", "in [0, 0.2 distance)", spot_radius_mm);
  Require(lamp_power > 0 && std::isfinite(lamp_power), "source.lamp_power", "> 0", lamp_power);
  Require(detector_solid_angle_sr > 0 && detector_solid_angle_sr <= 0.5, "detector.solid_angle_sr",
          "in (0, 0.5]", detector_solid_angle_sr);
  Require(photons >= 0 && photons <= 1e15, "detector.photons", "in [0, 1e15] (0 = ideal)", photons);
  Require(read_noise >= 0 && std::isfinite(read_noise), "detector.read_noise", ">= 0", read_noise);
  Require(blocked_within_deg >= 0 && blocked_within_deg < 45, "detector.blocked_within_deg",
          "in [0, 45)", blocked_within_deg);
  Require(stray_light >= 0 && stray_light < 1, "stray_light", "in [0, 1)", stray_light);
  Require(jitter_deg >= 0 && jitter_deg <= 5, "jitter_deg", "in [0, 5]", jitter_deg);
  Require(reference_rho > 0 && reference_rho <= 1, "reference.rho", "in (0, 1]", reference_rho);
  Require(reference_theta_i_deg >= 0 && reference_theta_i_deg < 80, "reference.theta_i_deg",
          "in [0, 80)", reference_theta_i_deg);
  Require(reference_theta_o_deg >= 0 && reference_theta_o_deg < 80, "reference.theta_o_deg",
          "in [0, 80)", reference_theta_o_deg);
  Require(reference_readings >= 1 && reference_readings <= 100000, "reference.readings",
          "in [1, 100000]", reference_readings);
  Require(camera_resolution >= 8 && camera_resolution <= 8192, "camera.resolution", "in [8, 8192]",
          camera_resolution);
  Require(camera_distance >= 1.5 && camera_distance <= 1000, "camera.distance",
          "in [1.5, 1000] sphere radii", camera_distance);
  Require(camera_max_theta_deg > 0 && camera_max_theta_deg <= 90, "camera.max_theta_deg",
          "in (0, 90]", camera_max_theta_deg);
  Require(sphere_segments >= 8 && sphere_segments <= 4096, "camera.sphere_segments", "in [8, 4096]",
          sphere_segments);
}

std::string Instrument::ToJson() const {
  nlohmann::json json = {{"source",
                          {{"kind", NameOf(kSourceKindNames, source_kind)},
                           {"angular_radius_deg", source_angular_radius_deg},
                           {"distance_m", source_distance_m},
                           {"spot_radius_mm", spot_radius_mm},
                           {"lamp_power", lamp_power}}},
                         {"detector",
                          {{"solid_angle_sr", detector_solid_angle_sr},
                           {"photons", photons},
                           {"read_noise", read_noise},
                           {"blocked_within_deg", blocked_within_deg}}},
                         {"jitter_deg", jitter_deg},
                         {"stray_light", stray_light},
                         {"reference",
                          {{"rho", reference_rho},
                           {"theta_i_deg", reference_theta_i_deg},
                           {"theta_o_deg", reference_theta_o_deg},
                           {"readings", reference_readings}}},
                         {"camera",
                          {{"resolution", camera_resolution},
                           {"distance", camera_distance},
                           {"sphere_segments", sphere_segments},
                           {"max_theta_deg", camera_max_theta_deg}}}};
  return json.dump();
}

double Instrument::DetectorCosHalfAngle() const {
  return ConeCosHalfAngle(detector_solid_angle_sr);
}

double Instrument::SourceAngularRadius() const {
  if (source_kind == SourceKind::kCollimated) return DegToRad(source_angular_radius_deg);
  return std::atan(spot_radius_mm * 1e-3 / source_distance_m);
}

Vec3 Instrument::SourceDirection(const Vec3& wi, double u1, double u2, double* weight) const {
  return SourceBeam(*this, wi).Direction(u1, u2, weight);
}

SourceBeam::SourceBeam(const Instrument& instrument, const Vec3& wi)
    : instrument_(instrument),
      wi_(wi),
      frame_(Frame::FromZ(wi)),
      cos_max_(std::cos(DegToRad(instrument.source_angular_radius_deg))) {}

Vec3 SourceBeam::Direction(double u1, double u2, double* weight) const {
  Vec3 direction;
  if (instrument_.source_kind == Instrument::SourceKind::kCollimated) {
    // Each direction of the beam lights the surface with irradiance ∝ cos(theta_i').
    direction = frame_.FromLocal(SampleUniformCone(Point2(u1, u2), cos_max_));
    *weight = direction.z() > 0 ? direction.z() / wi_.z() : 0.0;
    return direction;
  }
  // Point lamp: a uniform point p of the lit spot (a disk on the sample plane) sees the lamp
  // along L - p, with irradiance cos(theta')/|L - p|² relative to the spot's centre.
  const double distance = instrument_.source_distance_m;
  const double radius = instrument_.spot_radius_mm * 1e-3 * std::sqrt(u1);
  const Vec3 point(radius * std::cos(2 * kPi * u2), radius * std::sin(2 * kPi * u2), 0.0);
  const Vec3 to_lamp = distance * wi_ - point;
  const double distance_squared = to_lamp.squaredNorm();
  direction = to_lamp / std::sqrt(distance_squared);
  *weight = direction.z() > 0 ? (direction.z() / wi_.z()) * (distance * distance / distance_squared)
                              : 0.0;
  return direction;
}

Instrument ParseInstrument(const std::string& json_text, const std::string& origin) {
  const nlohmann::json json = ParseJsonText(json_text, origin, "an instrument description");
  Instrument instrument;
  JsonFields top(json, "", origin);
  top.Object("source", [&](JsonFields& source) {
    std::string kind = NameOf(kSourceKindNames, instrument.source_kind);
    source.Text("kind", &kind);
    const std::optional<Instrument::SourceKind> source_kind = LookupEnum(kSourceKindNames, kind);
    if (!source_kind) {
      throw InputError(origin, "source.kind: unknown source kind '" + PrintableText(kind) +
                                   "' (known: " + KnownNames(kSourceKindNames) + ")");
    }
    instrument.source_kind = *source_kind;
    source.Number("angular_radius_deg", &instrument.source_angular_radius_deg);
    source.Number("distance_m", &instrument.source_distance_m);
    source.Number("spot_radius_mm", &instrument.spot_radius_mm);
    source.Number("lamp_power", &instrument.lamp_power);
  });
  top.Object("detector", [&](JsonFields& detector) {
    detector.Number("solid_angle_sr", &instrument.detector_solid_angle_sr);
    detector.Number("photons", &instrument.photons);
    detector.Number("read_noise", &instrument.read_noise);
    detector.Number("blocked_within_deg", &instrument.blocked_within_deg);
  });
  top.Number("jitter_deg", &instrument.jitter_deg);
  top.Number("stray_light", &instrument.stray_light);
  top.Object("reference", [&](JsonFields& reference) {
    reference.Number("rho", &instrument.reference_rho);
    reference.Number("theta_i_deg", &instrument.reference_theta_i_deg);
    reference.Number("theta_o_deg", &instrument.reference_theta_o_deg);
    reference.Integer("readings", &instrument.reference_readings);
  });
  top.Object("camera", [&](JsonFields& camera) {
    camera.Integer("resolution", &instrument.camera_resolution);
    camera.Number("distance", &instrument.camera_distance);
    camera.Integer("sphere_segments", &instrument.sphere_segments);
    camera.Number("max_theta_deg", &instrument.camera_max_theta_deg);
  });
  top.RejectUnknown();
  try {
    instrument.Validate();
  } catch (const UsageError& error) {
    throw InputError(origin, error.what());
  }
  return instrument;
}

Instrument ReadInstrument(const std::string& path) {
  return ParseInstrument(ReadFileBytes(path, kMaxInstrumentBytes), path);
}

}  // namespace brdf::gonio
