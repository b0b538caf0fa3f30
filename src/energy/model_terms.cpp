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
  const LobeCoordinates diffuse_coordinates{LobeFrame::kNormal, 1.0};
  // Every model's diffuse term is rho_d/π (slot 0, DESIGN §2).
  const double diffuse_scale = MaxChannel(params, 0);
  if (!model.info().has_lobe()) return {{"diffuse", model, diffuse_coordinates, diffuse_scale}};
  const Model diffuse(FindModel(models::Lambert::kName), {params[0], params[1], params[2]});
  std::vector<double> lobe_params = params;
  std::fill(lobe_params.begin(), lobe_params.begin() + 3, 0.0);
  return {{"diffuse", diffuse, diffuse_coordinates, diffuse_scale},
          {"lobe", Model(model.info(), std::move(lobe_params)), model.Lobe(),
           model.LobeWeight().maxCoeff()}};
}

BrdfFunction ModelBrdf(const Model& model) {
  return [model](const Vec3& wi, const Vec3& wo) { return BrdfSample{model.Eval(wi, wo), true}; };
}

}  // namespace brdf
