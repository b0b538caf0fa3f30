#include "gonio/schedule.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>

#include "core/angles.h"
#include "core/errors.h"
#include "core/text.h"
#include "gonio/sampling.h"
#include "io/merl.h"

namespace brdf::gonio {
namespace {

[[noreturn]] void Fail(const std::string& spec, const std::string& what) {
  throw UsageError("schedule '" + spec + "': " + what);
}

// key=value options after the kind; only `allowed` keys, each a positive number.
std::map<std::string, double> ParseOptions(const std::string& spec,
                                           const std::vector<std::string>& allowed) {
  std::map<std::string, double> options;
  size_t start = spec.find(':');
  while (start != std::string::npos) {
    const size_t end = spec.find(':', start + 1);
    const std::string part =
        spec.substr(start + 1, end == std::string::npos ? end : end - start - 1);
    const size_t equals = part.find('=');
    if (equals == std::string::npos) Fail(spec, "expected key=value, found '" + part + "'");
    const std::string key = part.substr(0, equals);
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string list;
      for (const std::string& name : allowed) list += (list.empty() ? "" : ", ") + name;
      Fail(spec, "unknown option '" + key + "' (known: " + (list.empty() ? "none" : list) + ")");
    }
    const std::string text = part.substr(equals + 1);
    double value = 0;
    const auto [end_ptr, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end_ptr != text.data() + text.size() || !(value > 0)) {
      Fail(spec, "option '" + key + "' needs a positive number, found '" + text + "'");
    }
    if (!options.emplace(key, value).second) Fail(spec, "option '" + key + "' given twice");
    start = end;
  }
  return options;
}

double Option(const std::map<std::string, double>& options, const char* key, double fallback) {
  const auto found = options.find(key);
  return found == options.end() ? fallback : found->second;
}

// Polar angles 0, step, 2 step, ... below 90° (radians).
std::vector<double> PolarSteps(const std::string& spec, double step_deg) {
  if (step_deg < 0.1 || step_deg > 45) Fail(spec, "steps must lie in [0.1, 45] degrees");
  std::vector<double> thetas;
  for (int k = 0; k * step_deg < 90.0 - 1e-9; ++k) thetas.push_back(DegToRad(k * step_deg));
  return thetas;
}

Vec3 Direction(double theta, double phi) { return SphericalDirection(theta, phi); }

Schedule InPlane(const std::string& spec) {
  const auto options = ParseOptions(spec, {"step"});
  const std::vector<double> thetas = PolarSteps(spec, Option(options, "step", 5));
  Schedule schedule;
  for (double theta_i : thetas) {
    Incidence incidence{Direction(theta_i, 0), {}};
    // The plane of incidence: the backward side (phi_o = 0, toward the light) and the forward
    // side (phi_o = 180°, where the mirror direction lies).
    for (auto it = thetas.rbegin(); it != thetas.rend(); ++it) {
      if (*it > 0) incidence.detectors.push_back({Direction(*it, 0), 0});
    }
    for (double theta_o : thetas) incidence.detectors.push_back({Direction(theta_o, kPi), 0});
    schedule.incidences.push_back(std::move(incidence));
  }
  return schedule;
}

Schedule Hemisphere(const std::string& spec) {
  const auto options = ParseOptions(spec, {"theta_i_step", "theta_o_step", "phi_o_step"});
  const std::vector<double> thetas_i = PolarSteps(spec, Option(options, "theta_i_step", 5));
  const std::vector<double> thetas_o = PolarSteps(spec, Option(options, "theta_o_step", 5));
  const double phi_step = Option(options, "phi_o_step", 5);
  if (phi_step < 0.1 || phi_step > 180) Fail(spec, "phi_o_step must lie in [0.1, 180] degrees");
  Schedule schedule;
  for (double theta_i : thetas_i) {
    Incidence incidence{Direction(theta_i, 0), {}};
    for (double theta_o : thetas_o) {
      if (theta_o == 0) {  // the pole is one direction, whatever phi
        incidence.detectors.push_back({Direction(0, 0), 0});
        continue;
      }
      for (int k = 0; k * phi_step < 360.0 - 1e-9; ++k) {
        incidence.detectors.push_back({Direction(theta_o, DegToRad(k * phi_step)), 0});
      }
    }
    schedule.incidences.push_back(std::move(incidence));
  }
  return schedule;
}

Schedule Merl(const std::string& spec) {
  ParseOptions(spec, {});
  Schedule schedule;
  schedule.fixed_grid = true;
  for (int h = 0; h < MerlTable::kThetaHalfBins; ++h) {
    for (int d = 0; d < MerlTable::kThetaDiffBins; ++d) {
      for (int p = 0; p < MerlTable::kPhiDiffBins; ++p) {
        Vec3 wi, wo;
        FromHalfDiff(MerlTable::CellCentre(h, d, p), &wi, &wo);
        if (wi.z() <= 0 || wo.z() <= 0) continue;  // cell centre below the horizon
        schedule.incidences.push_back({wi, {{wo, 0}}});
      }
    }
  }
  return schedule;
}

Schedule EqualArea(const std::string& spec) {
  const auto options = ParseOptions(spec, {"cells", "theta_i_step"});
  const double cells = Option(options, "cells", 0);
  if (cells < 1 || cells > 1e6 || cells != std::floor(cells)) {
    Fail(spec, "needs cells=N, a whole number in [1, 1000000]");
  }
  const std::vector<Vec3> centres = EqualAreaCells(static_cast<int>(cells));
  const double cell_solid_angle = 2 * kPi / cells;
  Schedule schedule;
  schedule.has_weight = true;
  for (double theta_i : PolarSteps(spec, Option(options, "theta_i_step", 5))) {
    Incidence incidence{Direction(theta_i, 0), {}};
    for (const Vec3& wo : centres) incidence.detectors.push_back({wo, cell_solid_angle});
    schedule.incidences.push_back(std::move(incidence));
  }
  return schedule;
}

// Offsets (degrees) from the mirror direction of the rings added by `adaptive`: geometric, so
// that a lobe of any width from ~1° to tens of degrees is sampled by a few rings.
constexpr double kAdaptiveRingsDeg[] = {0.5, 1, 2, 4, 8, 16};
constexpr int kAdaptiveRingPoints = 12;

Schedule Adaptive(const std::string& spec) {
  const auto options = ParseOptions(spec, {"theta_i_step", "base_step"});
  const std::vector<double> thetas_i = PolarSteps(spec, Option(options, "theta_i_step", 5));
  const double base_step = Option(options, "base_step", 10);
  Schedule schedule;
  const std::vector<double> thetas_o = PolarSteps(spec, base_step);
  for (double theta_i : thetas_i) {
    Incidence incidence{Direction(theta_i, 0), {}};
    for (double theta_o : thetas_o) {
      const int azimuths = theta_o == 0 ? 1 : static_cast<int>(std::ceil(360.0 / base_step - 1e-9));
      for (int k = 0; k < azimuths; ++k) {
        incidence.detectors.push_back({Direction(theta_o, 2 * kPi * k / azimuths), 0});
      }
    }
    const Vec3 mirror = MirrorDirection(incidence.wi);
    incidence.detectors.push_back({mirror, 0});
    const Frame frame = Frame::FromZ(mirror);
    for (double ring_deg : kAdaptiveRingsDeg) {
      const double ring = DegToRad(ring_deg);
      for (int k = 0; k < kAdaptiveRingPoints; ++k) {
        const double phi = 2 * kPi * k / kAdaptiveRingPoints;
        const Vec3 wo = frame.FromLocal(
            Vec3(std::sin(ring) * std::cos(phi), std::sin(ring) * std::sin(phi), std::cos(ring)));
        if (wo.z() > std::cos(DegToRad(89.5))) incidence.detectors.push_back({wo, 0});
      }
    }
    schedule.incidences.push_back(std::move(incidence));
  }
  return schedule;
}

Schedule Uniform(const std::string& spec) {
  const auto options = ParseOptions(spec, {"count", "theta_max"});
  const double count = Option(options, "count", 0);
  if (count < 1 || count > 1e7 || count != std::floor(count)) {
    Fail(spec, "needs count=N, a whole number in [1, 10000000]");
  }
  const double theta_max = Option(options, "theta_max", kUniformThetaMaxDeg);
  if (theta_max > 89.9) Fail(spec, "theta_max must lie in (0, 89.9] degrees");
  Schedule schedule;
  for (const auto& [wi, wo] : UniformPairs(static_cast<int>(count), theta_max)) {
    if (schedule.incidences.empty() || schedule.incidences.back().wi != wi) {
      schedule.incidences.push_back({wi, {}});
    }
    schedule.incidences.back().detectors.push_back({wo, 0});
  }
  return schedule;
}

// A CSV of direction pairs: optional '#' lines, a header naming theta_i, phi_i, theta_o and
// phi_o (any order, other columns ignored), one geometry a row. Rows with the same incidence
// form one incidence, in the order of their first row.
Schedule FromFile(const std::string& spec) {
  const std::string path = spec.substr(5);
  if (path.empty()) Fail(spec, "expected file:PATH (a CSV with theta_i,phi_i,theta_o,phi_o)");
  const std::string text = ReadFileBytes(path, int64_t{1} << 30);
  LineReader reader(path, text);
  std::string_view line;
  constexpr const char* kNames[] = {"theta_i", "phi_i", "theta_o", "phi_o"};
  int column[4] = {-1, -1, -1, -1};
  size_t fields = 0;
  bool header = false;
  Schedule schedule;
  std::map<std::pair<double, double>, size_t> incidence_of;
  while (reader.Next(&line)) {
    const std::string_view trimmed = Trim(line);
    if (trimmed.empty() || (!header && trimmed[0] == '#')) continue;
    const std::vector<std::string_view> parts = SplitFields(trimmed, ",", false);
    if (!header) {
      for (size_t k = 0; k < parts.size(); ++k) {
        for (int name = 0; name < 4; ++name) {
          if (Trim(parts[k]) != kNames[name]) continue;
          if (column[name] >= 0) reader.Fail(std::string("column '") + kNames[name] + "' twice");
          column[name] = static_cast<int>(k);
        }
      }
      for (int name = 0; name < 4; ++name) {
        if (column[name] < 0) {
          reader.Fail(std::string("the header has no column '") + kNames[name] +
                      "' (a schedule file needs theta_i,phi_i,theta_o,phi_o in degrees)");
        }
      }
      fields = parts.size();
      header = true;
      continue;
    }
    if (parts.size() != fields) {
      reader.Fail("expected " + std::to_string(fields) + " fields as in the header, found " +
                  std::to_string(parts.size()));
    }
    double angle[4];
    for (int name = 0; name < 4; ++name) {
      angle[name] = ParseNumber(reader, Trim(parts[column[name]]), kNames[name]);
    }
    for (int name : {0, 2}) {
      if (!(angle[name] >= 0 && angle[name] < 90)) {
        reader.Fail(std::string(kNames[name]) + " must lie in [0, 90) degrees, found " +
                    FormatNumber(angle[name]));
      }
    }
    const Vec3 wi = Direction(DegToRad(angle[0]), DegToRad(angle[1]));
    const Vec3 wo = Direction(DegToRad(angle[2]), DegToRad(angle[3]));
    const auto [found, added] =
        incidence_of.emplace(std::make_pair(angle[0], angle[1]), schedule.incidences.size());
    if (added) schedule.incidences.push_back({wi, {}});
    schedule.incidences[found->second].detectors.push_back({wo, 0});
  }
  if (!header) throw InputError(path, "no header line theta_i,phi_i,theta_o,phi_o");
  if (schedule.incidences.empty()) throw InputError(path, "no geometries after the header");
  schedule.designed = true;
  return schedule;
}

}  // namespace

std::vector<std::pair<Vec3, Vec3>> UniformPairs(int count, double theta_max_deg) {
  // Incidences: about the cube root of the count (at least one, at most one per degree), at the
  // mid-points of equal-cos(theta) slices of [0, theta_max], so they too cover solid angle
  // evenly. Detectors: the first cells of an equal-solid-angle partition of the hemisphere
  // (EqualAreaCells orders them from the pole outward), sized so the cap holds them.
  std::vector<std::pair<Vec3, Vec3>> pairs;
  const double cos_max = std::cos(DegToRad(theta_max_deg));
  const int incidences = std::clamp(static_cast<int>(std::lround(std::cbrt(count))), 1,
                                    std::min(count, std::max(1, static_cast<int>(theta_max_deg))));
  for (int g = 0; g < incidences; ++g) {
    const int detectors = count / incidences + (g < count % incidences ? 1 : 0);
    const double cos_i = 1.0 - (1.0 - cos_max) * (g + 0.5) / incidences;
    const Vec3 wi = SphericalDirection(std::acos(cos_i), 0.0);
    const int cells = static_cast<int>(std::ceil(detectors / (1.0 - cos_max)));
    const std::vector<Vec3> centres = EqualAreaCells(std::max(cells, detectors));
    for (int k = 0; k < detectors; ++k) pairs.emplace_back(wi, centres[k]);
  }
  return pairs;
}

size_t Schedule::CountGeometries() const {
  size_t count = 0;
  for (const Incidence& incidence : incidences) count += incidence.detectors.size();
  return count;
}

std::vector<double> Schedule::IncidenceThetas() const {
  std::vector<double> thetas;
  for (const Incidence& incidence : incidences) thetas.push_back(Theta(incidence.wi));
  std::sort(thetas.begin(), thetas.end());
  thetas.erase(std::unique(thetas.begin(), thetas.end(),
                           [](double a, double b) { return std::abs(a - b) < 1e-9; }),
               thetas.end());
  return thetas;
}

std::vector<Vec3> EqualAreaCells(int cells) {
  // Every cell spans 2π/N sr; a cap of that solid angle has 1 − cos(theta) = 1/N. Rings then
  // get a height of about one cell width (√(2π/N) radians) and as many cells as their area
  // holds; boundaries are then moved so each ring holds exactly its cells' area
  // (1 − cos(theta_k) = cumulative cells / N), which makes every cell's solid angle exact.
  std::vector<Vec3> centres;
  if (cells == 1) return {Vec3(0, 0, 1)};
  const double cell_width = std::sqrt(2 * kPi / cells);
  const double cap_theta = std::acos(1.0 - 1.0 / cells);
  const int rings = std::max(1, static_cast<int>(std::lround((kPi / 2 - cap_theta) / cell_width)));
  // Cumulative counts rounded at the ideal (equally spaced) ring boundaries; the differences
  // sum to exactly N cells.
  std::vector<int> ring_cells(rings);
  int previous = 1;
  for (int k = 0; k < rings; ++k) {
    const double upper = cap_theta + (kPi / 2 - cap_theta) * (k + 1) / rings;
    const int cumulative =
        k + 1 == rings
            ? cells
            : std::max(previous, static_cast<int>(std::lround((1.0 - std::cos(upper)) * cells)));
    ring_cells[k] = cumulative - previous;
    previous = cumulative;
  }
  centres.push_back(Vec3(0, 0, 1));
  int cumulative = 1;
  for (int k = 0; k < rings; ++k) {
    const double cos_lower = 1.0 - static_cast<double>(cumulative) / cells;
    cumulative += ring_cells[k];
    const double cos_upper = std::max(0.0, 1.0 - static_cast<double>(cumulative) / cells);
    const double theta = std::acos(0.5 * (cos_lower + cos_upper));  // mid-area polar angle
    for (int j = 0; j < ring_cells[k]; ++j) {                       // an empty ring adds nothing
      centres.push_back(SphericalDirection(theta, 2 * kPi * (j + 0.5) / ring_cells[k]));
    }
  }
  return centres;
}

Schedule MakeSchedule(const std::string& spec) {
  const std::string kind = spec.substr(0, spec.find(':'));
  Schedule schedule;
  if (kind == "inplane") {
    schedule = InPlane(spec);
  } else if (kind == "hemisphere") {
    schedule = Hemisphere(spec);
  } else if (kind == "merl") {
    schedule = Merl(spec);
  } else if (kind == "equal-area") {
    schedule = EqualArea(spec);
  } else if (kind == "adaptive") {
    schedule = Adaptive(spec);
  } else if (kind == "uniform") {
    schedule = Uniform(spec);
  } else if (kind == "file") {
    schedule = FromFile(spec);
  } else {
    Fail(spec,
         "unknown kind (known: inplane, hemisphere, merl, equal-area, adaptive, uniform, "
         "file:PATH)");
  }
  schedule.spec = spec;
  schedule.kind = kind;
  return schedule;
}

}  // namespace brdf::gonio
