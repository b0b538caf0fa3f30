// The runtime model registry: name -> parameter table (names, bounds, meaning, defaults), an
// evaluator and the model's lobes. The templated terms and their compositions (term.h,
// composition.h) hold the math and their own tables; this file, built from the one list in
// model_list.h, lets the command line, readers, integrators and reports handle a model chosen at
// run time, asking it for capabilities rather than for its kind.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/vec.h"
#include "models/common.h"
#include "models/model_list.h"
#include "models/term.h"

namespace brdf {

// One lobe of a model, at its place among the model's parameters.
struct LobeInfo {
  std::string term;     // the term's name, e.g. "ggx"
  int first_slot = 0;   // its first parameter's slot in the model
  int shape_slot = -1;  // its width parameter's slot in the model (exponent or alpha)
  models::ShapeScale shape_scale = models::ShapeScale::kNone;
  double fit_shape_min = 0, fit_shape_max = 0;  // the range a fit gives the width
  bool vanishes_at_zero = true;  // no lobe at all when its per-channel parameter is 0
  std::string adds;  // what it brings to a fit, e.g. "Fresnel and masking lower" (the rmse)
  // Where the lobe lies and its density, its share of the albedo per channel (power cosine:
  // A(e) rho_s; microfacet: the hemispherical average of Fresnel; the weight of the lobe in an
  // importance mixture) and its half width as a power-cosine exponent (the diagnostics'), each
  // from the model's parameters.
  LobeCoordinates (*coordinates)(const double* params) = nullptr;
  Rgb (*weight)(const double* params) = nullptr;
  double (*equivalent_exponent)(const double* params) = nullptr;
};

struct ModelInfo {
  std::string name;           // as the command line writes it, e.g. "ggx"
  std::string terms;          // the composition, e.g. "lambert+ggx"
  std::string diffuse;        // its diffuse term's name, e.g. "lambert"
  std::string formula;        // f(wi, wo) as in DESIGN §2
  std::string bound_formula;  // how the fitter's energy bound is formed, e.g. "rho_d + A(e) rho_s"
  bool auto_candidate = false;  // a rung `--model auto` climbs
  int num_params = 0;
  std::vector<ParamInfo> params;
  std::vector<LobeInfo> lobes;  // in the composition's order
  Rgb (*eval)(const double* params, const Vec3& wi, const Vec3& wo) = nullptr;

  bool has_lobe() const { return !lobes.empty(); }
  // The first lobe's (every model with a lobe has one).
  int shape_slot() const { return has_lobe() ? lobes.front().shape_slot : -1; }
  // The first lobe's coordinates, its weight and width; for a model without a lobe the normal,
  // zero and 0.
  LobeCoordinates Lobe(const double* params) const;
  Rgb LobeWeight(const double* params) const;
  double EquivalentExponent(const double* params) const;

  const ParamInfo* FindParam(std::string_view param_name) const;
  // The parameter whose values start at `slot` (a lobe's first_slot or shape_slot).
  const ParamInfo& ParamAtSlot(int slot) const;
  std::vector<double> DefaultParams() const;
};

// The runtime description of composition M (models/composition.h) under `name`; the registry
// holds one for every model of model_list.h.
template <typename M>
ModelInfo MakeModelInfo(const std::string& name, bool auto_candidate = false);

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
  LobeCoordinates Lobe() const { return info_->Lobe(params_.data()); }
  Rgb LobeWeight() const { return info_->LobeWeight(params_.data()); }

  // The canonical model string, e.g. "phong:rho_d=0.5:rho_s=0.04:n=100"; ParseModel reads it
  // back to the same values (the shortest text that round-trips each double). With
  // `significant` > 0 the values are rounded to that many digits, for tables people read.
  std::string ToString(int significant = 0) const;

 private:
  const ModelInfo* info_;
  std::vector<double> params_;
};

template <typename M>
ModelInfo MakeModelInfo(const std::string& name, bool auto_candidate) {
  ModelInfo info;
  info.name = name;
  info.terms = M::TermNames();
  info.diffuse = M::DiffuseTerm::kName;
  info.formula = M::Formula();
  info.bound_formula = M::BoundFormula();
  info.auto_candidate = auto_candidate;
  info.num_params = M::kNumParams;
  info.params = M::Params();
  info.eval = [](const double* p, const Vec3& wi, const Vec3& wo) -> Rgb {
    return M::template Eval<double>(p, wi, wo);
  };
  M::ForEachLobe([&](auto lobe, auto index) {
    using Lobe = decltype(lobe);
    constexpr int kOffset = M::kOffsets[decltype(index)::value];
    LobeInfo entry;
    entry.term = Lobe::kName;
    entry.first_slot = kOffset;
    entry.shape_slot = Lobe::kShapeSlot >= 0 ? kOffset + Lobe::kShapeSlot : -1;
    entry.shape_scale = Lobe::kShapeScale;
    entry.fit_shape_min = Lobe::kFitShapeMin;
    entry.fit_shape_max = Lobe::kFitShapeMax;
    entry.vanishes_at_zero = Lobe::kVanishesAtZero;
    entry.adds = Lobe::kAdds;
    entry.coordinates = [](const double* p) { return Lobe::Lobe(p + kOffset); };
    entry.weight = [](const double* p) { return Lobe::LobeWeight(p + kOffset); };
    entry.equivalent_exponent = [](const double* p) {
      return Lobe::EquivalentExponent(p + kOffset);
    };
    info.lobes.push_back(entry);
  });
  return info;
}

}  // namespace brdf
