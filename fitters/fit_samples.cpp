#include "fitters/fit_samples.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <tuple>

#include "core/angles.h"
#include "core/colour.h"
#include "core/enum_names.h"
#include "core/errors.h"
#include "core/rng.h"
#include "fitters/image_error.h"
#include "io/merl.h"

namespace brdf::fitters {
namespace {

constexpr int kNearestNeighbours = 4;
// Larger incidence groups would make the O(n^2) neighbour search slow; they keep equal weights
// (and the report says so).
constexpr size_t kMaxNeighbourGroup = 4096;
// Measurement samples per chunk of PrepareSamples' parallel selection.
constexpr size_t kPrepareChunk = 16384;

// Samples written from a MERL table into another format (native CSV keeps the "grid"
// metadata); a measurement read with its table asks the table instead (Measurement::tabulated).
// Area of the detector directions nearest each sample of one incidence group, from the
// distance r_k to its k-th nearest neighbour: area ~ pi r_k^2 / k.
void NeighbourAreas(const std::vector<const Vec3*>& directions, std::vector<double>* areas) {
  const size_t n = directions.size();
  areas->assign(n, 1.0);
  if (n <= kNearestNeighbours || n > kMaxNeighbourGroup) return;
  std::vector<double> distances(n);
  for (size_t a = 0; a < n; ++a) {
    for (size_t b = 0; b < n; ++b) {
      distances[b] = std::acos(std::clamp(directions[a]->dot(*directions[b]), -1.0, 1.0));
    }
    // distances[a] = 0 is the sample itself: the k-th neighbour is element k.
    std::nth_element(distances.begin(), distances.begin() + kNearestNeighbours, distances.end());
    const double r = distances[kNearestNeighbours];
    (*areas)[a] = kPi * r * r / kNearestNeighbours;
  }
  // Coincident samples (e.g. Zemax's radial 0 repeated for every azimuth) share their area.
  double smallest = 0;
  for (double area : *areas) {
    if (area > 0 && (smallest == 0 || area < smallest)) smallest = area;
  }
  for (double& area : *areas) area = std::max(area, 0.1 * smallest);
}

}  // namespace

constexpr EnumName<Loss> kLossNames[] = {
    {Loss::kL2, "l2"},     {Loss::kLog, "log"},     {Loss::kCosineL2, "cosine-l2"},
    {Loss::kSqrt, "sqrt"}, {Loss::kImage, "image"}, {Loss::kAuto, "auto"},
};

Loss ParseLoss(const std::string& name) { return ParseEnum(kLossNames, name, "loss"); }

const char* LossName(Loss loss) { return NameOf(kLossNames, loss); }

void Release(PreparedSamples* prepared) {
  prepared->samples = std::vector<FitSample>();
  prepared->sigma = std::vector<Rgb>();
}

Loss ResolveLoss(Loss loss, const Measurement& measurement) {
  const bool renderable = measurement.tabulated != nullptr;
  if (loss == Loss::kAuto) {
    if (renderable) return Loss::kImage;
    return measurement.has_sigma() ? Loss::kL2 : Loss::kSqrt;
  }
  if (loss == Loss::kImage && !renderable) {
    throw InputError(measurement.source,
                     "the image loss fits rendered spheres of the measurement, and these data "
                     "have no evaluator to render them (only table formats such as MERL and "
                     "RGL-EPFL have); use the sqrt loss, its counterpart on the samples");
  }
  return loss;
}

PreparedSamples PrepareSamples(const Measurement& measurement, Loss loss) {
  if (loss == Loss::kImage) {
    PreparedSamples prepared = PrepareSamples(ImageLossSamples(measurement));
    prepared.weighting = ImageLossWeighting();
    prepared.designed = false;  // equal weights, but the pixels tile the spheres
    return prepared;
  }
  PreparedSamples prepared;
  const auto recorded = measurement.metadata.find(kInstrumentKey);
  if (recorded != measurement.metadata.end()) {
    prepared.instrument = std::make_shared<const gonio::Instrument>(gonio::ParseInstrument(
        recorded->second, measurement.source + " (metadata " + kInstrumentKey + ")"));
  }
  // The usable samples, in file order, copied in parallel: each chunk of the measurement counts
  // its usable ones, the running sum of the counts places each chunk's copies, and the vector is
  // sized once (growing a vector of a million samples by doubling would hold the old and the new
  // copy at once).
  const std::vector<Sample>& source = measurement.samples;
  const size_t chunks = (source.size() + kPrepareChunk - 1) / kPrepareChunk;
  const auto chunk_range = [&](size_t chunk) {
    return std::pair(chunk * kPrepareChunk, std::min(source.size(), (chunk + 1) * kPrepareChunk));
  };
  std::vector<size_t> first_usable(chunks + 1, 0), missing(chunks, 0);
  tbb::parallel_for(size_t{0}, chunks, [&](size_t chunk) {
    const auto [begin, end] = chunk_range(chunk);
    for (size_t k = begin; k < end; ++k) {
      first_usable[chunk + 1] += UsableForFit(source[k]);
      missing[chunk] += source[k].missing;
    }
  });
  std::partial_sum(first_usable.begin(), first_usable.end(), first_usable.begin());
  const size_t count = first_usable[chunks];
  prepared.skipped_missing = std::accumulate(missing.begin(), missing.end(), size_t{0});
  prepared.skipped_invalid = source.size() - count - prepared.skipped_missing;
  prepared.samples.resize(count);
  // Solid-angle weights from a table's cells (or from the cells of a MERL table's samples
  // written by another format) are taken in the same pass as the copies.
  std::shared_ptr<const CellMeasure> cells = measurement.cell_measure;
  if (cells == nullptr && !measurement.equal_weighting() && OnMerlGrid(source)) {
    cells = MerlCellMeasure();
  }
  const bool per_sample_columns = measurement.has_weight() || measurement.has_sigma();
  std::vector<size_t> source_index(per_sample_columns ? count : 0);
  tbb::parallel_for(size_t{0}, chunks, [&](size_t chunk) {
    const auto [begin, end] = chunk_range(chunk);
    size_t u = first_usable[chunk];
    for (size_t k = begin; k < end; ++k) {
      if (!UsableForFit(source[k])) continue;
      FitSample& fit_sample = prepared.samples[u];
      fit_sample.wi = source[k].wi;
      fit_sample.wo = source[k].wo;
      fit_sample.value = source[k].value;
      if (cells != nullptr) fit_sample.weight = cells->Measure(fit_sample.wi, fit_sample.wo);
      if (per_sample_columns) source_index[u] = k;
      ++u;
    }
  });
  std::vector<FitSample>& samples = prepared.samples;
  if (samples.empty()) {
    throw InputError(measurement.source, "no usable samples to fit (all missing or invalid)");
  }

  // Solid-angle weights (those of a table's cells are in place already).
  if (cells != nullptr) {
    prepared.weighting = cells->Name();
  } else if (measurement.equal_weighting()) {
    prepared.weighting = "equal (a designed schedule: each sample stands for itself)";
    prepared.designed = true;
  } else {
    std::map<std::tuple<long long, long long, long long>, std::vector<size_t>> groups;
    for (size_t k = 0; k < samples.size(); ++k) {
      const Vec3& wi = samples[k].wi;
      groups[{std::llround(wi.x() * 1e6), std::llround(wi.y() * 1e6), std::llround(wi.z() * 1e6)}]
          .push_back(k);
    }
    bool capped = false;
    for (const auto& [key, members] : groups) {
      std::vector<const Vec3*> directions;
      for (size_t k : members) directions.push_back(&samples[k].wo);
      std::vector<double> areas;
      NeighbourAreas(directions, &areas);
      capped = capped || members.size() > kMaxNeighbourGroup;
      for (size_t m = 0; m < members.size(); ++m) samples[members[m]].weight = areas[m];
    }
    prepared.weighting = "nearest-neighbour area per incidence direction (k = 4)";
    if (capped) prepared.weighting += "; groups over 4096 samples weighted equally";
  }
  if (measurement.has_weight()) {
    for (size_t k = 0; k < samples.size(); ++k) {
      samples[k].weight *= measurement.weight[source_index[k]];
    }
    prepared.weighting += ", times the file's weight column";
  }
  const double total =
      std::accumulate(samples.begin(), samples.end(), 0.0,
                      [](double sum, const FitSample& s) { return sum + s.weight; });
  if (!(total > 0)) throw InputError(measurement.source, "all sample weights are zero");
  const double normalization = samples.size() / total;

  // Sigma reweights samples relative to one another (a sample twice as noisy counts a quarter
  // as much); its absolute scale does not matter because standard errors come from the
  // residuals themselves (fit.cpp).
  Rgb mean_sigma = Rgb::Ones();
  if (measurement.has_sigma()) {
    prepared.sigma.resize(samples.size());
    Rgb sum = Rgb::Zero();
    for (size_t u = 0; u < samples.size(); ++u) {
      prepared.sigma[u] = measurement.sigma[source_index[u]];
      sum += prepared.sigma[u].square();
    }
    mean_sigma = (sum / static_cast<double>(source_index.size())).sqrt();
  }
  tbb::parallel_for(size_t{0}, samples.size(), [&](size_t k) {
    FitSample& sample = samples[k];
    sample.weight *= normalization;
    sample.scale = Rgb::Constant(std::sqrt(sample.weight));
    if (measurement.has_sigma()) {
      const Rgb& sigma = prepared.sigma[k];
      for (int c = 0; c < 3; ++c) {
        if (sigma[c] > 0 && mean_sigma[c] > 0) sample.scale[c] *= mean_sigma[c] / sigma[c];
      }
    }
  });
  return prepared;
}

VarianceFunction FitVarianceFunction(const PreparedSamples& prepared) {
  VarianceFunction variance;
  const std::vector<FitSample>& samples = prepared.samples;
  for (int c = 0; c < 3; ++c) {
    // Normal equations of the rows [1, x, x^2] / sigma^2 against 1.
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d right = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < samples.size(); ++k) {
      const double sigma = prepared.sigma[k][c];
      if (!(sigma > 0) || !std::isfinite(sigma)) continue;
      const double x = std::max(samples[k].value[c], 0.0), s2 = sigma * sigma;
      const Eigen::Vector3d row(1 / s2, x / s2, x * x / s2);
      normal += row * row.transpose();
      right += row;
    }
    // The best of the non-negative solutions on every subset of the three terms (at most 7
    // small solves): the cost 1 - 2 r.t + t^T N t up to a constant.
    Eigen::Vector3d best = Eigen::Vector3d::Zero();
    double best_cost = 0;
    for (int subset = 1; subset < 8; ++subset) {
      std::vector<int> terms;
      for (int t = 0; t < 3; ++t) {
        if (subset & (1 << t)) terms.push_back(t);
      }
      const int m = static_cast<int>(terms.size());
      Eigen::MatrixXd sub(m, m);
      Eigen::VectorXd sub_right(m);
      for (int i = 0; i < m; ++i) {
        sub_right[i] = right[terms[i]];
        for (int j = 0; j < m; ++j) sub(i, j) = normal(terms[i], terms[j]);
      }
      const Eigen::VectorXd solution = sub.ldlt().solve(sub_right);
      if (!solution.allFinite() || (solution.array() < 0).any()) continue;
      Eigen::Vector3d t = Eigen::Vector3d::Zero();
      for (int i = 0; i < m; ++i) t[terms[i]] = solution[i];
      const double cost = t.dot(normal * t) - 2 * t.dot(right);
      if (cost < best_cost) {
        best_cost = cost;
        best = t;
      }
    }
    variance.a[c] = best[0];
    variance.b[c] = best[1];
    variance.c[c] = best[2];
  }
  return variance;
}

namespace {

// The share lambda of channel c (fit_samples.h: VarianceFunction).
double FollowedShare(const std::vector<Rgb>& stated, const VarianceFunction& variance,
                     const std::vector<FitSample>& samples, const std::vector<Rgb>& predicted,
                     int c) {
  // Least squares of y = sigma^2 - v(prediction) on x = v(value) - v(prediction), each pair
  // weighted by 1 / sigma^4 (relative errors), through the origin.
  double xy = 0, xx = 0;
  for (size_t k = 0; k < samples.size(); ++k) {
    const double sigma = stated[k][c];
    if (!(sigma > 0) || !std::isfinite(sigma)) continue;
    const double model = variance.At(predicted[k])[c];
    const double x = variance.At(samples[k].value)[c] - model;
    const double y = sigma * sigma - model, w = 1 / std::pow(sigma, 4);
    xy += w * x * y;
    xx += w * x * x;
  }
  return xx > 0 ? std::clamp(xy / xx, 0.0, 1.0) : 0.0;
}

}  // namespace

std::vector<FitSample> ModelWeighted(const std::vector<FitSample>& samples,
                                     const std::vector<Rgb>& stated,
                                     const VarianceFunction& variance,
                                     const std::vector<Rgb>& predicted, Rgb* followed) {
  Rgb share;
  for (int c = 0; c < 3; ++c) share[c] = FollowedShare(stated, variance, samples, predicted, c);
  if (followed != nullptr) *followed = share;
  std::vector<FitSample> weighted = samples;
  tbb::parallel_for(size_t{0}, samples.size(), [&](size_t k) {
    const Rgb reading = variance.At(samples[k].value), model = variance.At(predicted[k]);
    for (int c = 0; c < 3; ++c) {
      const double sigma = stated[k][c];
      if (!(sigma > 0) || !std::isfinite(sigma)) continue;
      // At least a tenth of the stated variance: a prediction near zero where the reading is
      // not must not give one sample all the weight.
      const double variance_k =
          std::max(sigma * sigma - share[c] * (reading[c] - model[c]), 0.01 * sigma * sigma);
      weighted[k].scale[c] *= sigma / std::sqrt(variance_k);
    }
  });
  return weighted;
}

std::vector<int> IncidenceGroups(const std::vector<FitSample>& samples, int* count) {
  std::map<std::tuple<double, double, double>, int> group_of;
  std::vector<int> groups(samples.size());
  for (size_t k = 0; k < samples.size(); ++k) {
    const Vec3& wi = samples[k].wi;
    const int next = static_cast<int>(group_of.size());
    groups[k] = group_of.try_emplace(std::make_tuple(wi.x(), wi.y(), wi.z()), next).first->second;
  }
  *count = static_cast<int>(group_of.size());
  return groups;
}

std::vector<FitSample> Subsample(const std::vector<FitSample>& samples, size_t max_samples,
                                 uint64_t seed) {
  if (max_samples == 0 || samples.size() <= max_samples) return samples;
  // 32-bit indices, and the luminance taken where it is compared rather than stored: this runs
  // while all the samples are held, at the fit's peak of memory, where 8-byte indices and a
  // stored luminance would add 16 bytes a sample.
  if (samples.size() > std::numeric_limits<uint32_t>::max()) {
    throw ComputeError("Subsample: more than 2^32 samples");
  }
  std::vector<uint32_t> order(samples.size());
  std::iota(order.begin(), order.end(), uint32_t{0});
  const size_t peak_count = std::min(samples.size() / 100, max_samples / 2);
  // Peak: the brightest samples, all kept with their own weight.
  std::nth_element(order.begin(), order.begin() + peak_count, order.end(),
                   [&](uint32_t a, uint32_t b) {
                     const double la = Luminance(samples[a].value);
                     const double lb = Luminance(samples[b].value);
                     return la > lb || (la == lb && a < b);
                   });
  // The rest in ascending index order (a deterministic order for the draw), rebuilt in one
  // pass instead of sorted.
  std::vector<bool> in_peak(samples.size(), false);
  for (size_t k = 0; k < peak_count; ++k) in_peak[order[k]] = true;
  size_t next = peak_count;
  for (size_t index = 0; index < samples.size(); ++index) {
    if (!in_peak[index]) order[next++] = static_cast<uint32_t>(index);
  }
  std::vector<FitSample> subset;
  subset.reserve(max_samples);
  for (size_t k = 0; k < peak_count; ++k) subset.push_back(samples[order[k]]);
  // The rest: a seeded partial Fisher-Yates draw.
  Rng random(0, seed);
  const size_t rest = samples.size() - peak_count, drawn = max_samples - peak_count;
  for (size_t k = 0; k < drawn; ++k) {
    const size_t pick = k + random.Below(rest - k);
    std::swap(order[peak_count + k], order[peak_count + pick]);
    FitSample sample = samples[order[peak_count + k]];
    const double inverse_inclusion = static_cast<double>(rest) / drawn;
    sample.weight *= inverse_inclusion;
    sample.scale *= std::sqrt(inverse_inclusion);
    subset.push_back(sample);
  }
  return subset;
}

}  // namespace brdf::fitters
