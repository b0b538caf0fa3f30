#include "fitters/experiment_design.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <queue>
#include <tuple>

#include "core/angles.h"
#include "core/errors.h"
#include "core/sampling.h"
#include "core/text.h"
#include "fitters/covariance.h"
#include "fitters/fit.h"
#include "fitters/fit_samples.h"
#include "fitters/reading_nodes.h"

namespace brdf::fitters {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The ridge that makes the first choices possible (the information of one reading is rank 3
// at most), relative to a candidate's mean information per variable.
constexpr double kRidge = 1e-6;
// M^-1 is rebuilt from M (not updated) every this many choices, against rounding drift; the
// trace criteria's lazy gains are also all refreshed then.
constexpr int kFullRefresh = 64;
// Two geometries closer than this (radians) in both directions are the same geometry.
constexpr double kSameGeometry = 1e-6;

// The fitter's variables at `model`'s parameters and which of them a fit holds out.
// The design's fit is the default one (FitOptions: L2 loss, one variable per channel).
template <typename M>
struct DesignState {
  FitOptions fit_options;
  std::vector<double> v;
  std::vector<bool> held;
  std::vector<int> free;  // indices of the variables not held
  std::string held_note;
  // d params / d variables at v.
  Eigen::MatrixXd gradients;

  explicit DesignState(const Model& model) : v(ParamsToVariables<M>(model.params().data())) {
    held = HeldVariables<M>(fit_options.grey_specular, v, &held_note);
    for (size_t k = 0; k < v.size(); ++k) {
      if (!held[k]) free.push_back(static_cast<int>(k));
    }
    const std::vector<FitSample> none;
    const FitObjective<M> objective(none, fit_options.loss, fit_options.grey_specular);
    gradients = ParamGradients<M>(objective.At(v.data()), static_cast<int>(v.size()));
  }
  // The fit's objective over `samples`, through `nodes` when given (reading_nodes.h).
  FitObjective<M> Objective(const std::vector<FitSample>& samples,
                            const SampleNodes* nodes = nullptr) const {
    return FitObjective<M>(samples, fit_options.loss, fit_options.grey_specular,
                           FitObjective<M>::kDefaultBatch, nodes);
  }
};

// The fitter's samples for `points` with residual multipliers 1/sigma: their Jacobian rows are
// the whitened sensitivities whose outer products sum to the information.
std::vector<FitSample> WhitenedSamples(const Model& model, const std::vector<DesignPoint>& points) {
  std::vector<FitSample> samples(points.size());
  for (size_t k = 0; k < points.size(); ++k) {
    FitSample& sample = samples[k];
    sample.wi = points[k].wi;
    sample.wo = points[k].wo;
    sample.value = model.Eval(sample.wi, sample.wo);
    for (int c = 0; c < 3; ++c) {
      const double sigma = points[k].sigma[c];
      if (!(sigma > 0) || !std::isfinite(sigma)) {
        throw UsageError("the reading at theta_i=" + FormatNumber(RadToDeg(Theta(sample.wi)), 4) +
                         ", theta_o=" + FormatNumber(RadToDeg(Theta(sample.wo)), 4) +
                         " deg has no noise (sigma " + FormatNumber(sigma) +
                         "): its information is unbounded; give the instrument a photon budget "
                         "or positioning jitter");
      }
      sample.scale[c] = 1.0 / sigma;
    }
  }
  return samples;
}

// U_k (free variables x 3 channels) of every point, stacked: column 3 k + c.
template <typename M>
Eigen::MatrixXd Sensitivities(const DesignState<M>& state, const Model& model,
                              const std::vector<DesignPoint>& points,
                              const gonio::Instrument* instrument) {
  const std::vector<FitSample> samples = WhitenedSamples(model, points);
  const SampleNodes nodes =
      instrument != nullptr ? InstrumentNodes(*instrument, model, samples) : SampleNodes{};
  const FitObjective<M> objective =
      state.Objective(samples, instrument != nullptr ? &nodes : nullptr);
  const int m = static_cast<int>(state.free.size());
  Eigen::MatrixXd u(m, 3 * static_cast<Eigen::Index>(points.size()));
  objective.ForEachRow(objective.At(state.v.data()),
                       [&](int64_t row, const Eigen::VectorXd& jacobian, double) {
                         for (int i = 0; i < m; ++i) u(i, row) = jacobian[state.free[i]];
                       });
  return u;
}

// Rows c_p = (d param_p / d free variables) / param_p of the parameters a trace criterion sums.
template <typename M>
Eigen::MatrixXd CriterionRows(const DesignState<M>& state, const Model& model,
                              const DesignOptions& options) {
  const Eigen::MatrixXd& gradients = state.gradients;
  std::vector<Eigen::VectorXd> rows;
  const ModelInfo& info = model.info();
  for (const ParamInfo& param : info.params) {
    if (options.criterion == DesignCriterion::kParam && param.name != options.param) continue;
    for (int c = 0; c < param.channels; ++c) {
      const int p = param.slot + c;
      bool depends_on_held = false;
      for (size_t k = 0; k < state.held.size(); ++k) {
        depends_on_held = depends_on_held || (state.held[k] && gradients(p, k) != 0);
      }
      const double value = model.params()[p];
      if (depends_on_held || !(std::abs(value) > 0)) continue;
      Eigen::VectorXd row(state.free.size());
      for (size_t i = 0; i < state.free.size(); ++i) row[i] = gradients(p, state.free[i]) / value;
      rows.push_back(row);
    }
  }
  if (rows.empty()) {
    throw UsageError(options.criterion == DesignCriterion::kParam
                         ? "criterion param:" + options.param + ": " + options.param +
                               " is at a bound of " + model.name() +
                               " (see the warnings): no plan can inform it"
                         : "every parameter of " + model.ToString(6) +
                               " is at a bound: there is nothing to plan for");
  }
  Eigen::MatrixXd c(rows.size(), state.free.size());
  for (size_t r = 0; r < rows.size(); ++r) c.row(r) = rows[r].transpose();
  return c;
}

bool Conflicts(const DesignPoint& a, const DesignPoint& b, double cos_separation) {
  return a.wi.dot(b.wi) > cos_separation && a.wo.dot(b.wo) > cos_separation;
}

template <typename M>
DesignResult Choose(const Model& model, const std::vector<DesignPoint>& candidates,
                    const DesignOptions& options, const gonio::Instrument* instrument) {
  const DesignState<M> state(model);
  const int m = static_cast<int>(state.free.size());
  if (m == 0) {
    throw UsageError("every parameter of " + model.ToString(6) +
                     " is at a bound: there is nothing to plan for");
  }
  const size_t budget = static_cast<size_t>(options.budget);
  if (options.budget < 1) {
    throw UsageError("the measurement budget must be at least 1 geometry, got " +
                     std::to_string(options.budget));
  }
  if (budget > candidates.size()) {
    throw UsageError("the measurement budget (" + std::to_string(budget) +
                     " geometries) is larger than the candidate set (" +
                     std::to_string(candidates.size()) +
                     " geometries within the constraints): lower it or widen the candidates");
  }
  const bool trace = options.criterion != DesignCriterion::kD;
  const Eigen::MatrixXd c = trace ? CriterionRows(state, model, options) : Eigen::MatrixXd();
  const Eigen::MatrixXd u = Sensitivities(state, model, candidates, instrument);
  const auto block = [&](size_t k) { return u.middleCols(3 * static_cast<Eigen::Index>(k), 3); };

  const double mean_information = u.squaredNorm() / (static_cast<double>(candidates.size()) * m);
  Eigen::MatrixXd information = Eigen::MatrixXd::Identity(m, m) * kRidge * mean_information;
  Eigen::MatrixXd inverse = information.inverse();

  // The gain of candidate k at the current design.
  const auto gain = [&](size_t k) {
    const auto uk = block(k);
    const Eigen::MatrixXd inverse_u = inverse * uk;
    const Eigen::Matrix3d s = Eigen::Matrix3d::Identity() + uk.transpose() * inverse_u;
    if (!trace) return std::log(s.determinant());
    const Eigen::MatrixXd projected = c * inverse_u;  // rows x 3
    return (projected * s.llt().solve(projected.transpose())).trace();
  };

  // Lazy greedy: (gain, -index) so that ties go to the lower index; `stamp` is the step at which
  // the gain was computed.
  using Entry = std::tuple<double, int64_t, size_t>;  // gain, -index, stamp
  std::priority_queue<Entry> queue;
  for (size_t k = 0; k < candidates.size(); ++k) {
    queue.emplace(gain(k), -static_cast<int64_t>(k), 0);
  }
  std::vector<char> excluded(candidates.size(), 0);
  const double cos_separation =
      std::cos(std::max(DegToRad(options.min_separation_deg), kSameGeometry));
  DesignResult result;
  size_t step = 0;
  while (result.chosen.size() < budget) {
    if (queue.empty()) {
      throw UsageError(
          "the constraints leave room for only " + std::to_string(result.chosen.size()) +
          " geometries of the " + std::to_string(candidates.size()) +
          " candidates at min_separation_deg=" + FormatNumber(options.min_separation_deg) +
          "; a measurement budget of " + std::to_string(budget) +
          " geometries needs a smaller separation, wider candidates or a smaller budget");
    }
    const auto [value, negative_index, stamp] = queue.top();
    queue.pop();
    const size_t k = static_cast<size_t>(-negative_index);
    if (excluded[k]) continue;
    if (stamp != step) {
      queue.emplace(gain(k), negative_index, step);
      continue;
    }
    // Accept k: Woodbury update of M^-1, exclusion of its neighbours.
    const auto uk = block(k);
    information += uk * uk.transpose();
    const Eigen::MatrixXd inverse_u = inverse * uk;
    const Eigen::Matrix3d s = Eigen::Matrix3d::Identity() + uk.transpose() * inverse_u;
    inverse -= inverse_u * s.llt().solve(inverse_u.transpose());
    result.chosen.push_back(k);
    for (size_t j = 0; j < candidates.size(); ++j) {
      if (!excluded[j] && Conflicts(candidates[k], candidates[j], cos_separation)) excluded[j] = 1;
    }
    ++step;
    if (step % kFullRefresh == 0) {
      inverse = information.llt().solve(Eigen::MatrixXd::Identity(m, m));
      if (trace) {  // not submodular: stale gains are no bound, so recompute them all
        std::priority_queue<Entry> fresh;
        while (!queue.empty()) {
          const size_t j = static_cast<size_t>(-std::get<1>(queue.top()));
          queue.pop();
          if (!excluded[j]) fresh.emplace(gain(j), -static_cast<int64_t>(j), step);
        }
        queue.swap(fresh);
      }
    }
  }
  Eigen::MatrixXd chosen_information = Eigen::MatrixXd::Zero(m, m);
  for (size_t k : result.chosen) chosen_information += block(k) * block(k).transpose();
  const Eigen::LLT<Eigen::MatrixXd> llt(chosen_information);
  result.log_det = -kInf;
  if (llt.info() == Eigen::Success) {
    result.log_det = 2 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
  }
  return result;
}

template <typename M>
double LogDet(const Model& model, const std::vector<DesignPoint>& points,
              const gonio::Instrument* instrument) {
  const DesignState<M> state(model);
  const int m = static_cast<int>(state.free.size());
  if (m == 0 || points.empty()) return -kInf;
  const Eigen::MatrixXd u = Sensitivities(state, model, points, instrument);
  const Eigen::MatrixXd information = u * u.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(information);
  const Eigen::VectorXd values = eigen.eigenvalues();
  if (!(values.minCoeff() > kRankTolerance * values.maxCoeff())) return -kInf;
  return values.array().log().sum();
}

template <typename M>
PredictedErrors Predict(const Model& model, const Measurement& measurement,
                        const ExpectedNoise& noise) {
  DesignState<M> state(model);
  const PreparedSamples prepared = PrepareSamples(measurement);
  if (prepared.samples.size() != measurement.samples.size() || !measurement.has_sigma()) {
    throw UsageError("a predicted fit needs every geometry above the horizon, with its sigma");
  }
  const bool split = !noise.independent_sigma.empty();
  if (split && noise.independent_sigma.size() != measurement.samples.size()) {
    throw UsageError("a predicted fit needs one independent sigma per sample");
  }
  // E[r^2] of sample k's channel c: (scale_c sigma_c)^2 with the sigma that differs from reading
  // to reading; the multiplier scale_c weighs by the stated sigma, as the fit does.
  const std::vector<Rgb>& independent = split ? noise.independent_sigma : measurement.sigma;
  std::vector<double> expected(3 * prepared.samples.size());
  for (size_t k = 0; k < prepared.samples.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      expected[3 * k + c] = std::pow(prepared.samples[k].scale[c] * independent[k][c], 2);
    }
  }
  // Through the instrument the measurement records, as the fit will read it.
  const SampleNodes nodes = prepared.instrument != nullptr
                                ? InstrumentNodes(*prepared.instrument, model, prepared.samples)
                                : SampleNodes{};
  const FitObjective<M> objective =
      state.Objective(prepared.samples, prepared.instrument != nullptr ? &nodes : nullptr);
  const typename FitObjective<M>::Point at = objective.At(state.v.data());
  NormalSums sums = objective.Sums(at, &expected);
  sums.Symmetric();
  Eigen::MatrixXd& a = sums.a;
  Eigen::MatrixXd& b = sums.b;
  Eigen::MatrixXd covariance;
  if (noise.common_scale_variance > 0) {
    // Every value times (1 + e): the residuals change by -scale f e, the variables by
    // A^-1 g e with g = sum J^T scale f, which adds var(e) g g^T to B.
    Eigen::VectorXd g = Eigen::VectorXd::Zero(a.rows());
    const auto shared = objective.Prepare(at);
    objective.ForEachRow(at, [&](int64_t row, const Eigen::VectorXd& jacobian, double) {
      const FitSample& sample = prepared.samples[row / 3];
      const int c = static_cast<int>(row % 3);
      // The reading as the model predicts it (the noise-free value).
      const double value = objective.Value(at, shared, static_cast<size_t>(row / 3))[c];
      g += jacobian * (sample.scale[c] * value);
    });
    b += noise.common_scale_variance * g * g.transpose();
  }
  // Derivatives of every sample's channels when one arm turns by (a, b) s about its nominal
  // direction (the light arm turns wi, the detector arm wo) along the axes of that direction's
  // frame, by differences one s wide, through the instrument as the fit predicts: d[0], d[1]
  // the slopes times s, d[2], d[3], d[4] the Hessian's xx, yy, xy times s².
  const std::vector<FitSample>& samples = prepared.samples;
  // The readings with one arm (the detector's, or else the light's) turned by (a, b) s.
  const auto turned_values = [&](bool detector, double s, double a, double b) {
    std::vector<FitSample> turned = samples;
    for (FitSample& sample : turned) {
      Vec3& w = detector ? sample.wo : sample.wi;
      const Frame frame = Frame::FromZ(w);
      w = (w + s * (a * frame.x + b * frame.y)).normalized();
    }
    const SampleNodes turned_nodes = prepared.instrument != nullptr
                                         ? InstrumentNodes(*prepared.instrument, model, turned)
                                         : SampleNodes{};
    std::vector<Rgb> value(samples.size());
    for (size_t k = 0; k < samples.size(); ++k) {
      value[k] = turned[k].wi.z() > 0 && turned[k].wo.z() > 0
                     ? PredictReading(model, turned,
                                      prepared.instrument != nullptr ? &turned_nodes : nullptr, k)
                     : Rgb(Rgb::Zero());
    }
    return value;
  };
  // Unturned: the centre of both arms' differences.
  const std::vector<Rgb> centre = noise.light_arm_variance > 0 || noise.detector_arm_variance > 0
                                      ? turned_values(false, 0.0, 0.0, 0.0)
                                      : std::vector<Rgb>();
  const auto arm_derivatives = [&](bool detector, double s, std::vector<Rgb>* d) {
    const auto turned = [&](double a, double b) { return turned_values(detector, s, a, b); };
    const std::vector<Rgb> px = turned(1, 0), mx = turned(-1, 0), py = turned(0, 1),
                           my = turned(0, -1);
    for (int j = 0; j < 5; ++j) d[j].assign(samples.size(), Rgb::Zero());
    for (size_t k = 0; k < samples.size(); ++k) {
      d[0][k] = 0.5 * (px[k] - mx[k]);
      d[1][k] = 0.5 * (py[k] - my[k]);
    }
    const std::vector<Rgb> pp = turned(1, 1), pm = turned(1, -1), mp = turned(-1, 1),
                           mm = turned(-1, -1);
    for (size_t k = 0; k < samples.size(); ++k) {
      d[2][k] = px[k] - 2 * centre[k] + mx[k];
      d[3][k] = py[k] - 2 * centre[k] + my[k];
      d[4][k] = 0.25 * (pp[k] - pm[k] - mp[k] + mm[k]);
    }
  };
  // An arm's turn e (per axis N(0, s²)) shared by a group of rows changes their residuals by
  // -scale (g.e + e^T H e / 2), the variables by A^-1 times the sum over the group of
  // J^T scale (...): with h_j = sum J^T scale d_j, B gains h_0 h_0^T + h_1 h_1^T (first order)
  // and (h_xx h_xx^T + h_yy h_yy^T + 2 h_xy h_xy^T) / 2 (second order: cov(e^T P e, e^T Q e)
  // = 2 s^4 tr(PQ)). d is already scaled by s and s², so no further factor.
  const auto add_group = [&](const std::vector<Eigen::VectorXd>& h) {
    b += h[0] * h[0].transpose() + h[1] * h[1].transpose();
    b += 0.5 * (h[2] * h[2].transpose() + h[3] * h[3].transpose()) + h[4] * h[4].transpose();
  };
  if (noise.light_arm_variance > 0) {
    // The light arm turns the incidence once for all the readings of that incidence (samples of
    // equal wi, in order of first appearance).
    std::vector<Rgb> d[5];
    arm_derivatives(/*detector=*/false, std::sqrt(noise.light_arm_variance), d);
    int count = 0;
    const std::vector<int> group = IncidenceGroups(samples, &count);
    std::vector<std::vector<Eigen::VectorXd>> h(
        count, std::vector<Eigen::VectorXd>(5, Eigen::VectorXd::Zero(a.rows())));
    objective.ForEachRow(at, [&](int64_t row, const Eigen::VectorXd& jacobian, double) {
      const size_t k = static_cast<size_t>(row / 3);
      const int c = static_cast<int>(row % 3);
      for (int j = 0; j < 5; ++j) h[group[k]][j] += jacobian * (samples[k].scale[c] * d[j][k][c]);
    });
    for (const auto& group : h) add_group(group);
  }
  if (noise.detector_arm_variance > 0) {
    // The detector arm turns each reading's wo by its own e_k, which moves the reading's three
    // channels together: a group per reading (not the per-channel sum of squares an
    // independent sigma would give).
    std::vector<Rgb> d[5];
    arm_derivatives(/*detector=*/true, std::sqrt(noise.detector_arm_variance), d);
    std::vector<Eigen::VectorXd> h(5, Eigen::VectorXd::Zero(a.rows()));
    size_t current = 0;
    objective.ForEachRow(at, [&](int64_t row, const Eigen::VectorXd& jacobian, double) {
      const size_t k = static_cast<size_t>(row / 3);
      const int c = static_cast<int>(row % 3);
      if (k != current) {
        add_group(h);
        for (auto& column : h) column.setZero();
        current = k;
      }
      for (int j = 0; j < 5; ++j) h[j] += jacobian * (samples[k].scale[c] * d[j][k][c]);
    });
    add_group(h);
  }
  PredictedErrors errors;
  errors.note = state.held_note;
  errors.stderr_values.assign(M::kNumParams, std::numeric_limits<double>::quiet_NaN());
  if (SandwichCovariance(a, b, state.held, &covariance, &errors.note)) {
    errors.stderr_values = ParamStderr<M>(at, covariance);
    errors.available = true;
  }
  return errors;
}

std::string ChannelList(const std::vector<int>& channels, int size) {
  if (size == 1) return "";
  static const char* kNames[] = {"R", "G", "B"};
  std::string list;
  for (int c : channels) list += (list.empty() ? "" : ",") + std::string(kNames[c]);
  return " (" + list + ")";
}

}  // namespace

DesignOptions ParseCriterion(const std::string& text, const Model& model) {
  DesignOptions options;
  if (text == "d") {
    options.criterion = DesignCriterion::kD;
  } else if (text == "a") {
    options.criterion = DesignCriterion::kA;
  } else if (StartsWith(text, "param:")) {
    options.criterion = DesignCriterion::kParam;
    options.param = text.substr(6);
    if (model.info().FindParam(options.param) == nullptr) {
      std::string names;
      for (const ParamInfo& param : model.info().params) {
        names += (names.empty() ? "" : ", ") + param.name;
      }
      throw UsageError("criterion '" + text + "': " + model.name() + " has no parameter '" +
                       options.param + "' (its parameters: " + names + ")");
    }
  } else {
    throw UsageError("unknown criterion '" + text + "' (known: d, a, param:NAME)");
  }
  return options;
}

std::vector<std::string> DesignWarnings(const Model& model) {
  return VisitModelType(model.name(), [&](auto model_type) {
    using M = decltype(model_type);
    const DesignState<M> state(model);
    const Eigen::MatrixXd& gradients = state.gradients;
    std::vector<std::string> warnings;
    for (const ParamInfo& param : model.info().params) {
      std::vector<int> channels;
      for (int c = 0; c < param.channels; ++c) {
        for (size_t k = 0; k < state.held.size(); ++k) {
          if (state.held[k] && gradients(param.slot + c, k) != 0) {
            channels.push_back(c);
            break;
          }
        }
      }
      if (channels.empty()) continue;
      warnings.push_back(param.name + ChannelList(channels, param.channels) +
                         " is at a bound of the fit (" +
                         FormatNumber(model.params()[param.slot + channels[0]], 6) +
                         "): a fit cannot move it, so no reading informs it; the plan pins down "
                         "the other parameters");
    }
    for (const LobeInfo& lobe : model.info().lobes) {
      if (lobe.shape_slot < 0) continue;
      const double shape = model.params()[lobe.shape_slot];
      const double lower = std::log(lobe.fit_shape_min), upper = std::log(lobe.fit_shape_max);
      const double clamped = std::clamp(std::log(shape), lower, upper);
      if (std::abs(std::log(shape) - clamped) > 1e-12 || !(shape > 0)) {
        warnings.push_back(
            model.info().ParamAtSlot(lobe.shape_slot).name + " = " + FormatNumber(shape, 6) +
            " lies outside the fit's range [" + FormatNumber(lobe.fit_shape_min, 6) + ", " +
            FormatNumber(lobe.fit_shape_max, 6) + "]: planned at the nearest end of it");
      }
    }
    return warnings;
  });
}

DesignResult ChooseDesign(const Model& model, const std::vector<DesignPoint>& candidates,
                          const DesignOptions& options, const gonio::Instrument* instrument) {
  return VisitModelType(model.name(), [&](auto model_type) {
    return Choose<decltype(model_type)>(model, candidates, options, instrument);
  });
}

double InformationLogDet(const Model& model, const std::vector<DesignPoint>& points,
                         const gonio::Instrument* instrument) {
  return VisitModelType(model.name(), [&](auto model_type) {
    return LogDet<decltype(model_type)>(model, points, instrument);
  });
}

ExpectedNoise ExpectedNoiseAt(const std::vector<DesignPoint>& points, double common_scale_variance,
                              double light_arm_variance, double detector_arm_variance) {
  ExpectedNoise noise;
  noise.detector_arm_variance = detector_arm_variance;
  noise.common_scale_variance = common_scale_variance;
  noise.light_arm_variance = light_arm_variance;
  noise.independent_sigma.reserve(points.size());
  for (const DesignPoint& point : points)
    noise.independent_sigma.push_back(point.independent_sigma);
  return noise;
}

PredictedErrors PredictErrors(const Model& model, const Measurement& measurement,
                              const ExpectedNoise& noise) {
  return VisitModelType(model.name(), [&](auto model_type) {
    return Predict<decltype(model_type)>(model, measurement, noise);
  });
}

}  // namespace brdf::fitters
