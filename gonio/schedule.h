// Measurement schedules (DESIGN §5): which (incidence, detector) geometries the instrument
// visits, grouped by incidence because a goniometer sets the light arm once and sweeps the
// detector. Spec strings (angles in degrees):
//   inplane[:step=D]                                       (default step 5)
//   hemisphere[:theta_i_step=D:theta_o_step=D:phi_o_step=D] (the default schedule, all 5)
//   merl                                                    (MERL half/difference cell centres)
//   equal-area:cells=N[:theta_i_step=D]                     (N detector cells of equal solid
//                                                            angle, weight = cell solid angle)
//   adaptive[:theta_i_step=D:base_step=D]                   (a coarse hemisphere plus rings of
//                                                            detectors around the mirror direction)
//   uniform:count=N[:theta_max=D]                           (N geometries spread evenly over
//                                                            incidence and detector solid angle,
//                                                            theta up to D, default 85)
//   file:PATH                                               (the geometries of a CSV whose header
//                                                            names theta_i,phi_i,theta_o,phi_o, in
//                                                            degrees; other columns ignored;
//                                                            '#' lines before the header skipped)
// Polar angles run from 0 in steps up to but not including 90°; phi_i = 0.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/vec.h"

namespace brdf::gonio {

struct Detector {
  Vec3 wo;              // nominal direction, unit
  double weight = 0.0;  // solid angle the reading stands for (sr), 0 when not meaningful
};

struct Incidence {
  Vec3 wi;  // nominal direction, unit
  std::vector<Detector> detectors;
};

struct Schedule {
  std::string spec;  // as given, for the metadata
  std::string kind;  // "inplane", "hemisphere", "merl", "equal-area", "adaptive", "uniform", "file"
  bool has_weight = false;  // detectors carry solid-angle weights (equal-area)
  // The geometries were chosen one by one (file:, e.g. a plan): each reading stands for itself,
  // not for a patch of the hemisphere, so a fit weighs them equally (by their sigma only).
  bool designed = false;
  // The readings lie on a fixed grid of cells (the MERL half/difference grid), the one a
  // fixed-grid format (FileFormat::fixed_grid, MERL .binary) holds.
  bool fixed_grid = false;
  std::vector<Incidence> incidences;

  size_t CountGeometries() const;
  // Distinct polar angles of incidence, ascending (the sphere acquisition's light positions).
  std::vector<double> IncidenceThetas() const;
};

// The largest polar angle of the default schedule (hemisphere, 5 deg steps): 85 deg.
inline constexpr double kUniformThetaMaxDeg = 85.0;

// Parses a spec and builds its geometries. Throws UsageError naming the spec and what is wrong.
Schedule MakeSchedule(const std::string& spec);

// Cell centres of an equal-solid-angle partition of the hemisphere into `cells` cells: a polar
// cap and rings whose cell counts keep cells roughly square; every cell spans 2π/cells sr.
std::vector<Vec3> EqualAreaCells(int cells);

// `count` (wi, wo) pairs spread evenly over incidence and detector solid angle with both polar
// angles at most `theta_max_deg` (the `uniform` schedule; phi_i = 0), grouped by incidence.
std::vector<std::pair<Vec3, Vec3>> UniformPairs(int count, double theta_max_deg);

}  // namespace brdf::gonio
