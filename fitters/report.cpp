#include "fitters/report.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "core/format.h"
#include "core/text.h"

namespace brdf::fitters {
namespace {

nlohmann::json RgbJson(const Rgb& rgb) { return {rgb[0], rgb[1], rgb[2]}; }

// A parameter as JSON: [r, g, b] or a number; NaN (not available) becomes null.
nlohmann::json ParamJson(const ParamInfo& param, const std::vector<double>& values) {
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  if (param.channels == 1) return number(values[param.slot]);
  nlohmann::json array = nlohmann::json::array();
  for (int c = 0; c < param.channels; ++c) array.push_back(number(values[param.slot + c]));
  return array;
}

// `values` of one parameter, padded for the table; parameter values (not their errors) are shown
// as people read them, a value at its bound as the bound (ParamInfo::Displayed).
std::string Numbers(const ParamInfo& param, const std::vector<double>& values, bool displayed) {
  std::string text;
  for (int c = 0; c < param.channels; ++c) {
    const double value = values[param.slot + c];
    text += std::isfinite(value) ? Format("%-12.6g", displayed ? param.Displayed(value) : value)
                                 : Format("%-12s", "n/a");
  }
  return text;
}

// "rho_d (r, g) = 0; alpha = 1.5": the parameters whose value sits at a bound of its range.
std::string AtBoundList(const Model& model) {
  std::string text;
  for (const ParamInfo& param : model.info().params) {
    std::string channels;
    double bound = 0;
    int count = 0;
    for (int c = 0; c < param.channels; ++c) {
      const double value = model.params()[param.slot + c];
      if (!param.AtBound(value)) continue;
      bound = param.Displayed(value);
      channels += std::string(count++ ? ", " : "") + "rgb"[c];
    }
    if (count == 0) continue;
    if (!text.empty()) text += "; ";
    text += param.name + (param.channels > 1 ? " (" + channels + ")" : "") + " = " +
            FormatNumber(bound);
  }
  return text;
}

}  // namespace

nlohmann::json FitReportJson(const FitResult& fit, const std::string& source,
                             const Selection* selection) {
  nlohmann::json json;
  json["model"] = fit.model.name();
  json["model_string"] = fit.model.ToString();
  for (const ParamInfo& param : fit.model.info().params) {
    json["params"][param.name] = ParamJson(param, fit.model.params());
    json["stderr"][param.name] = ParamJson(param, fit.stderr_values);
  }
  if (!fit.stderr_available) json["stderr_note"] = fit.stderr_note;
  json["metrics"] = {{"rmse", fit.metrics.rmse},
                     {"log_rmse", fit.metrics.log_rmse},
                     {"cosine_l2", fit.metrics.cosine_l2}};
  json["loss"] = LossName(fit.loss);
  json["robust"] = RobustName(fit.robust);
  json["samples"] = fit.samples;
  json["skipped"] = fit.skipped;
  json["weighting"] = fit.weighting;
  json["converged"] = fit.converged;
  json["iterations"] = fit.iterations;
  json["time_s"] = fit.time_s;
  json["bic"] = fit.bic;
  json["termination"] = fit.termination;
  const EnergyCheck& energy = fit.energy;
  json["energy"] = {{"max_albedo", RgbJson(energy.max_albedo)},
                    {"albedo_error", RgbJson(energy.albedo_error)},
                    {"theta_deg_at_max", energy.theta_deg_at_max},
                    {"bound", RgbJson(energy.bound)},
                    {"verdict", energy.verdict.name()},
                    {"reason", energy.verdict.reason},
                    {"method", energy.method}};
  json["warnings"] = fit.warnings;
  json["source"] = source;
  if (selection != nullptr) {
    nlohmann::json candidates = nlohmann::json::array();
    for (const CandidateScore& candidate : selection->candidates) {
      candidates.push_back({{"model", candidate.model},
                            {"bic", candidate.bic},
                            {"rmse", candidate.rmse},
                            {"loss_rms", candidate.loss_rms},
                            {"free_variables", candidate.free_variables},
                            {"converged", candidate.converged}});
      if (std::isfinite(candidate.image_error)) {
        candidates.back()["image_error"] = candidate.image_error;
      }
    }
    json["selection"] = {{"criterion", selection->criterion},
                         {"chosen", selection->chosen},
                         {"reason", selection->reason},
                         {"candidates", candidates}};
  }
  return json;
}

void PrintFitReport(std::ostream& out, const FitResult& fit, const std::string& source,
                    const Selection* selection) {
  out << "source      " << source << "\n";
  // Seven significant digits: as many as a person reads, and the string reproduces the fit to
  // them (brdf render/energy accept it as it is printed).
  out << "model       " << fit.model.name() << "   (" << fit.model.ToString(kShownDigits) << ")\n";
  if (selection != nullptr) {
    out << "selection   " << selection->reason << "\n";
    for (const CandidateScore& candidate : selection->candidates) {
      const std::string image = std::isfinite(candidate.image_error)
                                    ? Format("  image error %.4g", candidate.image_error)
                                    : std::string();
      out << Format("            %-18s BIC %-14.8g rmse %-10.4g loss rms %.4g%s%s\n",
                    candidate.model.c_str(), candidate.bic, candidate.rmse, candidate.loss_rms,
                    image.c_str(), candidate.converged ? "" : "  (not converged)");
    }
  }
  out << "parameter   value (r g b)                           ± standard error\n";
  for (const ParamInfo& param : fit.model.info().params) {
    out << Format("%-11s %-39s ± %s\n", param.name.c_str(),
                  Numbers(param, fit.model.params(), true).c_str(),
                  fit.stderr_available ? Numbers(param, fit.stderr_values, false).c_str() : "n/a");
  }
  if (!fit.stderr_available) out << "stderr      " << fit.stderr_note << "\n";
  const std::string at_bound = AtBoundList(fit.model);
  if (!at_bound.empty()) {
    out << "at bound    " << at_bound
        << ": pinned at the end of the model's range (the data ask for no more of it)\n";
  }
  out << Format("metrics     rmse %.6g sr^-1, log_rmse %.6g, cosine_l2 %.6g (%s loss, robust %s)\n",
                fit.metrics.rmse, fit.metrics.log_rmse, fit.metrics.cosine_l2, LossName(fit.loss),
                RobustName(fit.robust));
  out << "samples     " << fit.samples << " fitted, " << fit.skipped << " missing or invalid; "
      << fit.weighting << "\n";
  out << Format("solve       %s, %d iterations, %.3f s\n",
                fit.converged ? "converged" : "NOT CONVERGED", fit.iterations, fit.time_s);
  out << Format("energy      max albedo %.4f %.4f %.4f (integrated; bound %.4f %.4f %.4f): %s\n",
                fit.energy.max_albedo[0], fit.energy.max_albedo[1], fit.energy.max_albedo[2],
                fit.energy.bound[0], fit.energy.bound[1], fit.energy.bound[2],
                fit.energy.verdict.Text().c_str());
  for (const std::string& warning : fit.warnings) out << "warning     " << warning << "\n";
}

}  // namespace brdf::fitters
