#include "models/model_string.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>

#include "core/errors.h"
#include "core/text.h"

namespace brdf {
namespace {

std::vector<std::string_view> Split(std::string_view text, char separator) {
  std::vector<std::string_view> parts;
  size_t start = 0;
  while (true) {
    const size_t end = text.find(separator, start);
    parts.push_back(text.substr(start, end == std::string_view::npos ? end : end - start));
    if (end == std::string_view::npos) return parts;
    start = end + 1;
  }
}

[[noreturn]] void Fail(std::string_view text, const std::string& what) {
  throw UsageError("model '" + std::string(text) + "': " + what);
}

double ParseValue(std::string_view text, std::string_view field, const ParamInfo& param) {
  double value = 0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (field.empty() || error != std::errc() || end != field.data() + field.size() ||
      !std::isfinite(value)) {
    Fail(text, "expected a number for " + param.name + ", found '" + std::string(field) + "'");
  }
  if (value < param.lower || value > param.upper) {
    Fail(text, param.name + " = " + FormatNumber(value) + " is outside [" +
                   FormatNumber(param.lower) + ", " + FormatNumber(param.upper) + "]");
  }
  return value;
}

}  // namespace

Model ParseModel(std::string_view text) {
  const std::vector<std::string_view> parts = Split(text, ':');
  const ModelInfo& info = FindModel(parts[0]);
  std::vector<double> params = info.DefaultParams();
  std::set<std::string_view> seen;
  for (size_t k = 1; k < parts.size(); ++k) {
    const std::string_view part = parts[k];
    const size_t equals = part.find('=');
    if (equals == std::string_view::npos) {
      Fail(text, "expected key=value, found '" + std::string(part) + "'");
    }
    const std::string_view key = part.substr(0, equals);
    const ParamInfo* param = info.FindParam(key);
    if (param == nullptr) {
      std::string names;
      for (const ParamInfo& p : info.params) names += (names.empty() ? "" : ", ") + p.name;
      Fail(text, "'" + info.name + "' has no parameter '" + std::string(key) + "' (it has " +
                     names + ")");
    }
    if (!seen.insert(key).second) Fail(text, "parameter '" + param->name + "' given twice");
    const std::vector<std::string_view> values = Split(part.substr(equals + 1), ',');
    if (values.size() == 1) {
      const double value = ParseValue(text, values[0], *param);
      for (int c = 0; c < param->channels; ++c) params[param->slot + c] = value;
    } else if (static_cast<int>(values.size()) == param->channels) {
      for (int c = 0; c < param->channels; ++c) {
        params[param->slot + c] = ParseValue(text, values[c], *param);
      }
    } else {
      Fail(text, param->name + " takes " +
                     (param->channels == 3 ? std::string("one number or three (r,g,b)")
                                           : std::string("one number")) +
                     ", found " + std::to_string(values.size()));
    }
  }
  return Model(info, std::move(params));
}

std::string Model::ToString(int significant) const {
  std::string text = info_->name;
  for (const ParamInfo& param : info_->params) {
    text += ":" + param.name + "=";
    // Rounded for people: a value at its bound reads as the bound (ParamInfo::Displayed), and
    // channels that agree to the digits shown are written once (0.2699260473095003 and
    // 0.2699260473095004 are one grey value to a reader).
    std::vector<std::string> channels;
    for (int c = 0; c < param.channels; ++c) {
      const double value = params_[param.slot + c];
      channels.push_back(significant > 0 ? FormatNumber(param.Displayed(value), significant)
                                         : FormatNumber(value));
    }
    const bool grey =
        std::all_of(channels.begin(), channels.end(),
                    [&](const std::string& channel) { return channel == channels[0]; });
    for (size_t c = 0; c < (grey ? 1 : channels.size()); ++c) text += (c ? "," : "") + channels[c];
  }
  return text;
}

}  // namespace brdf
