// A model's albedo as a sum of terms, each with the lobe coordinates that suit it: the diffuse
// term about the normal, phong's lobe about the mirror direction, the Blinn family's lobe in
// half-vector space. Every term is the model itself with the other terms' albedo parameters set
// to zero, so the integrand is always the model's own Eval, never a closed form.
#pragma once

#include <string>
#include <vector>

#include "energy/integrand.h"
#include "models/registry.h"

namespace brdf {

struct AlbedoTerm {
  std::string name;  // "diffuse", "lobe", or "whole model" when the model is not split
  Model model;       // the model with the other terms switched off
  LobeCoordinates coordinates;
  double scale = 0;  // largest channel of the term's albedo parameter (importance mixture weight)
};

// Models the registry does not know how to split are integrated whole about the normal; the
// adaptive rule still converges, only more slowly for a sharp lobe.
std::vector<AlbedoTerm> AlbedoTerms(const Model& model);

// The model as an integrand.
BrdfFunction ModelBrdf(const Model& model);

}  // namespace brdf
