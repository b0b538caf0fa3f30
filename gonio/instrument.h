// The simulated instrument of DESIGN §5: source, detector, positioning, detector noise, stray
// light and the Lambertian reference it is calibrated against. Every field has a default, so
// `{}` is a valid instrument file; ReadInstrument validates a JSON file and names the file and
// the field in every error.
//
// Signal chain of one reading (docs/gonio.md has the figure):
//   R      = (1/Ω) ∫_detector f(wi', wo) cos(theta_o) dwo, averaged over the source's directions
//            wi' — the power reaching the detector per unit incident power and steradian;
//   counts = Poisson(photons · lamp_power · (R + stray_light · R_norm) / R_norm) + N(0,
//   read_noise²)
//            with R_norm = (rho_ref/π) cos(theta_o,ref) the ideal reference reading;
//   f      = counts / counts_ref · R_norm / cos(theta_o),
// where counts_ref is the mean of `reference.readings` readings of the Lambertian reference at
// the reference geometry. Lamp power and detector gain cancel in the ratio, as on a real
// gonioreflectometer; photons = 0 is an ideal detector (no shot or read noise).
#pragma once

#include <string>
#include <vector>

#include "core/sampling.h"
#include "core/vec.h"

namespace brdf::gonio {

struct Instrument {
  enum class SourceKind { kCollimated, kPoint };

  // Source. Collimated: a beam whose directions fill a cone of `source_angular_radius_deg`.
  // Point: a lamp at `source_distance_m` lighting a spot of `spot_radius_mm`, so the incidence
  // direction and irradiance (cos/r²) vary across the spot.
  SourceKind source_kind = SourceKind::kCollimated;
  double source_angular_radius_deg = 0.25;
  double source_distance_m = 1.0;
  double spot_radius_mm = 5.0;
  double lamp_power = 1.0;  // relative; calibration removes it

  // Detector: a circular aperture of this solid angle (1e-3 sr is a cone of 1.03° half-angle).
  double detector_solid_angle_sr = 1e-3;
  // Counts the detector would register from the reference at the reference geometry
  // (the photon budget: shot noise is sqrt(counts)); 0 = ideal detector.
  double photons = 1e6;
  double read_noise = 10.0;  // counts, one standard deviation, per reading
  // Light scattered inside the instrument, as a fraction of the reference reading, added to
  // every reading (sample and reference) and not removed by calibration.
  double stray_light = 0.0;
  // The detector arm shadows the beam: geometries with wi and wo closer than this are skipped.
  double blocked_within_deg = 2.0;
  // Positioning jitter (one standard deviation) of the light arm (once per incidence) and of
  // the detector arm (per reading).
  double jitter_deg = 0.05;

  // Lambertian reference (Spectralon-like) measured with the same instrument.
  double reference_rho = 0.99;
  double reference_theta_i_deg = 0.0;
  double reference_theta_o_deg = 45.0;
  int reference_readings = 64;

  // Camera of the image-based (sphere) acquisition: square image, distance from the sphere's
  // centre in sphere radii, triangle mesh resolution (segments around the equator).
  int camera_resolution = 128;
  double camera_distance = 10.0;
  int sphere_segments = 256;
  // Pixels seeing the sphere at theta_i or theta_o above this are dropped: near the silhouette
  // and the terminator one pixel spans many degrees, as in MERL's acquisition.
  double camera_max_theta_deg = 80.0;

  // Throws UsageError naming the field when a value is out of range.
  void Validate() const;
  // Compact JSON with every field (for the metadata of a measurement).
  std::string ToJson() const;

  double DetectorCosHalfAngle() const;
  // Angular radius (radians) of the cone of incidence directions the source produces.
  double SourceAngularRadius() const;
  // A direction of incidence and its relative irradiance weight for a point (u1, u2) of the
  // unit square: a direction of the collimated beam's cone, or the direction from a point of
  // the lit spot to the point lamp. The weights average to about 1 over the square.
  Vec3 SourceDirection(const Vec3& wi, double u1, double u2, double* weight) const;
};

// The source's directions about one nominal incidence wi: Instrument::SourceDirection with what
// depends on wi alone (its frame, the beam's cone) worked out once, for the many draws of one
// incidence.
class SourceBeam {
 public:
  SourceBeam(const Instrument& instrument, const Vec3& wi);
  // Instrument::SourceDirection(wi, u1, u2, weight), the same value.
  Vec3 Direction(double u1, double u2, double* weight) const;

 private:
  const Instrument& instrument_;
  Vec3 wi_;
  Frame frame_;     // about wi
  double cos_max_;  // of the collimated beam's cone
};

// Reads an instrument JSON file; absent fields keep their defaults. Throws InputError naming
// the file (and byte offset for malformed JSON, the field for bad values or unknown keys).
Instrument ReadInstrument(const std::string& path);
// The same from JSON text; `origin` names it in errors.
Instrument ParseInstrument(const std::string& json_text, const std::string& origin);

}  // namespace brdf::gonio
