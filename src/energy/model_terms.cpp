#include "energy/model_terms.h"

#include <algorithm>

namespace brdf {
namespace {

// Largest channel of the RGB parameter at `slot`.
double MaxChannel(const std::vector<double>& params, int slot) {
  return std::max({params[slot], params[slot + 1], params[slot + 2]});
}

}  // namespace

std::vector<AlbedoTerm> AlbedoTerms(const Model& model) {
  const std::vector<double>& params = model.params();
  const ModelInfo& info = model.info();
  const LobeCoordinates diffuse_coordinates{kNormalFrame, 1.0};
  // Every model's diffuse term comes first and takes rho_d at slot 0 (DESIGN §2); alone, it is
  // the model named by the term (lambert, eon) with the composition's first parameters.
  const double diffuse_scale = MaxChannel(params, 0);
  if (!info.has_lobe()) return {{"diffuse", model, diffuse_coordinates, diffuse_scale}};
  const Model diffuse(
      FindModel(info.terms.substr(0, info.terms.find('+'))),
      std::vector<double>(params.begin(), params.begin() + info.lobes.front().first_slot));
  std::vector<AlbedoTerm> terms = {{"diffuse", diffuse, diffuse_coordinates, diffuse_scale}};
  for (size_t k = 0; k < info.lobes.size(); ++k) {
    const LobeInfo& lobe = info.lobes[k];
    // The lobe alone: the model with rho_d = 0, or with more lobes than one, the lobe's own
    // composition with lambert (rho_d = 0).
    const ModelInfo& alone = info.lobes.size() == 1 ? info : FindModel("lambert+" + lobe.term);
    std::vector<double> lobe_params(alone.num_params, 0.0);
    const int first = alone.lobes.front().first_slot;
    const int end = k + 1 < info.lobes.size() ? info.lobes[k + 1].first_slot : info.num_params;
    if (info.lobes.size() == 1) {
      lobe_params = params;
      std::fill(lobe_params.begin(), lobe_params.begin() + 3, 0.0);
    } else {
      std::copy(params.begin() + lobe.first_slot, params.begin() + end,
                lobe_params.begin() + first);
    }
    terms.push_back({k == 0 ? "lobe" : "lobe " + std::to_string(k + 1),
                     Model(alone, std::move(lobe_params)), lobe.coordinates(params.data()),
                     lobe.weight(params.data()).maxCoeff()});
  }
  return terms;
}

BrdfFunction ModelBrdf(const Model& model) {
  return [model](const Vec3& wi, const Vec3& wo) { return BrdfSample{model.Eval(wi, wo), true}; };
}

}  // namespace brdf
