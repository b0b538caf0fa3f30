#include "gonio/traced_surface.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/errors.h"
#include "core/text.h"
#include "gonio/detector_lookup.h"
#include "gonio/rng.h"
#include "gonio/sampling.h"

namespace brdf::gonio {
namespace {

constexpr int kRaysPerBatch = 4096;
// Batches traced together, sorted by where their paths enter the tile (TraceIncidence): 2^18
// paths, whose results (64 bytes each) are kept until their batches are summed.
constexpr int kBatchesPerSweep = 64;
// How many paths ahead the batch sums ask for a path's result.
constexpr int64_t kPrefetchAhead = 16;
// The sort's grid over the tile: kSortCells² cells along a Morton curve.
constexpr uint32_t kSortCells = 256;

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

}  // namespace

// One ray segment's Embree query, with the distances along the ray to the tile's sides (x, y)
// and top, where the segment ends if it hits nothing.
struct SegmentQuery {
  RTCRayHit rayhit;
  double t_x, t_y, t_top;
};

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

  // Sets up the query for the segment of the ray from `origin` that stays inside the tile:
  // Embree looks no further than the tile's side or its top.
  void Aim(const Vec3& origin, const Vec3& direction, SegmentQuery* query) const {
    const double inf = std::numeric_limits<double>::infinity();
    const Vec3& o = origin;
    query->t_x = direction.x() > 0   ? (size_ - o.x()) / direction.x()
                 : direction.x() < 0 ? -o.x() / direction.x()
                                     : inf;
    query->t_y = direction.y() > 0   ? (size_ - o.y()) / direction.y()
                 : direction.y() < 0 ? -o.y() / direction.y()
                                     : inf;
    query->t_top = direction.z() > 0 ? (top_ - o.z()) / direction.z() : inf;
    RTCRay& ray = query->rayhit.ray;
    ray.org_x = float(o.x()), ray.org_y = float(o.y()), ray.org_z = float(o.z());
    ray.dir_x = float(direction.x()), ray.dir_y = float(direction.y());
    ray.dir_z = float(direction.z());
    ray.tnear = 0.0f;
    ray.tfar = float(std::min(std::min(query->t_x, query->t_y), query->t_top));
    ray.mask = 0xffffffffu;
    ray.flags = 0;
    ray.time = 0.0f;
    query->rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  }

  // Answers `count` queries whose rays are coherent (one direction, neighbouring origins):
  // Embree traces them as packets.
  void IntersectCoherent(SegmentQuery* queries, int count) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    rtcIntersect1M(scene_, &context, &queries[0].rayhit, static_cast<unsigned>(count),
                   sizeof(SegmentQuery));
  }

  // Follows a ray through the periodic tiling. Returns true with the hit point and the unit
  // geometric normal facing the ray; false when it escaped upward (*escaped) or was lost.
  // `answered`, if given, is the first segment's query, aimed from *origin and answered.
  bool Intersect(Vec3* origin, const Vec3& direction, Vec3* normal, bool* escaped,
                 int64_t* segments, const SegmentQuery* answered = nullptr) const {
    *escaped = false;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    SegmentQuery own;
    for (int wrap = 0; wrap < kMaxWraps; ++wrap) {
      const SegmentQuery* query = answered;
      if (wrap > 0 || query == nullptr) {
        Aim(*origin, direction, &own);
        rtcIntersect1(scene_, &context, &own.rayhit);
        query = &own;
      }
      ++*segments;
      const RTCRayHit& result = query->rayhit;
      const Vec3& o = *origin;
      if (result.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
        *origin = o + double(result.ray.tfar) * direction;
        *normal = Vec3(result.hit.Ng_x, result.hit.Ng_y, result.hit.Ng_z).normalized();
        if (normal->dot(direction) > 0) *normal = -*normal;
        return true;
      }
      const double t_side = std::min(query->t_x, query->t_y);
      if (query->t_top <= t_side) {
        *escaped = true;
        return false;
      }
      Vec3 next = o + t_side * direction;
      if (next.z() < bottom_) return false;  // slipped through a seam: lost
      if (query->t_x <= t_side) next.x() = direction.x() > 0 ? 0.0 : size_;
      if (query->t_y <= t_side) next.y() = direction.y() > 0 ? 0.0 : size_;
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

namespace {

// What one path delivered, kept until its batch is summed in ray order. One cache line each:
// the sums read them out of trace order, and a result straddling two lines cost two misses.
struct alignas(64) PathResult {
  Vec3 direction = Vec3::Zero();  // the escape direction
  Rgb power = Rgb::Zero();        // the throughput that escaped (0 if the path did not)
  double incident = 0;            // the source weight of the ray
  int32_t segments = 0;
  bool escaped = false, cut = false;
};

// A path between its first segment and the rest.
struct PathState {
  Rng rng;
  Vec3 origin, direction;
  Rgb throughput;
  double weight = 0;
};

// The paths of one incidence. Path `ray` draws every number from its own stream, derived from
// (incidence, ray): neither the thread nor the order in which paths are traced shows.
class PathTracer {
 public:
  PathTracer(const EmbreeHeightField& scene, const FacetMaterial& material, int bounces,
             const Instrument& instrument, const Vec3& wi, uint64_t incidence_seed)
      : scene_(scene),
        material_(material),
        bounces_(bounces),
        source_(instrument, wi),
        incidence_seed_(incidence_seed) {}

  // The first numbers of path `ray`: two for its source direction, then its entry point
  // (x, y) in units of the tile.
  Rng StartRng(int64_t ray, Point2* source, Point2* entry) const {
    Rng rng = StreamRng(incidence_seed_, Stream::kRayPath, static_cast<uint64_t>(ray));
    // Separate statements: argument evaluation order is unspecified, and the output must not
    // depend on the compiler.
    source->x() = rng.Uniform();
    source->y() = rng.Uniform();
    entry->x() = rng.Uniform();
    entry->y() = rng.Uniform();
    return rng;
  }

  // Draws the source ray of path `ray`; false if the source gives it no weight.
  bool Start(int64_t ray, PathState* state, PathResult* result) const {
    Point2 source, entry;
    state->rng = StartRng(ray, &source, &entry);
    const Vec3 wi_source = source_.Direction(source.x(), source.y(), &state->weight);
    result->incident = state->weight;
    if (state->weight <= 0) return false;
    state->origin = Vec3(entry.x() * scene_.size(), entry.y() * scene_.size(), scene_.top());
    state->direction = -wi_source;
    state->throughput = Rgb::Constant(state->weight);
    return true;
  }

  // Follows a started path to its end; `first` is its first segment's answered query.
  void Finish(PathState* state, const SegmentQuery* first, PathResult* result) const {
    Vec3& origin = state->origin;
    Vec3& direction = state->direction;
    Rgb& throughput = state->throughput;
    Rng& rng = state->rng;
    int64_t segments = 0;
    for (int bounce = 0;; ++bounce) {
      Vec3 normal;
      bool escaped = false;
      if (!scene_.Intersect(&origin, direction, &normal, &escaped, &segments,
                            bounce == 0 ? first : nullptr)) {
        if (escaped) {
          result->escaped = true;
          result->power = throughput;
          result->direction = direction;
        }
        break;
      }
      if (bounce == bounces_) {
        result->cut = true;
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
        const double survival = std::min(1.0, throughput.maxCoeff() / state->weight);
        if (survival <= 0 || rng.Uniform() >= survival) break;
        throughput /= survival;
      }
    }
    result->segments = static_cast<int32_t>(segments);
  }

  // Traces the paths ray_begin + order[j] for j in [0, count) into results[j], a group small
  // enough that their first segments, which start close together in one direction, go to
  // Embree as one stream.
  void TraceGroup(int64_t ray_begin, const uint32_t* order, int count, PathResult* results) const {
    PathState states[kGroup];
    SegmentQuery queries[kGroup];
    int live[kGroup];
    int started = 0;
    for (int j = 0; j < count; ++j) {
      PathResult& result = results[j];
      result = PathResult();
      if (!Start(ray_begin + order[j], &states[j], &result)) continue;
      scene_.Aim(states[j].origin, states[j].direction, &queries[started]);
      live[started++] = j;
    }
    if (started > 0) scene_.IntersectCoherent(queries, started);
    for (int m = 0; m < started; ++m) {
      const int j = live[m];
      Finish(&states[j], &queries[m], &results[j]);
    }
  }

  // One Embree packet on an AVX-512 machine, two on AVX2.
  static constexpr int kGroup = 16;

 private:
  const EmbreeHeightField& scene_;
  const FacetMaterial& material_;
  int bounces_;
  const SourceBeam source_;  // the instrument's source about wi
  uint64_t incidence_seed_;
};

}  // namespace

TracedSurfaceSample::Trace TracedSurfaceSample::TraceIncidence(
    const Instrument& instrument, const Vec3& wi, const std::vector<Vec3>& detectors, uint64_t seed,
    uint64_t incidence_index, int64_t rays) const {
  const DetectorLookup lookup(detectors, instrument.DetectorCosHalfAngle());
  const int64_t batches = (rays + kRaysPerBatch - 1) / kRaysPerBatch;
  std::vector<Trace> partial(batches);
  const uint64_t incidence_seed = StreamRng(seed, Stream::kRayBatch, incidence_index).Bits();
  const PathTracer tracer(*scene_, material_, spec_.bounces, instrument, wi, incidence_seed);
  // The paths are traced in sweeps of whole batches, each sweep in the order of its entry
  // points along a Morton curve over the tile: neighbouring paths then walk the same part of
  // the BVH, which stays in cache. In random order nearly every query missed the cache.
  std::vector<PathResult> results;
  std::vector<uint32_t> keys, order, position, bucket_start;  // position[order[j]] = j
  for (int64_t first_batch = 0; first_batch < batches; first_batch += kBatchesPerSweep) {
    const int64_t last_batch = std::min(batches, first_batch + kBatchesPerSweep);
    const int64_t first = first_batch * kRaysPerBatch;
    const int64_t count = std::min(rays, last_batch * kRaysPerBatch) - first;
    keys.resize(count);
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, count, 4096),
                      [&](const tbb::blocked_range<int64_t>& range) {
                        for (int64_t i = range.begin(); i < range.end(); ++i) {
                          Point2 source, entry;
                          tracer.StartRng(first + i, &source, &entry);
                          keys[i] = MortonKey(static_cast<uint32_t>(entry.x() * kSortCells),
                                              static_cast<uint32_t>(entry.y() * kSortCells));
                        }
                      });
    // Counting sort by key: stable, so paths of one cell keep their index order.
    bucket_start.assign(size_t(kSortCells) * kSortCells + 1, 0);
    for (uint32_t key : keys) ++bucket_start[key + 1];
    for (size_t k = 1; k < bucket_start.size(); ++k) bucket_start[k] += bucket_start[k - 1];
    order.resize(count);
    position.resize(count);
    for (int64_t i = 0; i < count; ++i) {
      position[i] = bucket_start[keys[i]]++;
      order[position[i]] = static_cast<uint32_t>(i);
    }
    results.resize(count);
    // Fixed groups of the sorted order, whatever the thread count: which paths share a stream
    // does not depend on the threads either.
    const int64_t groups = (count + PathTracer::kGroup - 1) / PathTracer::kGroup;
    tbb::parallel_for(
        tbb::blocked_range<int64_t>(0, groups, 4), [&](const tbb::blocked_range<int64_t>& range) {
          for (int64_t g = range.begin(); g < range.end(); ++g) {
            const int64_t j = g * PathTracer::kGroup;
            tracer.TraceGroup(first, order.data() + j,
                              static_cast<int>(std::min<int64_t>(PathTracer::kGroup, count - j)),
                              results.data() + j);
          }
        });
    // Each batch sums its paths in ray order, as if they had been traced one after another.
    tbb::parallel_for(first_batch, last_batch, [&](int64_t b) {
      Trace& trace = partial[b];
      trace.detector_power.assign(detectors.size(), Rgb::Zero());
      const int64_t begin = b * kRaysPerBatch - first;
      const int64_t end = std::min(count, begin + kRaysPerBatch);
      for (int64_t i = begin; i < end; ++i) {
        // The results lie in trace order, so these reads jump: ask for one well ahead.
        if (i + kPrefetchAhead < end) __builtin_prefetch(&results[position[i + kPrefetchAhead]]);
        const PathResult& path = results[position[i]];
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
