// A model's albedo as a sum of terms, each with the lobe coordinates that suit it: the diffuse
// term rho_d/π about the normal, and the lobe where the model says it lies (Model::Lobe: phong's
// about the mirror direction, the Blinn family's and the microfacet models' in half-vector
// space). The lobe term is the model itself with rho_d = 0, so the integrand is always the
// model's own Eval, never a closed form.
#pragma once

#include <string>
#include <vector>

#include "energy/integrand.h"
#include "models/registry.h"

namespace brdf {

struct AlbedoTerm {
  std::string name;  // "diffuse" or "lobe"
  Model model;       // the model with the other terms switched off
  LobeCoordinates coordinates;
  double scale = 0;  // largest channel of the term's albedo parameter (importance mixture weight)
};

std::vector<AlbedoTerm> AlbedoTerms(const Model& model);

// The model as an integrand.
BrdfFunction ModelBrdf(const Model& model);

}  // namespace brdf
