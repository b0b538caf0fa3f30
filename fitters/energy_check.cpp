#include "fitters/energy_check.h"

#include "energy/albedo.h"
#include "fitters/energy_bound.h"

namespace brdf::fitters {

void CheckFitEnergy(FitResult* result) {
  const Model& model = result->model;
  const Rgb bound = EnergyBound(model);
  const AlbedoCurve curve = ModelAlbedoCurve(model, AlbedoOptions{});
  result->energy.max_albedo = curve.max_albedo;
  result->energy.albedo_error = curve.error_at_max;
  result->energy.bound = bound;
  result->energy.theta_deg_at_max = curve.theta_deg_at_max;
  result->energy.verdict = curve.verdict();
  result->energy.method = std::string("albedo integrated over ") +
                          std::to_string(curve.points.size()) + " incidence angles (" +
                          AlbedoMethodName(curve.method) + "); bound " + model.info().bound_formula;
  for (int c = 0; c < 3; ++c) {
    if (bound[c] > 0.999) {
      result->warnings.push_back(std::string("energy bound active in channel ") + "rgb"[c] +
                                 ": the data ask for an albedo of 1 or more");
    }
  }
}

}  // namespace brdf::fitters
