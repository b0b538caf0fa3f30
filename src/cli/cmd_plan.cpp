// brdf plan --model MODEL|FIT.json --budget N [--instrument J] [--constraints K=V,...]
// [--criterion d|a|param:NAME] [--candidates SCHEDULE] [--json] [--quiet] --out plan.csv:
// a measurement schedule of N direction pairs chosen to minimise the fitted parameters'
// variance (DESIGN §3; docs/planning.md). The design is fitters/experiment_design.h, weighted
// by the virtual instrument's noise model (gonio/measure.h) and predicting every reading through
// the instrument's apertures as `brdf fit` will (fitters/reading_nodes.h); `brdf measure
// --schedule file:plan.csv` measures it.
#include <tbb/parallel_for.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/commands.h"
#include "core/angles.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/progress.h"
#include "core/text.h"
#include "fitters/experiment_design.h"
#include "fitters/fit_samples.h"
#include "fitters/reading_nodes.h"
#include "gonio/instrument.h"
#include "gonio/measure.h"
#include "gonio/model_sample.h"
#include "gonio/schedule.h"
#include "models/model_source.h"

namespace brdf::cli {
namespace {

constexpr const char* kDefaultCandidates = "adaptive:theta_i_step=2.5:base_step=5";

struct Constraints {
  double theta_max_deg = gonio::kUniformThetaMaxDeg;
  double min_separation_deg = 0;
};

Constraints ParseConstraints(const std::string& text) {
  Constraints constraints;
  if (text.empty()) return constraints;
  std::map<std::string, bool> seen;
  for (std::string_view part : SplitFields(text, ",", false)) {
    part = Trim(part);
    const size_t equals = part.find('=');
    if (equals == std::string_view::npos) {
      throw UsageError("--constraints: expected key=value, found '" + std::string(part) + "'");
    }
    const std::string key(Trim(part.substr(0, equals)));
    const std::string value_text(Trim(part.substr(equals + 1)));
    if (key != "theta_max" && key != "min_separation_deg") {
      throw UsageError("--constraints: unknown key '" + key +
                       "' (known: theta_max, min_separation_deg)");
    }
    double value = 0;
    std::istringstream stream(value_text);
    if (!(stream >> value) || !stream.eof() || !std::isfinite(value)) {
      throw UsageError("--constraints: " + key + " needs a number, found '" + value_text + "'");
    }
    if (seen[key]) throw UsageError("--constraints: " + key + " given twice");
    seen[key] = true;
    if (key == "theta_max") {
      if (!(value > 0 && value <= 89.9)) {
        throw UsageError("--constraints: theta_max=" + value_text +
                         " is impossible: it must lie in (0, 89.9] degrees");
      }
      constraints.theta_max_deg = value;
    } else if (key == "min_separation_deg") {
      if (!(value >= 0 && value <= 90)) {
        throw UsageError("--constraints: min_separation_deg=" + value_text +
                         " is impossible: it must lie in [0, 90] degrees");
      }
      constraints.min_separation_deg = value;
    }
  }
  return constraints;
}

// The geometries of `schedule` the instrument can take (the detector arm does not shadow the
// beam) with both polar angles at most `theta_max_deg`, with the sigma it will state. With a
// `budget`, the candidates of a plan: none, or fewer than the budget, is a usage error.
std::vector<fitters::DesignPoint> Geometries(const gonio::Schedule& schedule,
                                             const gonio::Instrument& instrument,
                                             const gonio::NoiseModel& noise, double theta_max_deg,
                                             size_t budget = 0) {
  const double cos_blocked = std::cos(DegToRad(instrument.blocked_within_deg));
  const double cos_max = std::cos(DegToRad(theta_max_deg)) - 1e-12;
  std::vector<fitters::DesignPoint> points;
  for (const gonio::Incidence& incidence : schedule.incidences) {
    if (incidence.wi.z() < cos_max) continue;
    for (const gonio::Detector& detector : incidence.detectors) {
      if (detector.wo.z() < cos_max || incidence.wi.dot(detector.wo) > cos_blocked) continue;
      points.push_back({incidence.wi, detector.wo, Rgb::Ones()});
    }
  }
  if (budget > 0 && points.empty()) {
    throw UsageError("impossible constraint set: no candidate of '" + schedule.spec +
                     "' has both polar angles at most theta_max=" + FormatNumber(theta_max_deg) +
                     " deg and the detector at least " +
                     FormatNumber(instrument.blocked_within_deg) + " deg from the beam");
  }
  if (budget > points.size()) {
    throw UsageError("--budget " + std::to_string(budget) + " is larger than the candidate set (" +
                     std::to_string(points.size()) +
                     " geometries within the constraints): lower it or widen the candidates");
  }
  tbb::parallel_for(size_t{0}, points.size(), [&](size_t k) {
    points[k].sigma = noise.Sigma(points[k].wi, points[k].wo);
    // The arms' jitter enters the prediction through ExpectedNoise, shared by the readings it
    // moves together; the independent part is the detector's counts alone.
    points[k].independent_sigma = noise.CountSigma(points[k].wi, points[k].wo);
  });
  return points;
}

// A noise-free measurement of `model` at `points` with their sigma: what PredictErrors weighs.
Measurement Predicted(const Model& model, const std::vector<fitters::DesignPoint>& points,
                      bool designed, const gonio::Instrument& instrument) {
  Measurement measurement;
  measurement.source = "predicted";
  // Read through the instrument, as `brdf fit` reads the measurement `brdf measure` makes.
  measurement.metadata[fitters::kInstrumentKey] = instrument.ToJson();
  for (const fitters::DesignPoint& point : points) {
    measurement.samples.push_back({point.wi, point.wo, model.Eval(point.wi, point.wo), false});
    measurement.sigma.push_back(point.sigma);
  }
  if (designed) measurement.metadata[kWeightingKey] = kEqualWeighting;
  return measurement;
}

// The predicted standard errors of a fit to a measurement at `points`.
fitters::PredictedErrors PredictFit(const Model& model,
                                    const std::vector<fitters::DesignPoint>& points, bool designed,
                                    const gonio::Instrument& instrument,
                                    const gonio::NoiseModel& noise) {
  return fitters::PredictErrors(
      model, Predicted(model, points, designed, instrument),
      fitters::ExpectedNoiseAt(points, noise.CommonScaleVariance(), noise.LightArmVariance(),
                               noise.DetectorArmVariance()));
}

struct Comparison {
  std::string name, schedule;
  size_t count = 0;
  double log_det = 0;
  fitters::PredictedErrors errors;
};

std::string Number(double value) {
  if (!std::isfinite(value)) return "n/a";
  return FormatNumber(value, 3);
}

nlohmann::json JsonNumber(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

void PrintTable(const Model& model, const std::vector<Comparison>& rows, std::ostream& out) {
  out << "predicted standard errors of a fit (relative to the value in brackets):\n";
  out << std::left << std::setw(12) << "parameter";
  for (const Comparison& row : rows) {
    out << std::setw(26) << (row.name + " (" + std::to_string(row.count) + ")");
  }
  out << "\n";
  const std::vector<double>& params = model.params();
  for (const ParamInfo& param : model.info().params) {
    for (int c = 0; c < param.channels; ++c) {
      const int p = param.slot + c;
      out << std::setw(12)
          << (param.name + (param.channels == 3 ? std::string("[") + "RGB"[c] + "]" : ""));
      for (const Comparison& row : rows) {
        const double error = row.errors.stderr_values[p];
        const std::string relative =
            params[p] != 0 && std::isfinite(error) ? Number(100 * error / params[p]) + "%" : "";
        out << std::setw(26) << (Number(error) + (relative.empty() ? "" : " [" + relative + "]"));
      }
      out << "\n";
    }
  }
  out << std::setw(12) << "log det";
  for (const Comparison& row : rows) out << std::setw(26) << Number(row.log_det);
  out << "\n";
  for (const Comparison& row : rows) {
    if (!row.errors.note.empty()) out << row.name << ": " << row.errors.note << "\n";
  }
}

}  // namespace

Command AddPlanCommand(CLI::App& parent) {
  struct Options {
    std::string model, instrument, constraints, criterion = "d", candidates = kDefaultCandidates,
                                                out;
    int budget = 0;
    bool json = false, quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "plan",
      "Choose the direction pairs a measurement should visit so the fitted parameters come "
      "out with the smallest variance (optimal experimental design)");
  app->footer(
      "The plan is a CSV of theta_i,phi_i,theta_o,phi_o (degrees) in the order chosen: its "
      "first K rows are the plan for a budget of K. Measure it with 'brdf measure --schedule "
      "file:PLAN.csv'. See docs/planning.md.");
  app->add_option(
         "--model", options->model,
         "the material to plan for: a model string (e.g. ggx:rho_d=0.1:f0=0.04:alpha=0.05) "
         "or a fit report of a first measurement (FIT.json)")
      ->required();
  app->add_option("--budget", options->budget, "direction pairs to choose")
      ->required()
      ->check(CLI::Range(1, 10000000));
  app->add_option("--instrument", options->instrument,
                  "instrument JSON whose noise model weights the readings (default: brdf "
                  "measure's instrument)");
  app->add_option("--constraints", options->constraints,
                  "comma-separated key=value: theta_max (deg, both polar angles, default 85), "
                  "min_separation_deg (two chosen geometries differ by at least this in "
                  "incidence or detector direction, default 0)");
  app->add_option("--criterion", options->criterion,
                  "d (maximise det of the information), a (minimise the sum of squared relative "
                  "standard errors) or param:NAME (one parameter's, e.g. param:alpha for a sharp "
                  "lobe's width, at some cost to the others)")
      ->capture_default_str();
  app->add_option("--candidates", options->candidates,
                  "the geometries to choose from, as a brdf measure schedule (e.g. "
                  "hemisphere:theta_i_step=2 or file:CANDIDATES.csv)")
      ->capture_default_str();
  app->add_flag("--json", options->json, "print the comparison as JSON instead of the table");
  app->add_flag("--quiet", options->quiet, "no progress on stderr");
  app->add_option("--out", options->out, "the plan (CSV)")->required();

  return {app, [options]() {
            const Model model = LoadModel(options->model);
            const Constraints constraints = ParseConstraints(options->constraints);
            fitters::DesignOptions design = fitters::ParseCriterion(options->criterion, model);
            design.budget = options->budget;
            design.min_separation_deg = constraints.min_separation_deg;
            gonio::Instrument instrument;
            if (!options->instrument.empty()) {
              instrument = gonio::ReadInstrument(options->instrument);
            }
            instrument.Validate();
            std::vector<std::string> warnings = fitters::DesignWarnings(model);
            const std::string blur = fitters::ApertureBlurWarning(instrument, model);
            if (!blur.empty()) warnings.push_back(blur);
            for (const std::string& warning : warnings) {
              std::cerr << "brdf plan: warning: " << warning << "\n";
            }

            const gonio::ModelSample sample(model, instrument);
            const gonio::NoiseModel noise(sample, instrument);
            const gonio::Schedule candidate_schedule = gonio::MakeSchedule(options->candidates);
            Progress progress("planning", 4, options->quiet || options->json);
            const std::vector<fitters::DesignPoint> candidates =
                Geometries(candidate_schedule, instrument, noise, constraints.theta_max_deg,
                           static_cast<size_t>(options->budget));
            progress.Advance();
            const fitters::DesignResult result =
                fitters::ChooseDesign(model, candidates, design, &instrument);
            progress.Advance();
            std::vector<fitters::DesignPoint> plan;
            for (size_t k : result.chosen) plan.push_back(candidates[k]);

            // The comparisons: the same count spread uniformly, and brdf measure's default.
            const double theta_max = constraints.theta_max_deg;
            std::vector<fitters::DesignPoint> uniform;
            for (size_t count = plan.size(); uniform.size() < plan.size(); ++count) {
              gonio::Schedule schedule;
              for (const auto& [wi, wo] : gonio::UniformPairs(static_cast<int>(count), theta_max)) {
                if (schedule.incidences.empty() || schedule.incidences.back().wi != wi) {
                  schedule.incidences.push_back({wi, {}});
                }
                schedule.incidences.back().detectors.push_back({wo, 0});
              }
              uniform = Geometries(schedule, instrument, noise, 90);
            }
            const gonio::Schedule default_schedule = gonio::MakeSchedule("hemisphere");
            const std::vector<fitters::DesignPoint> standard =
                Geometries(default_schedule, instrument, noise, 90);
            progress.Advance();
            std::vector<Comparison> rows = {
                {"plan", "file:" + options->out, plan.size(), result.log_det, {}},
                {"uniform",
                 "uniform:count=" + std::to_string(uniform.size()) +
                     ":theta_max=" + FormatNumber(theta_max),
                 uniform.size(),
                 fitters::InformationLogDet(model, uniform, &instrument),
                 {}},
                {"default",
                 "hemisphere",
                 standard.size(),
                 fitters::InformationLogDet(model, standard, &instrument),
                 {}}};
            rows[0].errors = PredictFit(model, plan, true, instrument, noise);
            rows[1].errors = PredictFit(model, uniform, false, instrument, noise);
            rows[2].errors = PredictFit(model, standard, false, instrument, noise);
            progress.Advance();

            WriteFileAtomically(options->out, [&](std::ostream& out) {
              out << "# brdfkit plan v1\n";
              out << "# model: " << model.ToString() << "\n";
              out << "# criterion: " << options->criterion << "\n";
              out << "# instrument: "
                  << (options->instrument.empty() ? "default" : options->instrument) << "\n";
              out << "# constraints: theta_max=" << FormatNumber(constraints.theta_max_deg)
                  << ",min_separation_deg=" << FormatNumber(constraints.min_separation_deg) << "\n";
              out << "# candidates: " << options->candidates << " (" << candidates.size()
                  << " geometries)\n";
              out << "# rows are in the order chosen: the first K are the plan for a budget of K\n";
              out << "theta_i,phi_i,theta_o,phi_o,order\n";
              for (size_t k = 0; k < plan.size(); ++k) {
                const DegreesText wi = DirectionDegreesText(plan[k].wi);
                const DegreesText wo = DirectionDegreesText(plan[k].wo);
                out << wi.theta << "," << wi.phi << "," << wo.theta << "," << wo.phi << "," << k + 1
                    << "\n";
              }
            });

            if (options->json) {
              nlohmann::json report;
              report["model"] = model.ToString();
              report["criterion"] = options->criterion;
              report["budget"] = options->budget;
              report["candidates"] = candidates.size();
              report["out"] = options->out;
              report["warnings"] = warnings;
              nlohmann::json schedules = nlohmann::json::object();
              for (const Comparison& row : rows) {
                nlohmann::json entry;
                entry["schedule"] = row.schedule;
                entry["geometries"] = row.count;
                entry["log_det"] = JsonNumber(row.log_det);
                entry["stderr_available"] = row.errors.available;
                if (!row.errors.note.empty()) entry["note"] = row.errors.note;
                nlohmann::json errors = nlohmann::json::object();
                for (const ParamInfo& param : model.info().params) {
                  if (param.channels == 1) {
                    errors[param.name] = JsonNumber(row.errors.stderr_values[param.slot]);
                  } else {
                    nlohmann::json channels = nlohmann::json::array();
                    for (int c = 0; c < param.channels; ++c) {
                      channels.push_back(JsonNumber(row.errors.stderr_values[param.slot + c]));
                    }
                    errors[param.name] = channels;
                  }
                }
                entry["stderr"] = errors;
                schedules[row.name] = entry;
              }
              report["schedules"] = schedules;
              std::cout << report.dump(2) << "\n";
              return 0;
            }
            {
              std::cout << "wrote " << options->out << " (" << plan.size() << " of "
                        << candidates.size() << " candidate geometries, criterion "
                        << options->criterion << ")\n";
              PrintTable(model, rows, std::cout);
            }
            return 0;
          }};
}

}  // namespace brdf::cli
