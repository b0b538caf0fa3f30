// The runtime model registry: name -> parameter table (names, bounds, meaning, defaults), an
// evaluator and the model's lobe. The templated structs (lambert.h, phong.h, ggx.h, ...) hold the
// math and their own tables; this file, built from the one list in model_list.h, lets the command
// line, readers, integrators and reports handle a model chosen at run time.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/vec.h"
#include "models/common.h"
#include "models/model_list.h"

namespace brdf {

struct ModelInfo {
  std::string name;
  std::string formula;  // f(wi, wo) as in DESIGN §2
  int num_params = 0;
  std::vector<ParamInfo> params;
  models::ModelFamily family = models::ModelFamily::kDiffuse;
  int shape_slot = -1;  // the lobe's width parameter (exponent or alpha); -1 without a lobe
  Rgb (*eval)(const double* params, const Vec3& wi, const Vec3& wo) = nullptr;
  // Where the lobe lies and its density (kNormal for a diffuse model).
  LobeCoordinates (*lobe)(const double* params) = nullptr;
  // The lobe's share of the albedo per channel (power cosine: A(e) rho_s; microfacet: the
  // hemispherical average of Fresnel); the weight of the lobe in an importance mixture.
  Rgb (*lobe_weight)(const double* params) = nullptr;
  // The lobe's half width as a power-cosine exponent (0 without a lobe), for the diagnostics.
  double (*equivalent_exponent)(const double* params) = nullptr;

  bool has_lobe() const { return shape_slot >= 0; }
  const ParamInfo& shape_param() const;  // only when has_lobe()

  const ParamInfo* FindParam(std::string_view param_name) const;
  std::vector<double> DefaultParams() const;
};

// Every model, in the order of DESIGN §2.
const std::vector<ModelInfo>& ModelRegistry();
// Throws UsageError naming the known models when `name` is not one of them.
const ModelInfo& FindModel(std::string_view name);

// Calls visitor(ModelType{}) with the templated struct named `name` (for code that needs the
// model at compile time, such as Ceres residuals). Throws UsageError for an unknown name.
template <typename Visitor>
decltype(auto) VisitModelType(std::string_view name, Visitor&& visitor) {
  return models::VisitModel(models::AllModels{}, name, std::forward<Visitor>(visitor),
                            [&] { FindModel(name); });
}

// A model with its parameter values.
class Model {
 public:
  Model(const ModelInfo& info, std::vector<double> params);

  const ModelInfo& info() const { return *info_; }
  const std::string& name() const { return info_->name; }
  const std::vector<double>& params() const { return params_; }
  // Value of a named parameter; `channel` selects R, G or B of an RGB parameter.
  double Param(std::string_view param_name, int channel = 0) const;

  Rgb Eval(const Vec3& wi, const Vec3& wo) const { return info_->eval(params_.data(), wi, wo); }
  LobeCoordinates Lobe() const { return info_->lobe(params_.data()); }
  Rgb LobeWeight() const { return info_->lobe_weight(params_.data()); }

  // The canonical model string, e.g. "phong:rho_d=0.5:rho_s=0.04:n=100"; ParseModel reads it
  // back to the same values (the shortest text that round-trips each double). With
  // `significant` > 0 the values are rounded to that many digits, for tables people read.
  std::string ToString(int significant = 0) const;

 private:
  const ModelInfo* info_;
  std::vector<double> params_;
};

}  // namespace brdf
