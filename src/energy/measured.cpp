#include "energy/measured.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/angles.h"
#include "core/errors.h"
#include "core/text.h"
#include "io/formats.h"

namespace brdf {
namespace {

// Neighbours blended by inverse-distance weighting (Shepard 1968, power 2).
constexpr int kNeighbours = 4;
// A query farther than this many typical sample spacings from every sample is a hole.
constexpr double kCoverageSpacings = 2.0;

// A direction pair reduced by the symmetries of an isotropic BRDF: rotated about the normal
// so that wo has azimuth 0, mirrored so that wi has y >= 0 (isotropic BRDFs are symmetric about
// the plane of incidence). Distance is the chordal distance of both directions together.
struct CanonicalPair {
  double theta_o = 0;  // polar angle of wo: the sort key
  Vec3 wi, wo;
};

CanonicalPair Canonical(const Vec3& wi, const Vec3& wo) {
  const double phi_o = Phi(wo);
  const double c = std::cos(-phi_o), s = std::sin(-phi_o);
  CanonicalPair pair;
  pair.wo = Vec3(c * wo.x() - s * wo.y(), 0.0, wo.z());
  pair.wi = Vec3(c * wi.x() - s * wi.y(), std::abs(s * wi.x() + c * wi.y()), wi.z());
  pair.theta_o = Theta(pair.wo);
  return pair;
}

double SquaredDistance(const CanonicalPair& a, const CanonicalPair& b) {
  return (a.wi - b.wi).squaredNorm() + (a.wo - b.wo).squaredNorm();
}

class ScatteredInterpolator {
 public:
  explicit ScatteredInterpolator(const Measurement& measurement) {
    for (const Sample& sample : measurement.samples) {
      if (sample.missing || !sample.value.allFinite()) continue;
      if (CosTheta(sample.wi) <= 0.0 || CosTheta(sample.wo) <= 0.0) continue;
      // Reciprocity (DESIGN §1): f(wi, wo) = f(wo, wi), so every sample stands for both.
      points_.push_back({Canonical(sample.wi, sample.wo), sample.value});
      points_.push_back({Canonical(sample.wo, sample.wi), sample.value});
    }
    if (points_.empty()) {
      throw InputError(measurement.source, "no usable sample (all missing or below the horizon)");
    }
    std::sort(points_.begin(), points_.end(),
              [](const Point& a, const Point& b) { return a.pair.theta_o < b.pair.theta_o; });
    // Typical spacing: the median over samples of the distance to the nearest other sample.
    std::vector<double> nearest;
    nearest.reserve(points_.size());
    for (const Point& point : points_) {
      const std::array<Neighbour, kNeighbours> found = Nearest(point.pair);
      for (const Neighbour& neighbour : found) {
        if (neighbour.squared_distance > 1e-18 && neighbour.index >= 0) {
          nearest.push_back(std::sqrt(neighbour.squared_distance));
          break;
        }
      }
    }
    if (!nearest.empty()) {
      std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
      spacing_ = nearest[nearest.size() / 2];
    }
    coverage_radius_ = kCoverageSpacings * spacing_;
  }

  BrdfSample operator()(const Vec3& wi, const Vec3& wo) const {
    const std::array<Neighbour, kNeighbours> found = Nearest(Canonical(wi, wo));
    BrdfSample result;
    result.supported = std::sqrt(found[0].squared_distance) <= coverage_radius_;
    if (found[0].squared_distance < 1e-18) {
      result.value = points_[found[0].index].value;
      return result;
    }
    double total_weight = 0;
    Rgb sum = Rgb::Zero();
    for (const Neighbour& neighbour : found) {
      if (neighbour.index < 0) continue;
      const double weight = 1.0 / neighbour.squared_distance;
      sum += weight * points_[neighbour.index].value;
      total_weight += weight;
    }
    result.value = sum / total_weight;
    return result;
  }

  double spacing() const { return spacing_; }
  double coverage_radius() const { return coverage_radius_; }
  size_t size() const { return points_.size(); }

 private:
  struct Point {
    CanonicalPair pair;
    Rgb value;
  };
  struct Neighbour {
    int64_t index = -1;
    double squared_distance = std::numeric_limits<double>::infinity();
  };

  // The k nearest points, nearest first. Points are sorted by theta_o, and two canonical wo lie
  // on one great circle, so |wo - wo'| = 2 sin(|theta_o - theta_o'| / 2) bounds the distance
  // from below: the search walks outward from the query's theta_o and stops when that bound
  // exceeds the k-th best distance.
  std::array<Neighbour, kNeighbours> Nearest(const CanonicalPair& query) const {
    std::array<Neighbour, kNeighbours> best;
    auto consider = [&](int64_t index) {
      const double squared_distance = SquaredDistance(query, points_[index].pair);
      if (squared_distance >= best[kNeighbours - 1].squared_distance) return;
      int slot = kNeighbours - 1;
      while (slot > 0 && best[slot - 1].squared_distance > squared_distance) {
        best[slot] = best[slot - 1];
        --slot;
      }
      best[slot] = {index, squared_distance};
    };
    auto lower_bound = [&](int64_t index) {
      const double chord = 2.0 * std::sin(0.5 * (points_[index].pair.theta_o - query.theta_o));
      return chord * chord;
    };
    const int64_t count = static_cast<int64_t>(points_.size());
    int64_t above = std::lower_bound(points_.begin(), points_.end(), query.theta_o,
                                     [](const Point& point, double theta_o) {
                                       return point.pair.theta_o < theta_o;
                                     }) -
                    points_.begin();
    int64_t below = above - 1;
    while (below >= 0 || above < count) {
      const double bound_below = below >= 0 ? lower_bound(below) : kInfinity;
      const double bound_above = above < count ? lower_bound(above) : kInfinity;
      if (std::min(bound_below, bound_above) >= best[kNeighbours - 1].squared_distance) break;
      if (bound_below <= bound_above) {
        consider(below--);
      } else {
        consider(above++);
      }
    }
    return best;
  }

  static constexpr double kInfinity = std::numeric_limits<double>::infinity();
  std::vector<Point> points_;
  double spacing_ = 0, coverage_radius_ = 0;
};

// Degrees to one decimal, for notes.
std::string OneDecimal(double degrees) { return FormatNumber(std::round(degrees * 10) / 10); }

}  // namespace

MeasuredBrdf MerlMeasuredBrdf(std::shared_ptr<const MerlTable> table, const std::string& source) {
  int64_t missing = 0;
  for (int64_t cell = 0; cell < MerlTable::kCells; ++cell) missing += table->raw(0, cell) < 0.0;
  MeasuredBrdf measured;
  measured.source = source;
  measured.brdf = [table](const Vec3& wi, const Vec3& wo) {
    BrdfSample sample{table->Lookup(wi, wo), true};
    sample.supported = sample.value.allFinite();
    return sample;
  };
  // MERL's grid is a half-vector grid: integrate where it is dense (theta_h), uniform in
  // cos(theta_h).
  measured.coordinates = {LobeFrame::kHalfVector, 0.0};
  measured.notes.push_back("MERL table: nearest-cell lookup (Matusik et al. 2003 grid); " +
                           std::to_string(missing) + " of " + std::to_string(MerlTable::kCells) +
                           " cells missing count as zero");
  return measured;
}

MeasuredBrdf ScatteredMeasuredBrdf(const Measurement& measurement) {
  auto interpolator = std::make_shared<const ScatteredInterpolator>(measurement);
  const MeasurementSummary summary = Summarize(measurement);
  MeasuredBrdf measured;
  measured.source = measurement.source;
  measured.brdf = [interpolator](const Vec3& wi, const Vec3& wo) {
    return (*interpolator)(wi, wo);
  };
  measured.coordinates = {LobeFrame::kHalfVector, 0.0};
  measured.notes.push_back(
      "scattered samples: inverse-distance weighting of the " + std::to_string(kNeighbours) +
      " nearest of " + std::to_string(interpolator->size()) +
      " (samples and their reciprocals, isotropy assumed); a direction farther than " +
      FormatNumber(std::round(interpolator->coverage_radius() * 1000) / 1000) +
      " (chordal, twice the median sample spacing) from every sample counts as a hole");
  measured.notes.push_back("data cover theta_i " + OneDecimal(summary.theta_i_deg[0]) + ".." +
                           OneDecimal(summary.theta_i_deg[1]) + " deg, theta_o " +
                           OneDecimal(summary.theta_o_deg[0]) + ".." +
                           OneDecimal(summary.theta_o_deg[1]) + " deg");
  return measured;
}

MeasuredBrdf LoadMeasuredBrdf(const std::string& path) {
  if (DetectFormat(path).name == "merl") {
    return MerlMeasuredBrdf(std::make_shared<const MerlTable>(MerlTable::Read(path)), path);
  }
  return ScatteredMeasuredBrdf(ReadMeasurement(path));
}

}  // namespace brdf
