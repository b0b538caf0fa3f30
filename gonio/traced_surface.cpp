#include "gonio/traced_surface.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/errors.h"
#include "core/text.h"
#include "gonio/rng.h"
#include "gonio/sampling.h"

namespace brdf::gonio {
namespace {

constexpr int kRaysPerBatch = 4096;
// Batches traced together, sorted by where their paths enter the tile (TraceIncidence).
constexpr int kBatchesPerSweep = 64;
// The sort's grid over the tile: kSortCells² cells along a Morton curve.
constexpr uint32_t kSortCells = 128;

// Interleaves the bits of x and y (each below 2^16): the Z-order index of cell (x, y).
uint32_t MortonKey(uint32_t x, uint32_t y) {
  const auto spread = [](uint32_t v) {
    v = (v | (v << 8)) & 0x00ff00ffu;
    v = (v | (v << 4)) & 0x0f0f0f0fu;
    v = (v | (v << 2)) & 0x33333333u;
    return (v | (v << 1)) & 0x55555555u;
  };
  return spread(x) | (spread(y) << 1);
}
// Lateral wraps before a path is abandoned: only a ray almost parallel to the mean surface
// crosses this many tiles, and its weight is lost either way.
constexpr int kMaxWraps = 256;
// Russian roulette starts after this many bounces (Arvo & Kirk 1990).
constexpr int kRouletteAfter = 3;

// Detector cones indexed by 1° cells of (theta, phi) so that an escaping ray is compared with
// the few detectors that can contain it, not with all of them. The cells' lists are stored one
// after another (offsets into one array), so a look-up touches two cache lines, not a
// separately allocated list per cell.
class DetectorLookup {
 public:
  DetectorLookup(const std::vector<Vec3>& detectors, double cos_half_angle)
      : detectors_(detectors), cos_half_angle_(cos_half_angle) {
    std::vector<std::vector<int>> cells(kThetaCells * kPhiCells);
    const double radius = std::acos(cos_half_angle);
    for (size_t k = 0; k < detectors.size(); ++k) {
      const double theta = Theta(detectors[k]), phi = Phi(detectors[k]);
      const int theta_low = std::max(0, CellTheta(theta - radius) - 1);
      const int theta_high = std::min(kThetaCells - 1, CellTheta(theta + radius) + 1);
      const double sin_low = std::sin(std::max(theta - radius, 0.0));
      const bool all_phi = theta - radius <= DegToRad(1) || radius / sin_low >= kPi;
      const double phi_radius =
          all_phi ? kPi : std::asin(std::min(1.0, std::sin(radius) / sin_low));
      const int phi_span = static_cast<int>(std::ceil(RadToDeg(phi_radius))) + 1;
      const int first = all_phi ? 0 : CellPhi(phi) - phi_span;
      const int last = all_phi ? kPhiCells - 1 : CellPhi(phi) + phi_span;
      for (int t = theta_low; t <= theta_high; ++t) {
        for (int p = first; p <= last; ++p) {
          cells[t * kPhiCells + ((p % kPhiCells) + kPhiCells) % kPhiCells].push_back(int(k));
        }
      }
    }
    offsets_.reserve(cells.size() + 1);
    offsets_.push_back(0);
    for (auto& cell : cells) {  // a detector may have been added twice through phi wrap
      std::sort(cell.begin(), cell.end());
      cell.erase(std::unique(cell.begin(), cell.end()), cell.end());
      members_.insert(members_.end(), cell.begin(), cell.end());
      offsets_.push_back(static_cast<uint32_t>(members_.size()));
    }
  }

  template <typename Visit>
  void ForEachContaining(const Vec3& w, Visit&& visit) const {
    const int cell = CellTheta(Theta(w)) * kPhiCells + CellPhi(Phi(w));
    for (uint32_t m = offsets_[cell]; m < offsets_[cell + 1]; ++m) {
      const int k = members_[m];
      if (w.dot(detectors_[k]) >= cos_half_angle_) visit(k);
    }
  }

 private:
  static constexpr int kThetaCells = 90, kPhiCells = 360;
  static int CellTheta(double theta) {
    return std::clamp(static_cast<int>(std::floor(RadToDeg(theta))), 0, kThetaCells - 1);
  }
  static int CellPhi(double phi) {
    const int cell = static_cast<int>(std::floor(RadToDeg(phi)));
    return ((cell % kPhiCells) + kPhiCells) % kPhiCells;
  }

  const std::vector<Vec3>& detectors_;
  double cos_half_angle_;
  std::vector<uint32_t> offsets_;  // cell c holds members_[offsets_[c] .. offsets_[c + 1])
  std::vector<int> members_;
};

}  // namespace

// The Embree device and scene of one height field (Embree 3 API).
class EmbreeHeightField {
 public:
  explicit EmbreeHeightField(const HeightField& field) : size_(field.resolution) {
    device_ = rtcNewDevice(nullptr);
    if (device_ == nullptr) throw ComputeError("Embree: cannot create a device");
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    const int n = field.resolution;
    RTCGeometry mesh = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    // (n+1)² vertices: the last row and column repeat the first, so the tile is seamless.
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), size_t(n + 1) * (n + 1)));
    auto* triangles = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), size_t(2) * n * n));
    if (vertices == nullptr || triangles == nullptr) throw ComputeError("Embree: out of memory");
    for (int y = 0; y <= n; ++y) {
      for (int x = 0; x <= n; ++x) {
        float* v = vertices + 3 * (size_t(y) * (n + 1) + x);
        v[0] = float(x), v[1] = float(y), v[2] = field.At(x, y);
      }
    }
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        const unsigned a = y * (n + 1) + x, b = a + 1, c = a + (n + 1), d = c + 1;
        unsigned* t = triangles + 6 * (size_t(y) * n + x);
        t[0] = a, t[1] = b, t[2] = d;  // counter-clockwise seen from above: normals point up
        t[3] = a, t[4] = d, t[5] = c;
      }
    }
    rtcCommitGeometry(mesh);
    rtcAttachGeometry(scene_, mesh);
    rtcReleaseGeometry(mesh);
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE)
      throw ComputeError("Embree: scene build failed");
    top_ = field.MaxHeight() + 1e-3f;
    bottom_ = field.MinHeight() - 1.0f;
  }
  ~EmbreeHeightField() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeHeightField(const EmbreeHeightField&) = delete;
  EmbreeHeightField& operator=(const EmbreeHeightField&) = delete;

  double top() const { return top_; }
  double size() const { return size_; }

  // Follows a ray through the periodic tiling. Returns true with the hit point and the unit
  // geometric normal facing the ray; false when it escaped upward (*escaped) or was lost.
  bool Intersect(Vec3* origin, const Vec3& direction, Vec3* normal, bool* escaped,
                 int64_t* segments) const {
    *escaped = false;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    const double inf = std::numeric_limits<double>::infinity();
    for (int wrap = 0; wrap < kMaxWraps; ++wrap) {
      const Vec3& o = *origin;
      const double t_x = direction.x() > 0   ? (size_ - o.x()) / direction.x()
                         : direction.x() < 0 ? -o.x() / direction.x()
                                             : inf;
      const double t_y = direction.y() > 0   ? (size_ - o.y()) / direction.y()
                         : direction.y() < 0 ? -o.y() / direction.y()
                                             : inf;
      const double t_top = direction.z() > 0 ? (top_ - o.z()) / direction.z() : inf;
      const double t_side = std::min(t_x, t_y);
      RTCRayHit query;
      query.ray.org_x = float(o.x()), query.ray.org_y = float(o.y()),
      query.ray.org_z = float(o.z());
      query.ray.dir_x = float(direction.x()), query.ray.dir_y = float(direction.y());
      query.ray.dir_z = float(direction.z());
      query.ray.tnear = 0.0f;
      query.ray.tfar = float(std::min(t_side, t_top));
      query.ray.mask = 0xffffffffu;
      query.ray.flags = 0;
      query.ray.time = 0.0f;
      query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene_, &context, &query);
      ++*segments;
      if (query.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
        *origin = o + double(query.ray.tfar) * direction;
        *normal = Vec3(query.hit.Ng_x, query.hit.Ng_y, query.hit.Ng_z).normalized();
        if (normal->dot(direction) > 0) *normal = -*normal;
        return true;
      }
      if (t_top <= t_side) {
        *escaped = true;
        return false;
      }
      Vec3 next = o + t_side * direction;
      if (next.z() < bottom_) return false;  // slipped through a seam: lost
      if (t_x <= t_side) next.x() = direction.x() > 0 ? 0.0 : size_;
      if (t_y <= t_side) next.y() = direction.y() > 0 ? 0.0 : size_;
      *origin = next;
    }
    return false;
  }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  double size_;
  double top_ = 0, bottom_ = 0;
};

TracedSurfaceSample::TracedSurfaceSample(HeightField field, FacetMaterial material,
                                         const SurfaceSpec& spec)
    : field_(std::move(field)),
      material_(std::move(material)),
      spec_(spec),
      scene_(std::make_unique<EmbreeHeightField>(field_)) {}

TracedSurfaceSample::~TracedSurfaceSample() = default;

std::string TracedSurfaceSample::Modelled() const {
  return "height field " + spec_.heightfield.kind + " " + std::to_string(field_.resolution) + "x" +
         std::to_string(field_.resolution) + " (rms slope " + FormatNumber(field_.RmsSlope()) +
         ") of " + material_.ToString() + " facets, ray traced with Embree (BVH of " +
         std::to_string(2 * int64_t(field_.resolution) * field_.resolution) +
         " triangles), up to " + std::to_string(spec_.bounces) +
         " bounces with Russian roulette, " + std::to_string(spec_.rays_per_incidence) +
         " rays per incidence; masking, shadowing and interreflection traced; sigma includes "
         "the Monte Carlo standard error";
}

// What one path delivered, kept until its batch is summed in ray order.
struct TracedSurfaceSample::PathResult {
  Vec3 direction = Vec3::Zero();  // the escape direction
  Rgb power = Rgb::Zero();        // the throughput that escaped (0 if the path did not)
  double incident = 0;            // the source weight of the ray
  int32_t segments = 0;
  bool escaped = false, cut = false;
};

TracedSurfaceSample::PathResult TracedSurfaceSample::TracePath(const Instrument& instrument,
                                                               const Vec3& wi,
                                                               uint64_t incidence_seed,
                                                               int64_t ray) const {
  PathResult result;
  Rng rng(incidence_seed, Stream::kRayPath, static_cast<uint64_t>(ray));
  double weight = 0;
  const double u1 = rng.Uniform(), u2 = rng.Uniform();
  const Vec3 wi_source = instrument.SourceDirection(wi, u1, u2, &weight);
  result.incident = weight;
  if (weight <= 0) return result;
  const double tile = scene_->size();
  // Separate statements: argument evaluation order is unspecified, and the output must not
  // depend on the compiler.
  const double x = rng.Uniform() * tile;
  const double y = rng.Uniform() * tile;
  Vec3 origin(x, y, scene_->top());
  Vec3 direction = -wi_source;
  Rgb throughput = Rgb::Constant(weight);
  int64_t segments = 0;
  for (int bounce = 0;; ++bounce) {
    Vec3 normal;
    bool escaped = false;
    if (!scene_->Intersect(&origin, direction, &normal, &escaped, &segments)) {
      if (escaped) {
        result.escaped = true;
        result.power = throughput;
        result.direction = direction;
      }
      break;
    }
    if (bounce == spec_.bounces) {
      result.cut = true;
      break;
    }
    const Frame facet = Frame::FromZ(normal);
    const double s0 = rng.Uniform();
    const double s1 = rng.Uniform();
    const Vec3 wo_local = material_.Scatter(facet.ToLocal(-direction), s0, s1, &throughput);
    if (wo_local.z() <= 0) break;
    direction = facet.FromLocal(wo_local).normalized();
    origin += 1e-4 * normal;  // step off the facet so the next ray does not hit it again
    if (bounce + 1 >= kRouletteAfter) {
      const double survival = std::min(1.0, throughput.maxCoeff() / weight);
      if (survival <= 0 || rng.Uniform() >= survival) break;
      throughput /= survival;
    }
  }
  result.segments = static_cast<int32_t>(segments);
  return result;
}

TracedSurfaceSample::Trace TracedSurfaceSample::TraceIncidence(
    const Instrument& instrument, const Vec3& wi, const std::vector<Vec3>& detectors, uint64_t seed,
    uint64_t incidence_index, int64_t rays) const {
  const DetectorLookup lookup(detectors, instrument.DetectorCosHalfAngle());
  const int64_t batches = (rays + kRaysPerBatch - 1) / kRaysPerBatch;
  std::vector<Trace> partial(batches);
  // Every path has its own random stream, derived from (incidence, ray index): neither the
  // thread nor the order in which paths are traced shows in the result.
  const uint64_t incidence_seed = Rng(seed, Stream::kRayBatch, incidence_index).NextU64();
  // The paths are traced in sweeps of whole batches, each sweep in the order of its entry
  // points along a Morton curve over the tile: neighbouring paths then walk the same part of
  // the BVH, which stays in cache. In random order nearly every query missed the cache.
  std::vector<PathResult> results;
  std::vector<uint32_t> keys, order, bucket_start;
  for (int64_t first_batch = 0; first_batch < batches; first_batch += kBatchesPerSweep) {
    const int64_t last_batch = std::min(batches, first_batch + kBatchesPerSweep);
    const int64_t first = first_batch * kRaysPerBatch;
    const int64_t count = std::min(rays, last_batch * kRaysPerBatch) - first;
    keys.resize(count);
    tbb::parallel_for(int64_t{0}, count, int64_t{4096}, [&](int64_t begin) {
      const int64_t end = std::min(count, begin + 4096);
      for (int64_t i = begin; i < end; ++i) {
        Rng rng(incidence_seed, Stream::kRayPath, static_cast<uint64_t>(first + i));
        rng.Uniform();  // the source direction's two numbers
        rng.Uniform();
        const double x = rng.Uniform();
        const double y = rng.Uniform();
        keys[i] = MortonKey(static_cast<uint32_t>(x * kSortCells),
                            static_cast<uint32_t>(y * kSortCells));
      }
    });
    // Counting sort by key: stable, so paths of one cell keep their index order.
    bucket_start.assign(size_t(kSortCells) * kSortCells + 1, 0);
    for (uint32_t key : keys) ++bucket_start[key + 1];
    for (size_t k = 1; k < bucket_start.size(); ++k) bucket_start[k] += bucket_start[k - 1];
    order.resize(count);
    for (int64_t i = 0; i < count; ++i) order[bucket_start[keys[i]]++] = static_cast<uint32_t>(i);
    results.resize(count);
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, count, 256),
                      [&](const tbb::blocked_range<int64_t>& range) {
                        for (int64_t j = range.begin(); j < range.end(); ++j) {
                          const int64_t i = order[j];
                          results[i] = TracePath(instrument, wi, incidence_seed, first + i);
                        }
                      });
    // Each batch sums its paths in ray order, as if they had been traced one after another.
    tbb::parallel_for(first_batch, last_batch, [&](int64_t b) {
      Trace& trace = partial[b];
      trace.detector_power.assign(detectors.size(), Rgb::Zero());
      const int64_t begin = b * kRaysPerBatch - first;
      const int64_t end = std::min(count, begin + kRaysPerBatch);
      for (int64_t i = begin; i < end; ++i) {
        const PathResult& path = results[i];
        trace.incident += path.incident;
        trace.segments += path.segments;
        trace.paths_cut += path.cut;
        if (!path.escaped) continue;
        trace.reflected += path.power;
        ++trace.escaped;
        lookup.ForEachContaining(path.direction,
                                 [&](int k) { trace.detector_power[k] += path.power; });
      }
    });
  }
  // Sum in batch order: the result does not depend on which thread ran which batch.
  Trace total;
  total.detector_power.assign(detectors.size(), Rgb::Zero());
  for (const Trace& trace : partial) {
    for (size_t k = 0; k < detectors.size(); ++k)
      total.detector_power[k] += trace.detector_power[k];
    total.reflected += trace.reflected;
    total.escaped += trace.escaped;
    total.incident += trace.incident;
    total.segments += trace.segments;
    total.paths_cut += trace.paths_cut;
  }
  // Monte Carlo standard error of each detector's power, from the spread of the batches'
  // fractions x_b = power_b / incident_b about the pooled fraction: the batches are independent,
  // so the pooled estimate's variance is about var(x_b) / B (in units of total incident power).
  //
  // The spread says nothing about a detector that few paths reached: with no hit at all it is
  // exactly 0, and a reading of zero with no uncertainty is a certainty the tracer does not
  // have. So one escaped path of the mean escaping weight is added to every detector's variance
  // (the Poisson "n + 1" rule for a count n): a detector no path reached reads 0 ± one path,
  // one with many hits is unchanged to 1/(2 hits). Without it a fit weighted by sigma treats
  // the empty detectors around a lobe as exact zeros and narrows the lobe (a Beckmann fit of a
  // Gaussian surface of rms slope 0.3 gave alpha 0.18; docs/gonio.md).
  const Rgb one_path =
      total.escaped > 0 ? Rgb(total.reflected / double(total.escaped)) : Rgb(Rgb::Zero());
  total.detector_power_standard_error.assign(detectors.size(), Rgb::Zero());
  for (size_t k = 0; k < detectors.size(); ++k) {
    Rgb variance = one_path.square();
    if (batches > 1) {
      const Rgb pooled = total.detector_power[k] / total.incident;
      Rgb sum_squares = Rgb::Zero();
      for (const Trace& trace : partial) {
        if (trace.incident <= 0) continue;
        sum_squares += (trace.detector_power[k] / trace.incident - pooled).square();
      }
      variance +=
          sum_squares / double(batches - 1) / double(batches) * total.incident * total.incident;
    }
    total.detector_power_standard_error[k] = variance.sqrt();
  }
  return total;
}

Readings TracedSurfaceSample::Measure(const Instrument& instrument, const Vec3& wi,
                                      const std::vector<Vec3>& detectors, uint64_t seed,
                                      uint64_t incidence_index) const {
  const Trace trace =
      TraceIncidence(instrument, wi, detectors, seed, incidence_index, spec_.rays_per_incidence);
  Readings readings;
  const double scale = 1.0 / (trace.incident * instrument.detector_solid_angle_sr);
  for (size_t k = 0; k < detectors.size(); ++k) {
    readings.value.push_back(trace.detector_power[k] * scale);
    readings.standard_error.push_back(trace.detector_power_standard_error[k] * scale);
  }
  return readings;
}

}  // namespace brdf::gonio
