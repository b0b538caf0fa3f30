#include "fitters/reading_nodes.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/angles.h"
#include "core/text.h"

namespace brdf::fitters {

SampleNodes InstrumentNodes(const gonio::Instrument& instrument, const Model& model,
                            const std::vector<FitSample>& samples) {
  const gonio::ForwardModel forward(instrument, gonio::LobeWidth(model));
  SampleNodes result;
  result.points_per_reading = forward.PointsPerReading();
  // Pass 1: whether each sample needs the average, and its node count.
  std::vector<size_t> count(samples.size() + 1, 0);
  std::vector<char> averaged(samples.size(), 0);
  tbb::parallel_for(size_t{0}, samples.size(), [&](size_t k) {
    std::vector<gonio::ReadingNode> nodes;
    forward.AppendNodes(samples[k].wi, samples[k].wo, &nodes);
    Rgb average = Rgb::Zero();
    for (const gonio::ReadingNode& node : nodes) {
      average += node.weight * model.Eval(node.wi, node.wo);
    }
    const Rgb nominal = model.Eval(samples[k].wi, samples[k].wo);
    const double size = std::max({average.abs().maxCoeff(), nominal.abs().maxCoeff(), 1e-300});
    averaged[k] = (average - nominal).abs().maxCoeff() > kNominalTolerance * size;
    count[k + 1] = averaged[k] ? nodes.size() : 1;
  });
  std::partial_sum(count.begin(), count.end(), count.begin());
  result.first = std::move(count);
  result.nodes.resize(result.first.back());
  // Pass 2: the nodes in place.
  tbb::parallel_for(size_t{0}, samples.size(), [&](size_t k) {
    const size_t first = result.first[k], size = result.first[k + 1] - first;
    if (!averaged[k]) {
      result.nodes[first] = {samples[k].wi, samples[k].wo, 1.0};
      return;
    }
    std::vector<gonio::ReadingNode> nodes;
    nodes.reserve(size);
    forward.AppendNodes(samples[k].wi, samples[k].wo, &nodes);
    std::copy(nodes.begin(), nodes.end(), result.nodes.begin() + first);
  });
  result.averaged = static_cast<size_t>(std::count(averaged.begin(), averaged.end(), 1));
  return result;
}

std::string ApertureBlurWarning(const gonio::Instrument& instrument, const Model& model) {
  const double width = gonio::LobeWidth(model);
  const double radius = std::acos(instrument.DetectorCosHalfAngle());
  if (!(width < kBlurredLobe * radius)) return "";
  return "the lobe of " + model.ToString(4) + " is " + FormatNumber(RadToDeg(width), 3) +
         " deg wide, under half the detector aperture's radius (" +
         FormatNumber(RadToDeg(radius), 3) +
         " deg): readings average the whole lobe and only the aperture's rim sees its width, "
         "so the width is known only as well as the standard errors say; a smaller detector "
         "resolves it";
}

Rgb PredictReading(const Model& model, const std::vector<FitSample>& samples,
                   const SampleNodes* nodes, size_t k) {
  if (nodes == nullptr) return model.Eval(samples[k].wi, samples[k].wo);
  Rgb sum = Rgb::Zero();
  for (size_t n = nodes->first[k]; n < nodes->first[k + 1]; ++n) {
    sum += nodes->nodes[n].weight * model.Eval(nodes->nodes[n].wi, nodes->nodes[n].wo);
  }
  return sum;
}

}  // namespace brdf::fitters
