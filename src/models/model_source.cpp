#include "models/model_source.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/json_text.h"
#include "core/text.h"
#include "models/model_string.h"

namespace brdf {
namespace {

// Fit reports are small; anything larger is not one.
constexpr int64_t kMaxReportBytes = int64_t{16} << 20;

class AnalyticTable : public TabulatedBrdf, public CellMeasure {
 public:
  explicit AnalyticTable(Model model) : model_(std::move(model)) {}
  Rgb Eval(const Vec3& wi, const Vec3& wo) const override { return model_.Eval(wi, wo); }
  std::string Describe() const override { return "the analytic model " + model_.ToString(7); }
  std::string LookupName() const override { return "analytic " + model_.name(); }
  // A model has no cells: each evaluation stands for itself.
  double Measure(const Vec3&, const Vec3&) const override { return 1.0; }
  std::string Name() const override { return "none (an analytic model)"; }

 private:
  Model model_;
};

}  // namespace

bool IsFitReportPath(const std::string& spec) {
  if (spec.size() < 5) return false;
  std::string extension = spec.substr(spec.size() - 5);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return extension == ".json";
}

Model ReadFitReportModel(const std::string& path) {
  const std::string text = ReadFileBytes(path, kMaxReportBytes);
  const nlohmann::json report = ParseJsonText(text, path, "a fit report");
  if (!report.is_object() || !report.contains("model") || !report["model"].is_string()) {
    throw InputError(
        path, "expected a fit report (the JSON `brdf fit --json` writes) with a \"model\" name");
  }
  const std::string name = report["model"].get<std::string>();
  const ModelInfo* info = nullptr;
  try {
    info = &FindModel(name);
  } catch (const UsageError& error) {
    throw InputError(path, error.what());
  }
  if (!report.contains("params") || !report["params"].is_object()) {
    throw InputError(path, "expected \"params\": {...} with the parameters of '" + name + "'");
  }
  const nlohmann::json& params = report["params"];
  std::vector<double> values(info->num_params, 0.0);
  for (const ParamInfo& param : info->params) {
    if (!params.contains(param.name)) {
      throw InputError(path, "params has no \"" + param.name + "\" (model '" + name + "')");
    }
    const nlohmann::json& value = params[param.name];
    std::vector<double> channels;
    if (value.is_number()) {
      channels.assign(param.channels, value.get<double>());
    } else if (value.is_array() && static_cast<int>(value.size()) == param.channels &&
               std::all_of(value.begin(), value.end(),
                           [](const nlohmann::json& v) { return v.is_number(); })) {
      for (const nlohmann::json& v : value) channels.push_back(v.get<double>());
    } else {
      throw InputError(path, "params." + param.name + " must be a number" +
                                 (param.channels == 3 ? " or [r, g, b]" : ""));
    }
    for (int c = 0; c < param.channels; ++c) {
      if (!std::isfinite(channels[c]) || channels[c] < param.lower || channels[c] > param.upper) {
        throw InputError(path, "params." + param.name + " = " + FormatNumber(channels[c]) +
                                   " is outside [" + FormatNumber(param.lower) + ", " +
                                   FormatNumber(param.upper) + "]");
      }
      values[param.slot + c] = channels[c];
    }
  }
  return Model(*info, std::move(values));
}

Model LoadModel(const std::string& spec) {
  if (IsFitReportPath(spec)) return ReadFitReportModel(spec);
  return ParseModel(spec);
}

Measurement ModelAsMeasurement(const Model& model, const std::string& spec) {
  Measurement measurement;
  measurement.format = "model";
  measurement.source = spec;
  measurement.metadata["model"] = model.ToString();
  auto table = std::make_shared<AnalyticTable>(model);
  measurement.tabulated = table;
  measurement.cell_measure = table;
  return measurement;
}

bool IsModelSpec(const std::string& spec) {
  if (IsFitReportPath(spec)) return true;
  struct stat info;
  if (::stat(spec.c_str(), &info) == 0) return false;
  const std::string name = spec.substr(0, spec.find(':'));
  // A composition names its terms: FindModel says which one is wrong.
  if (name.find('+') != std::string::npos) {
    FindModel(name);
    return true;
  }
  std::string names;
  for (const ModelInfo& model : ModelRegistry()) {
    if (model.name == name) return true;
    names += (names.empty() ? "" : ", ") + model.name;
  }
  throw InputError(spec, "no such file, and not a model string (models: " + names + ")");
}

}  // namespace brdf
