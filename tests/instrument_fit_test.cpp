// Fitting through the instrument (DESIGN §6; fitters/reading_nodes.h, gonio/forward_model.h):
// the forward model against the virtual instrument's own readings, the aperture-averaged
// objective's Jacobian against automatic differentiation, the plan -> measure -> fit workflow
// recovering the truth where the nominal fit does not, the blurred-lobe warning on both sides,
// and the model-predicted weights (fit_samples.h: VarianceFunction).
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "core/angles.h"
#include "fitters/experiment_design.h"
#include "fitters/fit.h"
#include "fitters/objective.h"
#include "fitters/reading_nodes.h"
#include "fitters/residual.h"
#include "gonio/forward_model.h"
#include "gonio/measure.h"
#include "gonio/model_sample.h"
#include "gonio/schedule.h"
#include "models/model_source.h"
#include "objective_rows.h"
#include "test_util.h"

namespace brdf {
namespace {

// Geometries about the mirror direction of 30 deg incidence, from the lobe's core to its
// flanks, and a few far off it.
std::vector<fitters::FitSample> LobeSamples(const Model& model) {
  std::vector<fitters::FitSample> samples;
  const Vec3 wi = SphericalDirection(DegToRad(30), 0);
  for (double theta_o : {24.0, 27.0, 28.5, 29.5, 30.0, 30.7, 31.5, 33.0, 36.0, 60.0}) {
    for (double phi_o : {178.0, 180.0, 181.0}) {
      fitters::FitSample sample;
      sample.wi = wi;
      sample.wo = SphericalDirection(DegToRad(theta_o), DegToRad(phi_o));
      sample.value = model.Eval(sample.wi, sample.wo);
      samples.push_back(sample);
    }
  }
  return samples;
}

// With an ideal detector and no jitter the virtual instrument's calibrated value is the forward
// model's prediction: the same quadrature, the same reference.
TEST(InstrumentFit, ForwardModelIsTheInstrumentsReading) {
  for (const char* text : {"blinn-phong:rho_d=0.2:rho_s=0.3:m=5000",
                           "ggx:rho_d=0.1:f0=0.04:alpha=0.02", "lambert:rho_d=0.5"}) {
    SCOPED_TRACE(text);
    const Model model = LoadModel(text);
    gonio::Instrument instrument;
    instrument.photons = 0;
    instrument.jitter_deg = 0;
    gonio::MeasureOptions options;
    options.sample = std::string("model:") + text;
    options.instrument = instrument;
    const Measurement measurement = gonio::Measure(options, gonio::MakeSchedule("inplane"));
    std::vector<fitters::FitSample> samples;
    for (const Sample& sample : measurement.samples) {
      samples.push_back({sample.wi, sample.wo, sample.value});
    }
    const fitters::SampleNodes nodes = fitters::InstrumentNodes(instrument, model, samples);
    double largest_nominal_error = 0;
    for (size_t k = 0; k < samples.size(); ++k) {
      const Rgb predicted = fitters::PredictReading(model, samples, &nodes, k);
      const Rgb nominal = model.Eval(samples[k].wi, samples[k].wo);
      for (int c = 0; c < 3; ++c) {
        const double value = samples[k].value[c];
        EXPECT_NEAR(predicted[c], value, 2 * fitters::kNominalTolerance * std::abs(value) + 1e-12)
            << "sample " << k;
        largest_nominal_error =
            std::max(largest_nominal_error, std::abs(nominal[c] - value) / std::abs(value));
      }
    }
    // The apertures matter for the lobes (the nominal value is off by far more than the
    // tolerance near the peak), not for the Lambertian sample.
    if (model.name() == "lambert") {
      EXPECT_EQ(nodes.averaged, 0u);
    } else {
      EXPECT_GT(largest_nominal_error, 0.05);
      EXPECT_GT(nodes.averaged, 0u);
      EXPECT_LT(nodes.averaged, samples.size());
    }
  }
}

// The second and fourth moments of the angle between each node's direction and the nominal
// one, over the nodes of one reading, weighted as the reading weighs them (the detector's
// cos(theta_o) taken out): `of_source` picks wi, else wo.
std::pair<double, double> NodeMoments(const std::vector<gonio::ReadingNode>& nodes,
                                      const Vec3& nominal, bool of_source) {
  double total = 0, second = 0, fourth = 0;
  for (const gonio::ReadingNode& node : nodes) {
    const Vec3& w = of_source ? node.wi : node.wo;
    const double weight = node.weight / node.wo.z();
    const double angle = std::acos(std::min(1.0, w.dot(nominal)));
    total += weight;
    second += weight * angle * angle;
    fourth += weight * std::pow(angle, 4);
  }
  return {second / total, fourth / total};
}

// Through positioning jitter (Gaussian, sigma per axis) a point of an aperture's rule at angle r
// lands at E|z|^2 = r^2 + 2 sigma^2 and E|z|^4 = r^4 + 8 sigma^2 r^2 + 8 sigma^4 from the nominal
// direction. The forward model's nodes have those moments over the virtual instrument's own
// rule, for the two-ring detector and the one-ring source of a ggx alpha 0.02 lobe, and, without
// jitter, the rule's own. (Apertures widened to the jittered second moments alone, as before,
// missed the fourth by 0.9 % and 11 % on the detector at 0.05 and 0.2 deg, 20 % and 48 % on the
// source.)
TEST(InstrumentFit, ForwardModelHasTheJitteredRulesSecondAndFourthMoments) {
  const Model model = LoadModel("ggx:rho_d=0.1:f0=0.04:alpha=0.02");
  const double width = gonio::LobeWidth(model);
  const Vec3 wi = SphericalDirection(DegToRad(30), 0), wo = SphericalDirection(DegToRad(20), kPi);
  for (double jitter_deg : {0.0, 0.05, 0.2}) {
    gonio::Instrument instrument;
    instrument.jitter_deg = jitter_deg;
    const double s2 = std::pow(DegToRad(jitter_deg), 2);
    const gonio::ForwardModel forward(instrument, width);
    std::vector<gonio::ReadingNode> nodes;
    forward.AppendNodes(wi, wo, &nodes);
    for (bool of_source : {true, false}) {
      const double radius = of_source ? instrument.SourceAngularRadius()
                                      : std::acos(instrument.DetectorCosHalfAngle());
      const std::vector<gonio::AperturePoint> rule = gonio::ApertureQuadrature(radius, width);
      double rings = 0, second = 0, fourth = 0;
      for (const gonio::AperturePoint& point : rule) {
        const double r2 = std::pow(std::acos(1 - point.u1 * (1 - std::cos(radius))), 2);
        second += point.weight * (r2 + 2 * s2);
        fourth += point.weight * (r2 * r2 + 8 * s2 * r2 + 8 * s2 * s2);
        rings += point.u1 != rule.front().u1;
      }
      const auto [node_second, node_fourth] = NodeMoments(nodes, of_source ? wi : wo, of_source);
      SCOPED_TRACE(std::string(of_source ? "source" : "detector") + " jitter " +
                   std::to_string(jitter_deg));
      EXPECT_EQ(rings > 0, !of_source);  // the detector's rule has two rings, the source's one
      EXPECT_NEAR(node_second, second, 1e-4 * second);
      EXPECT_NEAR(node_fourth, fourth, 1e-4 * fourth);
    }
  }
}

// The aperture-averaged objective's closed-form Jacobian (objective.h, summed over nodes)
// against automatic differentiation of the same residuals (residual.h with nodes), for every
// loss, on a lobe's core and flanks.
TEST(InstrumentFit, ApertureAveragedJacobianMatchesAutodiff) {
  for (const char* text :
       {"blinn-phong:rho_d=0.2:rho_s=0.3:m=5000", "ggx:rho_d=0.1:f0=0.04:alpha=0.05"}) {
    const Model model = LoadModel(text);
    const std::vector<fitters::FitSample> samples = LobeSamples(model);
    const gonio::Instrument instrument;
    const fitters::SampleNodes nodes = fitters::InstrumentNodes(instrument, model, samples);
    ASSERT_GT(nodes.averaged, samples.size() / 2) << text;
    VisitModelType(model.name(), [&](auto model_type) {
      using M = decltype(model_type);
      for (const fitters::Loss loss : {fitters::Loss::kL2, fitters::Loss::kLog,
                                       fitters::Loss::kCosineL2, fitters::Loss::kSqrt}) {
        SCOPED_TRACE(std::string(text) + " loss " + fitters::LossName(loss));
        const fitters::FitObjective<M> objective(samples, loss, false,
                                                 fitters::FitObjective<M>::kDefaultBatch, &nodes);
        const int n = objective.NumVariables();
        const int count = static_cast<int>(samples.size()), rows = 3 * count;
        ceres::DynamicAutoDiffCostFunction<testing::DynamicBatchResidual<M>> automatic(
            new testing::DynamicBatchResidual<M>{
                fitters::BatchResidual<M>(false, loss, samples.data(), count, &nodes, 0)});
        automatic.AddParameterBlock(n);
        automatic.SetNumResiduals(rows);
        // At the truth and away from it (a wider lobe, other shares).
        std::vector<double> x = fitters::ParamsToVariables<M>(model.params().data());
        for (int trial = 0; trial < 2; ++trial) {
          if (trial == 1) {
            for (double& v : x) v = 0.9 * v + 0.05;
          }
          std::vector<double> residuals(rows), jacobian(static_cast<size_t>(rows) * n);
          objective.ForEachRow(objective.At(x.data()),
                               [&](int64_t row, const Eigen::VectorXd& j, double r) {
                                 residuals[row] = r;
                                 for (int i = 0; i < n; ++i) jacobian[row * n + i] = j[i];
                               });
          std::vector<double> expected_residuals(rows), expected(static_cast<size_t>(rows) * n);
          const double* blocks[] = {x.data()};
          double* expected_blocks[] = {expected.data()};
          ASSERT_TRUE(automatic.Evaluate(blocks, expected_residuals.data(), expected_blocks));
          double largest = 0, largest_residual = 1e-300;
          for (const double v : expected) largest = std::max(largest, std::abs(v));
          for (const double r : expected_residuals) {
            largest_residual = std::max(largest_residual, std::abs(r));
          }
          ASSERT_GT(largest, 0.0);
          for (int r = 0; r < rows; ++r) {
            EXPECT_NEAR(residuals[r], expected_residuals[r], 1e-12 * largest_residual) << r;
          }
          for (size_t k = 0; k < expected.size(); ++k) {
            EXPECT_NEAR(jacobian[k], expected[k], 1e-11 * largest) << "entry " << k;
          }
        }
      }
    });
  }
}

// What the plan -> measure -> fit workflow gives for blinn-phong m: the plan's predicted
// standard error, and over `seeds` measurements of the plan the mean and spread of m fitted
// through the instrument and the mean fitted at the nominal directions.
struct Workflow {
  double predicted = 0, mean = 0, spread = 0, nominal_mean = 0;
  double reported = 0;  // the median of the standard errors the fits through it report
};

Workflow RunWorkflow(const Model& truth, const gonio::Instrument& instrument, int budget,
                     int seeds) {
  const gonio::ModelSample sample(truth, instrument);
  const gonio::NoiseModel noise(sample, instrument);
  const gonio::Schedule candidates = gonio::MakeSchedule("adaptive:theta_i_step=10:base_step=10");
  const double cos_blocked = std::cos(DegToRad(instrument.blocked_within_deg));
  std::vector<fitters::DesignPoint> points;
  for (const gonio::Incidence& incidence : candidates.incidences) {
    for (const gonio::Detector& detector : incidence.detectors) {
      if (incidence.wi.dot(detector.wo) > cos_blocked) continue;
      points.push_back({incidence.wi, detector.wo, noise.Sigma(incidence.wi, detector.wo),
                        noise.CountSigma(incidence.wi, detector.wo)});
    }
  }
  fitters::DesignOptions design;
  design.budget = budget;
  const fitters::DesignResult result = fitters::ChooseDesign(truth, points, design, &instrument);
  EXPECT_EQ(result.chosen.size(), static_cast<size_t>(budget));
  gonio::Schedule plan;
  plan.spec = "file:plan";
  plan.kind = "file";
  plan.designed = true;
  Measurement predicted;
  predicted.metadata[kWeightingKey] = kEqualWeighting;
  predicted.metadata[fitters::kInstrumentKey] = instrument.ToJson();
  std::vector<fitters::DesignPoint> chosen;
  for (size_t k : result.chosen) {
    const fitters::DesignPoint& point = points[k];
    chosen.push_back(point);
    if (plan.incidences.empty() || plan.incidences.back().wi != point.wi) {
      plan.incidences.push_back({point.wi, {}});
    }
    plan.incidences.back().detectors.push_back({point.wo, 0});
    predicted.samples.push_back({point.wi, point.wo, truth.Eval(point.wi, point.wo), false});
    predicted.sigma.push_back(point.sigma);
  }
  const fitters::PredictedErrors errors = fitters::PredictErrors(
      truth, predicted,
      fitters::ExpectedNoiseAt(chosen, noise.CommonScaleVariance(), noise.LightArmVariance(),
                               noise.DetectorArmVariance()));
  EXPECT_TRUE(errors.available) << errors.note;
  const int m_slot = 6;
  Workflow workflow;
  workflow.predicted = errors.stderr_values[m_slot];
  std::vector<double> through, reported;
  gonio::MeasureOptions measure;
  measure.sample = "model:" + truth.ToString();
  measure.instrument = instrument;
  const fitters::FitOptions options;
  for (int seed = 1; seed <= seeds; ++seed) {
    measure.seed = static_cast<uint64_t>(seed);
    Measurement measurement = gonio::Measure(measure, plan);
    EXPECT_EQ(measurement.metadata.count(fitters::kInstrumentKey), 1u);
    const fitters::FitResult fit = fitters::FitModel(measurement, "blinn-phong", options);
    through.push_back(fit.model.params()[m_slot]);
    reported.push_back(fit.stderr_values[m_slot]);
    measurement.metadata.erase(fitters::kInstrumentKey);
    workflow.nominal_mean +=
        fitters::FitModel(measurement, "blinn-phong", options).model.params()[m_slot] / seeds;
  }
  for (double m : through) workflow.mean += m / seeds;
  double squares = 0;
  for (double m : through) squares += (m - workflow.mean) * (m - workflow.mean);
  workflow.spread = std::sqrt(squares / (seeds - 1));
  std::nth_element(reported.begin(), reported.begin() + seeds / 2, reported.end());
  workflow.reported = reported[seeds / 2];
  return workflow;
}

// The plan -> measure -> fit workflow (docs/planning.md has the 20-seed table). With the default
// instrument a fit through it recovers a sharp lobe's exponent within the spread the plan
// predicts, where the fit at the nominal directions misses it by tens of those. With the arms'
// positioning jitter (to second order, each arm's turn shared by the readings and channels it
// moves) and without it, the seeds' spread is the predicted one.
TEST(InstrumentFit, PlanMeasureFitRecoversASharpLobe) {
  const Model truth = LoadModel("blinn-phong:rho_d=0.2:rho_s=0.3:m=5000");
  const int kSeeds = 8;
  const Workflow standard = RunWorkflow(truth, gonio::Instrument{}, 200, kSeeds);
  const double standard_error = standard.spread / std::sqrt(double(kSeeds));
  EXPECT_NEAR(standard.mean, 5000, 3 * standard_error) << "spread " << standard.spread;
  EXPECT_GT(std::abs(standard.nominal_mean - 5000), 10 * standard_error)
      << "nominal mean " << standard.nominal_mean;
  // Eight seeds estimate a spread to about 25 %. The fits' own standard errors, clustered by
  // incidence, see the arms' jitter too (per-row squares reported half the spread).
  EXPECT_NEAR(standard.spread / standard.predicted, 1.0, 0.6)
      << "spread " << standard.spread << ", predicted " << standard.predicted;
  EXPECT_NEAR(standard.spread / standard.reported, 1.0, 0.6)
      << "spread " << standard.spread << ", reported " << standard.reported;

  gonio::Instrument steady;
  steady.jitter_deg = 0;
  const Workflow still = RunWorkflow(truth, steady, 200, kSeeds);
  EXPECT_NEAR(still.mean, 5000, 3 * still.spread / std::sqrt(double(kSeeds)));
  EXPECT_NEAR(still.spread / still.predicted, 1.0, 0.6)
      << "spread " << still.spread << ", predicted " << still.predicted;
}

// The warning is true on both sides: a lobe under half the detector's radius is named, a lobe
// the aperture resolves is not.
TEST(InstrumentFit, BlurredLobeWarningFiresOnlyForLobesUnderTheAperture) {
  const gonio::Instrument instrument;  // detector radius 1.03 deg
  EXPECT_EQ(fitters::ApertureBlurWarning(instrument, LoadModel("ggx:alpha=0.05")), "");
  EXPECT_EQ(fitters::ApertureBlurWarning(instrument, LoadModel("blinn-phong:m=5000")), "");
  EXPECT_EQ(fitters::ApertureBlurWarning(instrument, LoadModel("lambert")), "");
  const std::string sharp = fitters::ApertureBlurWarning(instrument, LoadModel("ggx:alpha=0.003"));
  EXPECT_NE(sharp.find("under half the detector aperture"), std::string::npos) << sharp;
  gonio::Instrument fine;
  fine.detector_solid_angle_sr = 1e-6;
  EXPECT_EQ(fitters::ApertureBlurWarning(fine, LoadModel("ggx:alpha=0.003")), "");
}

// The variance function recovers read, shot and relative noise from exact sigmas; the share of
// the stated variance that follows the readings' own noise is 1 for sigmas computed from the
// readings and 0 for sigmas computed from the noise-free values, and the weights move only in
// the first case.
TEST(InstrumentFit, VarianceFunctionAndTheShareThatFollowsTheReadings) {
  const auto v = [](double x) { return 1e-6 + 1e-4 * x + 4e-4 * x * x; };
  fitters::PreparedSamples exact;
  for (int k = 0; k < 200; ++k) {
    fitters::FitSample sample;
    sample.value = Rgb::Constant(0.01 * k);
    exact.samples.push_back(sample);
    exact.sigma.push_back(Rgb::Constant(std::sqrt(v(0.01 * k))));
  }
  const fitters::VarianceFunction variance = fitters::FitVarianceFunction(exact);
  EXPECT_NEAR(variance.a[0], 1e-6, 1e-9);
  EXPECT_NEAR(variance.b[1], 1e-4, 1e-7);
  EXPECT_NEAR(variance.c[2], 4e-4, 4e-7);

  // Noisy readings of known truths, the sigma stated from the reading or from the truth.
  std::mt19937_64 random(3);
  std::normal_distribution<double> normal;
  std::vector<fitters::FitSample> samples;
  std::vector<Rgb> truth, from_reading, from_truth;
  for (int k = 0; k < 2000; ++k) {
    const double f = 0.05 + 0.001 * k;
    fitters::FitSample sample;
    sample.value = Rgb::Constant(f + std::sqrt(v(f)) * normal(random));
    samples.push_back(sample);
    truth.push_back(Rgb::Constant(f));
    from_reading.push_back(variance.At(sample.value).sqrt());
    from_truth.push_back(variance.At(Rgb::Constant(f)).sqrt());
  }
  Rgb followed;
  const std::vector<fitters::FitSample> reweighted =
      fitters::ModelWeighted(samples, from_reading, variance, truth, &followed);
  EXPECT_NEAR(followed[0], 1.0, 1e-9);
  for (size_t k = 0; k < samples.size(); ++k) {
    // Weighted as the truth's sigma says.
    ASSERT_NEAR(reweighted[k].scale[0] * from_truth[k][0], from_reading[k][0], 1e-9) << k;
  }
  const std::vector<fitters::FitSample> kept =
      fitters::ModelWeighted(samples, from_truth, variance, truth, &followed);
  EXPECT_LT(followed[0], 0.1);
  double largest_change = 0;
  for (size_t k = 0; k < samples.size(); ++k) {
    largest_change = std::max(largest_change, std::abs(kept[k].scale[0] - 1));
  }
  EXPECT_LT(largest_change, 0.05);
}

// Readings whose stated sigma comes from their own noisy value (sigma^2 proportional to the
// reading, as a photon count's or a Monte Carlo estimate's) pull a sigma-weighted fit toward
// the readings that came out low; weighted by the model's prediction the fit is unbiased.
TEST(InstrumentFit, WeightsFromTheModelAreUnbiased) {
  const Model truth = LoadModel("blinn-phong:rho_d=0.1:rho_s=0.6:m=40");
  Measurement measurement;
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  const double kRelative = 0.15;  // a value's relative noise at 1 sr^-1 (Poisson-like)
  for (int i = 0; i < 8; ++i) {
    const Vec3 wi = SphericalDirection(DegToRad(5 + 9 * i), 0);
    for (int a = 0; a < 36; ++a) {
      for (int b = 0; b < 18; ++b) {
        const Vec3 wo = SphericalDirection(DegToRad(2.5 + 4.8 * b), DegToRad(10 * a));
        const double f = truth.Eval(wi, wo)[0];
        const double value = f + kRelative * std::sqrt(f) * normal(random);
        measurement.samples.push_back({wi, wo, Rgb::Constant(value), false});
        const double stated = kRelative * std::sqrt(std::max(value, 1e-4));
        measurement.sigma.push_back(Rgb::Constant(stated));
      }
    }
  }
  fitters::FitOptions options;
  options.grey_specular = true;
  const fitters::FitResult fit = fitters::FitModel(measurement, "blinn-phong", options);
  ASSERT_TRUE(fit.converged);
  EXPECT_NEAR(fit.model.params()[6], 40, 0.02 * 40) << fit.model.ToString();
  EXPECT_NE(fit.weighting.find("sigma predicted from the model"), std::string::npos);
}

// `brdf fit` reads a measurement through the instrument it records, `--instrument none` at the
// nominal directions, and a missing instrument file is a usage error naming it (exit 2).
TEST(InstrumentFit, FitCommandReadsThroughTheRecordedInstrument) {
  testing::ScratchDir dir;
  const std::string measured = dir.File("m.csv");
  ASSERT_EQ(testing::RunBrdf("measure --sample model:blinn-phong:m=300 --schedule inplane --quiet "
                             "--out '" +
                             measured + "'")
                .exit_status,
            0);
  const auto weighting = [&](const std::string& extra) {
    const testing::CommandResult result =
        testing::RunBrdf("fit '" + measured + "' --model blinn-phong --json " + extra);
    EXPECT_EQ(result.exit_status, 0) << result.err;
    return nlohmann::json::parse(result.out)["weighting"].get<std::string>();
  };
  EXPECT_NE(weighting("").find("through the instrument"), std::string::npos);
  EXPECT_EQ(weighting("--instrument none").find("through the instrument"), std::string::npos);
  const testing::CommandResult missing = testing::RunBrdf(
      "fit '" + measured + "' --model blinn-phong --instrument '" + dir.File("absent.json") + "'");
  EXPECT_EQ(missing.exit_status, 2);
  EXPECT_NE(missing.err.find("absent.json"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace brdf
