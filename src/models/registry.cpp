#include "models/registry.h"

#include <limits>
#include <string>
#include <vector>

#include "core/errors.h"

namespace brdf {
namespace {

std::vector<ModelInfo> BuildRegistry() {
  std::vector<ModelInfo> registry;
  models::ForEachModel([&](auto model) {
    using M = decltype(model);
    registry.push_back(MakeModelInfo<M>(M::kName, M::kAuto));
  });
  return registry;
}

// Why `name`, written as a composition (terms joined by '+'), is not a model: the first term that
// is not one, a lobe before the diffuse term, a second diffuse term, more than two lobes, or a
// valid composition that has no entry in models/model_list.h.
std::string CompositionError(std::string_view name, const std::string& known) {
  std::vector<std::string> terms;
  for (size_t start = 0;;) {
    const size_t end = name.find('+', start);
    terms.emplace_back(name.substr(start, end == std::string_view::npos ? end : end - start));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  std::string diffuse_names, lobe_names;
  std::vector<bool> diffuse(terms.size(), false);
  std::vector<bool> found(terms.size(), false);
  models::ForEachTerm([&](auto term) {
    using Term = decltype(term);
    std::string& names = Term::kDiffuse ? diffuse_names : lobe_names;
    names += (names.empty() ? "" : ", ") + std::string(Term::kName);
    for (size_t k = 0; k < terms.size(); ++k) {
      if (terms[k] == Term::kName) {
        found[k] = true;
        diffuse[k] = Term::kDiffuse;
      }
    }
  });
  const std::string model = "model '" + std::string(name) + "': ";
  for (size_t k = 0; k < terms.size(); ++k) {
    if (!found[k]) {
      return model + "unknown term '" + terms[k] + "' (diffuse terms: " + diffuse_names +
             "; lobes: " + lobe_names + ")";
    }
  }
  if (!diffuse[0]) {
    return model + "a composition starts with a diffuse term (" + diffuse_names + "), not '" +
           terms[0] + "'";
  }
  for (size_t k = 1; k < terms.size(); ++k) {
    if (diffuse[k]) return model + "'" + terms[k] + "' is a diffuse term; only the first term is";
  }
  if (terms.size() > 3) {
    return model + "at most two lobes after the diffuse term, found " +
           std::to_string(terms.size() - 1);
  }
  return model + "this composition has no entry in the model list (known: " + known + ")";
}

}  // namespace

const ParamInfo* ModelInfo::FindParam(std::string_view param_name) const {
  for (const ParamInfo& param : params) {
    if (param.name == param_name) return &param;
  }
  return nullptr;
}

LobeCoordinates ModelInfo::Lobe(const double* p) const {
  if (!has_lobe()) return {kNormalFrame, 1.0};
  return lobes.front().coordinates(p);
}

Rgb ModelInfo::LobeWeight(const double* p) const {
  return has_lobe() ? lobes.front().weight(p) : Rgb::Zero();
}

double ModelInfo::EquivalentExponent(const double* p) const {
  return has_lobe() ? lobes.front().equivalent_exponent(p) : 0.0;
}

const ParamInfo& ModelInfo::ParamAtSlot(int slot) const {
  for (const ParamInfo& param : params) {
    if (param.slot == slot) return param;
  }
  throw UsageError("model '" + name + "' has no parameter at slot " + std::to_string(slot));
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
    if (info.name == name || info.terms == name) return info;
    known += (known.empty() ? "" : ", ") + info.name;
  }
  if (name.find('+') != std::string_view::npos) throw UsageError(CompositionError(name, known));
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
