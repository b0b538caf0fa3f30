#include "energy/measured.h"

#include <tbb/parallel_for.h>

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
  double theta_o = 0, theta_i = 0;  // polar angles: the search index's keys
  Vec3 wi, wo;
};

CanonicalPair Canonical(const Vec3& wi, const Vec3& wo) {
  const double phi_o = Phi(wo);
  const double c = std::cos(-phi_o), s = std::sin(-phi_o);
  CanonicalPair pair;
  pair.wo = Vec3(c * wo.x() - s * wo.y(), 0.0, wo.z());
  pair.wi = Vec3(c * wi.x() - s * wi.y(), std::abs(s * wi.x() + c * wi.y()), wi.z());
  pair.theta_o = Theta(pair.wo);
  pair.theta_i = Theta(pair.wi);
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
    for (size_t index = 0; index < points_.size(); ++index) {
      const CanonicalPair& pair = points_[index].pair;
      cells_[CellIndex(BinOf(pair.theta_o), BinOf(pair.theta_i))].push_back(index);
    }
    // Typical spacing: the median over samples of the distance to the nearest other sample.
    // Searched in parallel, gathered in order (-1: no other sample).
    std::vector<double> distances(points_.size(), -1.0);
    tbb::parallel_for(size_t{0}, points_.size(), [&](size_t index) {
      const std::array<Neighbour, kNeighbours> found = Nearest(points_[index].pair);
      for (const Neighbour& neighbour : found) {
        if (neighbour.squared_distance > 1e-18 && neighbour.index >= 0) {
          distances[index] = std::sqrt(neighbour.squared_distance);
          break;
        }
      }
    });
    std::vector<double> nearest;
    nearest.reserve(points_.size());
    for (double distance : distances) {
      if (distance >= 0.0) nearest.push_back(distance);
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

  // The search index: cells of kBinWidth x kBinWidth in (theta_o, theta_i). For unit vectors
  // |a - b| >= 2 sin(|theta_a - theta_b| / 2), so a cell's gap in both polar angles bounds the
  // distance of everything in it from below.
  static constexpr int kBins = 45;
  static constexpr double kBinWidth = 0.5 * kPi / kBins;
  static int BinOf(double theta) {
    return std::clamp(static_cast<int>(theta / kBinWidth), 0, kBins - 1);
  }
  static int CellIndex(int bin_o, int bin_i) { return bin_o * kBins + bin_i; }
  // A lower bound on the squared chord (2 sin(angle / 2))^2 of an angle in [0, pi]: the sine's
  // series alternates with falling terms there, so 2 sin(x / 2) >= x - x^3 / 24 (within
  // 0.3 % of it below pi / 2). Cheaper than the sine, which made up half the cost of
  // tabulating the interpolant; the search skips a cell only when even this bound is too far,
  // so it finds the same neighbours.
  static double SquaredChord(double angle) {
    const double x = std::max(0.0, angle);
    const double chord = x - x * x * x * (1.0 / 24.0);
    return chord * chord;
  }
  // Distance from theta to the bin's interval of polar angles.
  static double GapToBin(double theta, int bin) {
    return std::max({0.0, bin * kBinWidth - theta, theta - (bin + 1) * kBinWidth});
  }

  // The k nearest points, nearest first: cells visited in square rings around the query's
  // cell, until the ring's lower bound exceeds the k-th best distance.
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
    const int query_o = BinOf(query.theta_o), query_i = BinOf(query.theta_i);
    for (int ring = 0; ring < kBins; ++ring) {
      // Every cell of this ring is at least ring - 1 whole bins away in one of the angles.
      if (SquaredChord((ring - 1) * kBinWidth) >= best[kNeighbours - 1].squared_distance) break;
      for (int bin_o = query_o - ring; bin_o <= query_o + ring; ++bin_o) {
        if (bin_o < 0 || bin_o >= kBins) continue;
        const bool edge_row = bin_o == query_o - ring || bin_o == query_o + ring;
        const int step = edge_row ? 1 : 2 * ring;  // inner rows: only the two end cells
        for (int bin_i = query_i - ring; bin_i <= query_i + ring; bin_i += std::max(step, 1)) {
          if (bin_i < 0 || bin_i >= kBins) continue;
          const double bound = SquaredChord(GapToBin(query.theta_o, bin_o)) +
                               SquaredChord(GapToBin(query.theta_i, bin_i));
          if (bound >= best[kNeighbours - 1].squared_distance) continue;
          for (int64_t index : cells_[CellIndex(bin_o, bin_i)]) consider(index);
        }
      }
    }
    return best;
  }

  std::vector<Point> points_;
  std::vector<std::vector<int64_t>> cells_ = std::vector<std::vector<int64_t>>(kBins * kBins);
  double spacing_ = 0, coverage_radius_ = 0;
};

// The largest polar angle of a present sample's wi, and of its wo when `reciprocal`; 90 when the
// reader kept no samples in memory (a table's sample source), whose table then spans the
// hemisphere.
double LargestIncidenceDeg(const Measurement& measurement, bool reciprocal) {
  if (measurement.samples.empty()) return 90.0;
  double largest = 0;
  for (const Sample& sample : measurement.samples) {
    if (sample.missing) continue;
    largest = std::max(largest, Theta(sample.wi));
    if (reciprocal) largest = std::max(largest, Theta(sample.wo));
  }
  return RadToDeg(largest);
}

// Degrees to one decimal, for notes.
std::string OneDecimal(double degrees) { return FormatNumber(std::round(degrees * 10) / 10); }

}  // namespace

MeasuredBrdf TabulatedMeasuredBrdf(std::shared_ptr<const TabulatedBrdf> tabulated,
                                   const std::string& source) {
  MeasuredBrdf measured;
  measured.source = source;
  measured.brdf = [tabulated](const Vec3& wi, const Vec3& wo) {
    BrdfSample sample{tabulated->Eval(wi, wo), true};
    sample.supported = sample.value.allFinite();
    return sample;
  };
  // Dense tables (MERL's half-vector grid, RGL's warp about the half vector) are densest where
  // the lobe is: integrate in the half vector, uniform in cos(theta_h).
  measured.coordinates = {kHalfVectorFrame, 0.0};
  measured.notes.insert(measured.notes.begin(), tabulated->Describe());
  return measured;
}

MeasuredBrdf MerlMeasuredBrdf(std::shared_ptr<const MerlTable> table, const std::string& source) {
  return TabulatedMeasuredBrdf(MerlTabulated(std::move(table)), source);
}

MeasuredBrdf ScatteredMeasuredBrdf(const Measurement& measurement) {
  auto interpolator = std::make_shared<const ScatteredInterpolator>(measurement);
  const MeasurementSummary summary = Summarize(measurement);
  MeasuredBrdf measured;
  measured.source = measurement.source;
  measured.brdf = [interpolator](const Vec3& wi, const Vec3& wo) {
    return (*interpolator)(wi, wo);
  };
  measured.coordinates = {kHalfVectorFrame, 0.0};
  measured.largest_incidence_deg = LargestIncidenceDeg(measurement, /*reciprocal=*/true);
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

MeasuredBrdf MeasuredBrdfOf(const Measurement& measurement) {
  if (measurement.tabulated != nullptr) {
    MeasuredBrdf measured = TabulatedMeasuredBrdf(measurement.tabulated, measurement.source);
    measured.largest_incidence_deg = LargestIncidenceDeg(measurement, /*reciprocal=*/false);
    return measured;
  }
  return ScatteredMeasuredBrdf(measurement);
}

MeasuredBrdf LoadMeasuredBrdf(const std::string& path) {
  return MeasuredBrdfOf(ReadMeasurement(path));
}

}  // namespace brdf
