// The runtime model registry: name -> parameter table (names, bounds, meaning, defaults) and
// an evaluator. The templated structs (lambert.h, phong.h, ...) hold the math; this file lets
// the command line, readers and reports handle a model chosen at run time.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/vec.h"
#include "models/blinn_phong.h"
#include "models/blinn_phong_exact.h"
#include "models/lambert.h"
#include "models/phong.h"

namespace brdf {

struct ParamInfo {
  std::string name;    // as written in model strings and reports, e.g. "rho_d"
  int slot = 0;        // first index in the flat parameter array
  int channels = 1;    // 3 for RGB parameters
  double lower = 0.0;  // accepted range (inclusive)
  double upper = 0.0;
  double default_value = 0.0;
  std::string meaning;
};

struct ModelInfo {
  std::string name;
  std::string formula;  // f(wi, wo) as in DESIGN §2
  int num_params = 0;
  std::vector<ParamInfo> params;
  Rgb (*eval)(const double* params, const Vec3& wi, const Vec3& wo) = nullptr;

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
  if (name == models::Lambert::kName) return visitor(models::Lambert{});
  if (name == models::Phong::kName) return visitor(models::Phong{});
  if (name == models::BlinnPhong::kName) return visitor(models::BlinnPhong{});
  if (name == models::BlinnPhongExact::kName) return visitor(models::BlinnPhongExact{});
  FindModel(name);  // throws the descriptive error
  return visitor(models::Lambert{});
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

  // The canonical model string, e.g. "phong:rho_d=0.5:rho_s=0.04:n=100"; ParseModel reads it
  // back to the same values (the shortest text that round-trips each double). With
  // `significant` > 0 the values are rounded to that many digits, for tables people read.
  std::string ToString(int significant = 0) const;

 private:
  const ModelInfo* info_;
  std::vector<double> params_;
};

}  // namespace brdf
