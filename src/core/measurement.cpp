#include "core/measurement.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <vector>

#include "core/angles.h"

namespace brdf {

std::string Measurement::SampleName() const {
  // A file that names its sample, or describes it in one line (RGL-EPFL's "description":
  // "TeckWrap vinyl wrapping film (Ibiza Sunset RD02)"), is named so rather than by its path.
  for (const char* key : {"sample", "description"}) {
    auto it = metadata.find(key);
    if (it != metadata.end() && !it->second.empty()) return it->second;
  }
  const size_t slash = source.find_last_of('/');
  return slash == std::string::npos ? source : source.substr(slash + 1);
}

MeasurementSummary Summarize(const Measurement& measurement) {
  MeasurementSummary summary;
  summary.format = measurement.format;
  summary.sample_name = measurement.SampleName();
  summary.samples = measurement.samples.size();

  constexpr double kInf = std::numeric_limits<double>::infinity();
  double theta_i[2] = {kInf, -kInf}, theta_o[2] = {kInf, -kInf};
  Rgb min = Rgb::Constant(kInf), max = Rgb::Constant(-kInf);
  // Distinct incidence directions, quantized to ~1e-6 so that angles printed with six
  // decimals (as in the Cornell files) compare equal.
  std::vector<std::tuple<long long, long long, long long>> incidences;
  incidences.reserve(measurement.samples.size());
  for (const Sample& sample : measurement.samples) {
    if (sample.missing) {
      ++summary.missing;
      continue;
    }
    const double ti = Theta(sample.wi), to = Theta(sample.wo);
    theta_i[0] = std::min(theta_i[0], ti);
    theta_i[1] = std::max(theta_i[1], ti);
    theta_o[0] = std::min(theta_o[0], to);
    theta_o[1] = std::max(theta_o[1], to);
    incidences.emplace_back(std::llround(sample.wi.x() * 1e6), std::llround(sample.wi.y() * 1e6),
                            std::llround(sample.wi.z() * 1e6));
    for (int c = 0; c < 3; ++c) {
      const double v = sample.value[c];
      if (!std::isfinite(v)) {
        ++summary.nan;
        continue;
      }
      if (v < 0) ++summary.negative;
      min[c] = std::min(min[c], v);
      max[c] = std::max(max[c], v);
    }
  }
  std::sort(incidences.begin(), incidences.end());
  summary.incidence_directions =
      std::unique(incidences.begin(), incidences.end()) - incidences.begin();
  if (theta_i[0] <= theta_i[1]) {
    for (int k = 0; k < 2; ++k) {
      summary.theta_i_deg[k] = RadToDeg(theta_i[k]);
      summary.theta_o_deg[k] = RadToDeg(theta_o[k]);
    }
  }
  for (int c = 0; c < 3; ++c) {
    summary.min[c] = min[c] <= max[c] ? min[c] : 0.0;
    summary.max[c] = min[c] <= max[c] ? max[c] : 0.0;
  }
  return summary;
}

bool Measurement::equal_weighting() const {
  const auto found = metadata.find(kWeightingKey);
  return found != metadata.end() && found->second == kEqualWeighting;
}

}  // namespace brdf
