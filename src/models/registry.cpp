#include "models/registry.h"

#include <limits>

#include "core/errors.h"

namespace brdf {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Albedos are not capped at 1 here: a non-conserving material must be expressible so that
// `brdf energy` can show that it is not conserving. Exponents up to 1e6 cover real materials
// (measured lobes reach ~1e5) with room to spare.
ParamInfo RhoD(double default_value) {
  return {"rho_d", models::LobedSlots::kRhoD, 3, 0.0, kInf, default_value, "diffuse albedo (RGB)"};
}
ParamInfo RhoS() {
  return {"rho_s", models::LobedSlots::kRhoS,         3, 0.0, kInf,
          0.04,    "specular lobe albedo scale (RGB)"};
}
ParamInfo Exponent(const char* name) {
  return {name,  models::LobedSlots::kExponent,      1, 0.0, 1e6,
          100.0, "lobe exponent (larger is sharper)"};
}

template <typename M>
ModelInfo MakeInfo(std::string formula, std::vector<ParamInfo> params) {
  ModelInfo info;
  info.name = M::kName;
  info.formula = std::move(formula);
  info.num_params = M::kNumParams;
  info.params = std::move(params);
  info.eval = [](const double* p, const Vec3& wi, const Vec3& wo) -> Rgb {
    return M::template Eval<double>(p, wi, wo);
  };
  return info;
}

std::vector<ModelInfo> BuildRegistry() {
  std::vector<ModelInfo> registry;
  registry.push_back(MakeInfo<models::Lambert>("rho_d/pi", {RhoD(0.5)}));
  registry.push_back(MakeInfo<models::Phong>("rho_d/pi + rho_s (n+2)/(2pi) cos^n(alpha)",
                                             {RhoD(0.5), RhoS(), Exponent("n")}));
  registry.push_back(MakeInfo<models::BlinnPhong>("rho_d/pi + rho_s (m+8)/(8pi) cos^m(theta_h)",
                                                  {RhoD(0.5), RhoS(), Exponent("m")}));
  registry.push_back(MakeInfo<models::BlinnPhongExact>(
      "rho_d/pi + rho_s (m+2)(m+4)/(8pi(2^(-m/2)+m)) cos^m(theta_h)",
      {RhoD(0.5), RhoS(), Exponent("m")}));
  return registry;
}

}  // namespace

const ParamInfo* ModelInfo::FindParam(std::string_view param_name) const {
  for (const ParamInfo& param : params) {
    if (param.name == param_name) return &param;
  }
  return nullptr;
}

std::vector<double> ModelInfo::DefaultParams() const {
  std::vector<double> values(num_params, 0.0);
  for (const ParamInfo& param : params) {
    for (int c = 0; c < param.channels; ++c) values[param.slot + c] = param.default_value;
  }
  return values;
}

const std::vector<ModelInfo>& ModelRegistry() {
  static const std::vector<ModelInfo> registry = BuildRegistry();
  return registry;
}

const ModelInfo& FindModel(std::string_view name) {
  std::string known;
  for (const ModelInfo& info : ModelRegistry()) {
    if (info.name == name) return info;
    known += (known.empty() ? "" : ", ") + info.name;
  }
  throw UsageError("unknown model '" + std::string(name) + "' (known: " + known + ")");
}

Model::Model(const ModelInfo& info, std::vector<double> params)
    : info_(&info), params_(std::move(params)) {
  if (static_cast<int>(params_.size()) != info.num_params) {
    throw UsageError("model '" + info.name + "' takes " + std::to_string(info.num_params) +
                     " values, got " + std::to_string(params_.size()));
  }
}

double Model::Param(std::string_view param_name, int channel) const {
  const ParamInfo* param = info_->FindParam(param_name);
  if (param == nullptr || channel < 0 || channel >= param->channels) {
    throw UsageError("model '" + info_->name + "' has no parameter '" + std::string(param_name) +
                     "'" + (param ? " channel " + std::to_string(channel) : ""));
  }
  return params_[param->slot + channel];
}

}  // namespace brdf
