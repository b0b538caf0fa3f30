#include "energy/model_terms.h"

#include <algorithm>

namespace brdf {
namespace {

using models::LobedSlots;

// Largest channel of the RGB parameter at `slot`.
double MaxChannel(const std::vector<double>& params, int slot) {
  return std::max({params[slot], params[slot + 1], params[slot + 2]});
}

// The model with the three channels at `slot` set to zero.
Model WithoutRgb(const Model& model, int slot) {
  std::vector<double> params = model.params();
  std::fill(params.begin() + slot, params.begin() + slot + 3, 0.0);
  return Model(model.info(), std::move(params));
}

}  // namespace

std::vector<AlbedoTerm> AlbedoTerms(const Model& model) {
  const std::string& name = model.name();
  const std::vector<double>& params = model.params();
  const LobeCoordinates diffuse_coordinates{LobeFrame::kNormal, 1.0};
  if (name == models::Lambert::kName) {
    return {{"diffuse", model, diffuse_coordinates, MaxChannel(params, models::Lambert::kRhoD)}};
  }
  LobeCoordinates lobe_coordinates;
  if (name == models::Phong::kName) {
    // cos^n(alpha), alpha measured from the mirror direction (phong.h).
    lobe_coordinates = {LobeFrame::kMirror, params[LobedSlots::kExponent]};
  } else if (name == models::BlinnPhong::kName || name == models::BlinnPhongExact::kName) {
    // cos^m(theta_h): a power-cosine lobe of the half vector about the normal.
    lobe_coordinates = {LobeFrame::kHalfVector, params[LobedSlots::kExponent]};
  } else {
    return {{"whole model", model, diffuse_coordinates, 1.0}};
  }
  return {{"diffuse", WithoutRgb(model, LobedSlots::kRhoS), diffuse_coordinates,
           MaxChannel(params, LobedSlots::kRhoD)},
          {"lobe", WithoutRgb(model, LobedSlots::kRhoD), lobe_coordinates,
           MaxChannel(params, LobedSlots::kRhoS)}};
}

BrdfFunction ModelBrdf(const Model& model) {
  return [model](const Vec3& wi, const Vec3& wo) { return BrdfSample{model.Eval(wi, wo), true}; };
}

}  // namespace brdf
