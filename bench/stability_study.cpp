// Where the methods fail (docs/stability.md): sweeps of the fitter, the albedo integrators and
// the tone pipeline past their comfort zone, each printed as CSV. Deterministic: every random
// number comes from a seed fixed per row.
//
//   stability_study SWEEP [--quick]
//   SWEEP: exponent | noise | coverage | starts | outliers | mismatch | integration | tonemap
//   (mismatch also writes its plane-of-incidence table to --plane=FILE)
//
// Synthetic measurements (tests/synthetic_measurement.h, shared with the tests that catch these
// failures) read the truth at the default schedule of `brdf measure` (hemisphere, 5 deg steps)
// at the nominal directions, with multiplicative Gaussian noise of a known level and a sigma
// column that states it honestly. The aperture's own averaging is docs/gonio.md's subject.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/errors.h"
#include "core/format.h"
#include "energy/albedo.h"
#include "fitters/diagnostics.h"
#include "fitters/fit.h"
#include "gonio/measure.h"
#include "gonio/schedule.h"
#include "hdr/image.h"
#include "hdr/pipeline.h"
#include "models/model_string.h"
#include "synthetic_measurement.h"

namespace brdf {
namespace {

using fitters::FitModel;
using fitters::FitOptions;
using fitters::FitResult;

bool quick = false;

// Short names of the report's warnings (the text before the first ':'), joined by ';'.
std::string WarningCodes(const FitResult& fit) {
  std::string codes;
  for (const std::string& warning : fit.warnings) {
    std::string head = warning.substr(0, warning.find(':'));
    if (head.rfind("started from", 0) == 0) continue;  // the subsample note, not a failure
    if (head.rfind("energy bound", 0) == 0) head = "energy bound";
    for (char& c : head) c = c == ' ' ? '-' : c;
    if (codes.find(head) != std::string::npos) continue;
    codes += (codes.empty() ? "" : ";") + head;
  }
  return codes.empty() ? "none" : codes;
}

double MaxRelativeError(const Model& fitted, const Model& truth, const char* name) {
  double worst = 0;
  for (int c = 0; c < 3; ++c) {
    const double expected = truth.Param(name, c);
    worst = std::max(worst, std::abs(fitted.Param(name, c) - expected) / expected);
  }
  return worst;
}

std::string Truth(const std::string& model, double exponent) {
  const char* symbol = model == "phong" ? "n" : "m";
  return Format("%s:rho_d=0.3,0.2,0.1:rho_s=0.2,0.25,0.3:%s=%.10g", model.c_str(), symbol,
                exponent);
}

const char* kFitHeader =
    "rel_err_rho_d,rel_err_rho_s,rel_err_exponent,fitted_exponent,exponent_rel_stderr,"
    "exponent_z,converged,rmse,flank_samples,warnings";

// The common columns of a fit of a known truth.
std::string FitColumns(const FitResult& fit, const Model& truth, const Measurement& data) {
  const double m_true = truth.params()[models::SingleLobeSlots::kExponent];
  const double m_fit = fit.model.params()[models::SingleLobeSlots::kExponent];
  const double m_stderr = fit.stderr_values[models::SingleLobeSlots::kExponent];
  const fitters::PreparedSamples prepared = fitters::PrepareSamples(data);
  const fitters::LobeResolution lobe =
      fitters::ResolveLobe(truth.Lobe().frame, m_true, prepared.samples);
  return Format("%.4g,%.4g,%.4g,%.6g,%.4g,%.4g,%d,%.5g,%zu,%s",
                MaxRelativeError(fit.model, truth, "rho_d"),
                MaxRelativeError(fit.model, truth, "rho_s"), std::abs(m_fit - m_true) / m_true,
                m_fit, m_stderr / m_fit, (m_fit - m_true) / m_stderr, fit.converged ? 1 : 0,
                fit.metrics.rmse, lobe.flank_samples, WarningCodes(fit).c_str());
}

const std::vector<std::string> kLobedModels = {"phong", "blinn-phong"};

void SweepExponent() {
  std::cout << "model,exponent," << kFitHeader << "\n";
  const std::vector<double> exponents =
      quick ? std::vector<double>{1, 100, 1e4, 1e5}
            : std::vector<double>{1, 3, 10, 30, 100, 300, 1e3, 3e3, 1e4, 3e4, 1e5, 1e6};
  for (const std::string& name : kLobedModels) {
    for (double exponent : exponents) {
      const Model truth = ParseModel(Truth(name, exponent));
      const Measurement data = testing::SynthesizeOnHemisphere(truth, {});
      const FitResult fit = FitModel(data, name, FitOptions{});
      std::cout << name << "," << exponent << "," << FitColumns(fit, truth, data) << "\n";
    }
  }
}

void SweepNoise() {
  std::cout << "model,noise,seed," << kFitHeader << "\n";
  const std::vector<double> levels = quick
                                         ? std::vector<double>{0.001, 0.2}
                                         : std::vector<double>{0.001, 0.003, 0.01, 0.03, 0.1, 0.2};
  const int seeds = quick ? 1 : 2;
  for (const std::string& name : kLobedModels) {
    const Model truth = ParseModel(Truth(name, 300));
    for (double noise : levels) {
      for (int seed = 1; seed <= seeds; ++seed) {
        testing::SyntheticOptions synthesis;
        synthesis.noise = noise;
        synthesis.seed = static_cast<uint64_t>(seed);
        const Measurement data = testing::SynthesizeOnHemisphere(truth, synthesis);
        const FitResult fit = FitModel(data, name, FitOptions{});
        std::cout << name << "," << noise << "," << seed << "," << FitColumns(fit, truth, data)
                  << "\n";
      }
    }
  }
}

void SweepCoverage() {
  std::cout << "model,exponent,theta_max_deg," << kFitHeader << "\n";
  const std::vector<double> maxima =
      quick ? std::vector<double>{60, 89} : std::vector<double>{60, 65, 70, 75, 80, 85, 89};
  for (const std::string& name : kLobedModels) {
    for (double exponent : {10.0, 1000.0}) {
      const Model truth = ParseModel(Truth(name, exponent));
      for (double theta_max : maxima) {
        testing::SyntheticOptions synthesis;
        synthesis.theta_max_deg = theta_max;
        synthesis.grazing_rings = true;
        const Measurement data = testing::SynthesizeOnHemisphere(truth, synthesis);
        const FitResult fit = FitModel(data, name, FitOptions{});
        std::cout << name << "," << exponent << "," << theta_max << ","
                  << FitColumns(fit, truth, data) << "\n";
      }
    }
  }
}

void SweepStarts() {
  std::cout << "model,exponent,starts,start_exponent,final_cost," << kFitHeader << "\n";
  const std::vector<double> exponents =
      quick ? std::vector<double>{3, 3e4} : std::vector<double>{3, 30, 300, 3e3, 3e4, 1e5};
  for (const std::string& name : kLobedModels) {
    for (double exponent : exponents) {
      const Model truth = ParseModel(Truth(name, exponent));
      const Measurement data = testing::SynthesizeOnHemisphere(truth, {});
      // The far start: the end of the default range farther from the truth in log space.
      const double far = exponent < 256 ? 32768 : 2;
      for (const bool multi : {false, true}) {
        FitOptions options;
        if (!multi) options.start_exponents = {far};
        const FitResult fit = FitModel(data, name, options);
        std::cout << name << "," << exponent << "," << (multi ? "multi" : "single") << ","
                  << (multi ? 0.0 : far) << "," << fit.final_cost << ","
                  << FitColumns(fit, truth, data) << "\n";
      }
    }
  }
}

void SweepOutliers() {
  std::cout << "model,outlier_fraction,robust," << kFitHeader << "\n";
  const std::vector<double> fractions =
      quick ? std::vector<double>{0, 0.05} : std::vector<double>{0, 0.001, 0.01, 0.05, 0.1, 0.2};
  const std::string name = "blinn-phong";
  const Model truth = ParseModel(Truth(name, 300));
  for (double fraction : fractions) {
    testing::SyntheticOptions synthesis;
    synthesis.outlier_fraction = fraction;
    synthesis.seed = 7;
    const Measurement data = testing::SynthesizeOnHemisphere(truth, synthesis);
    for (fitters::Robust robust :
         {fitters::Robust::kNone, fitters::Robust::kHuber, fitters::Robust::kCauchy}) {
      FitOptions options;
      options.robust = robust;
      const FitResult fit = FitModel(data, name, options);
      std::cout << name << "," << fraction << "," << fitters::RobustName(robust) << ","
                << FitColumns(fit, truth, data) << "\n";
    }
  }
}

// The Embree sample: rough gold (data/surfaces/rough-gold.json), a Gaussian height field of rms
// slope 0.3 under a smooth conductor, measured by the default instrument and schedule with
// fewer rays than the file asks for (the fit needs shape, not the last percent of noise).
Measurement MeasureRoughGold() {
  const std::string json = std::string(BRDFKIT_DATA_DIR) + "/surfaces/rough-gold.json";
  const std::string scratch =
      (std::filesystem::temp_directory_path() / "brdfkit_stability_rough_gold.json").string();
  std::ifstream in(json);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string key = "\"rays_per_incidence\": 1000000";
  const size_t at = text.find(key);
  if (at == std::string::npos) throw InputError(json, "no rays_per_incidence of 1000000");
  text.replace(at, key.size(),
               quick ? "\"rays_per_incidence\": 50000" : "\"rays_per_incidence\": 400000");
  {
    std::ofstream out(scratch);
    out << text;
  }
  gonio::MeasureOptions options;
  options.sample = "surface:" + scratch;
  options.schedule = quick ? "hemisphere:theta_i_step=15" : "hemisphere";
  options.seed = 1;
  const gonio::Schedule schedule = gonio::MakeSchedule(options.schedule);
  Measurement measurement = gonio::Measure(options, schedule);
  std::remove(scratch.c_str());
  return measurement;
}

const std::vector<std::string> kAllModels = {"lambert", "phong", "blinn-phong",
                                             "blinn-phong-exact"};

std::string
    plane_path;  // --plane=FILE: where the mismatch sweep writes its plane-of-incidence table

void SweepMismatch() {
  const Measurement data = MeasureRoughGold();
  std::vector<FitResult> fits;
  for (const std::string& name : kAllModels) fits.push_back(FitModel(data, name, FitOptions{}));
  {
    // Fit summary, then the residual in units of the file's sigma (green channel) by
    // half-vector angle: mean (bias) and rms per 10 deg bin.
    std::cout << "model,fit,rmse,log_rmse,bic,reduced_chi_square,converged,warnings,"
                 "theta_h_bin_deg,rms_z,mean_z,samples\n";
    const fitters::PreparedSamples prepared_data = fitters::PrepareSamples(data);
    for (size_t k = 0; k < fits.size(); ++k) {
      const FitResult& fit = fits[k];
      const fitters::ResidualCheck check = fitters::CheckResiduals(fit.model, prepared_data);
      const int bins = 9;  // 10 deg each over theta_h 0 ... 90
      std::vector<double> sum_square(bins, 0), sum(bins, 0);
      std::vector<int> count(bins, 0);
      for (size_t s = 0; s < data.samples.size(); ++s) {
        const Sample& sample = data.samples[s];
        const double f = fit.model.Eval(sample.wi, sample.wo)[1];
        const double sigma = data.sigma[s][1];
        if (!(sigma > 0)) continue;
        const double theta_h = std::acos((sample.wi + sample.wo).normalized().z()) * 180 / kPi;
        const int bin = std::min(bins - 1, static_cast<int>(theta_h / 10));
        const double z = (sample.value[1] - f) / sigma;
        sum_square[bin] += z * z;
        sum[bin] += z;
        ++count[bin];
      }
      for (int bin = 0; bin < bins; ++bin) {
        if (count[bin] == 0) continue;
        std::printf("%s,\"%s\",%.5g,%.5g,%.6g,%.4g,%d,%s,%d,%.4g,%.4g,%d\n", kAllModels[k].c_str(),
                    fit.model.ToString().c_str(), fit.metrics.rmse, fit.metrics.log_rmse, fit.bic,
                    check.reduced_chi_square, fit.converged ? 1 : 0, WarningCodes(fit).c_str(),
                    10 * bin + 5, std::sqrt(sum_square[bin] / count[bin]), sum[bin] / count[bin],
                    count[bin]);
      }
    }
  }
  if (plane_path.empty()) return;
  // The plane of incidence: measured (green) and every fit.
  FILE* out = std::fopen(plane_path.c_str(), "w");
  if (out == nullptr) throw UsageError("cannot write " + plane_path);
  std::fprintf(out, "theta_i_deg,theta_o_signed_deg,measured,sigma");
  for (const std::string& name : kAllModels) std::fprintf(out, ",%s", name.c_str());
  std::fprintf(out, "\n");
  for (size_t k = 0; k < data.samples.size(); ++k) {
    const Sample& sample = data.samples[k];
    const double phi_o = std::atan2(sample.wo.y(), sample.wo.x());
    const bool forward = std::abs(std::abs(phi_o) - kPi) < 1e-6;
    const bool back = std::abs(phi_o) < 1e-6 && sample.wo.z() < 1 - 1e-12;
    const bool normal = sample.wo.z() > 1 - 1e-12;
    if (!forward && !back && !normal) continue;
    const double theta_i = std::acos(sample.wi.z()) * 180 / kPi;
    const double theta_o = std::acos(std::min(sample.wo.z(), 1.0)) * 180 / kPi;
    std::fprintf(out, "%.4g,%.4g,%.6g,%.4g", theta_i, forward ? theta_o : -theta_o, sample.value[1],
                 data.sigma[k][1]);
    for (const FitResult& fit : fits) {
      std::fprintf(out, ",%.6g", fit.model.Eval(sample.wi, sample.wo)[1]);
    }
    std::fprintf(out, "\n");
  }
  std::fclose(out);
}

// Albedo of rho_s = 1, rho_d = 0 lobes, whose normal-incidence albedo is exactly 1 (phong and
// blinn-phong-exact are normalized for it), and at 60 deg against a tight quadrature.
void SweepIntegration() {
  std::cout << "model,exponent,theta_deg,method,samples,albedo,error_estimate,true_error,"
               "evaluations,reference\n";
  const std::vector<double> exponents =
      quick ? std::vector<double>{1, 1e4, 1e6}
            : std::vector<double>{1, 10, 100, 1e3, 1e4, 1e5, 3e5, 1e6};
  for (const std::string name : {"phong", "blinn-phong-exact"}) {
    for (double exponent : exponents) {
      const Model model = ParseModel(Format("%s:rho_d=0:rho_s=1:%s=%.10g", name.c_str(),
                                            name == "phong" ? "n" : "m", exponent));
      for (double theta_deg : {0.0, 60.0}) {
        const double theta = DegToRad(theta_deg);
        double reference = 1.0;
        if (theta_deg != 0) {
          AlbedoOptions tight;
          tight.quadrature.tolerance = 1e-10;
          tight.quadrature.max_intervals = 2000;
          reference = ModelDirectionalAlbedo(model, theta, tight).albedo[1];
        }
        struct Case {
          AlbedoMethod method;
          int64_t samples;
        };
        std::vector<Case> cases = {{AlbedoMethod::kQuadrature, 0}};
        for (int64_t samples :
             quick ? std::vector<int64_t>{65536} : std::vector<int64_t>{4096, 65536, 1048576}) {
          cases.push_back({AlbedoMethod::kMonteCarlo, samples});
          cases.push_back({AlbedoMethod::kImportance, samples});
        }
        for (const Case& c : cases) {
          AlbedoOptions options;
          options.method = c.method;
          if (c.samples > 0) options.samples = c.samples;
          const AlbedoEstimate estimate = ModelDirectionalAlbedo(model, theta, options, 3);
          std::printf("%s,%.10g,%g,%s,%lld,%.9g,%.3g,%.3g,%lld,%.9g\n", name.c_str(), exponent,
                      theta_deg, AlbedoMethodName(c.method), static_cast<long long>(c.samples),
                      estimate.albedo[1], estimate.error[1],
                      std::abs(estimate.albedo[1] - reference),
                      static_cast<long long>(estimate.evaluations), reference);
        }
      }
    }
  }
}

// A 64 x 64 scene (a smooth luminance ramp over four decades) with broken pixels.
Image TestScene() {
  Image image(64, 64);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      float* rgba = image.pixel(x, y);
      const float luminance = std::pow(10.0f, -2.0f + 4.0f * x / 63.0f);
      rgba[0] = luminance * (0.8f + 0.4f * y / 63.0f);
      rgba[1] = luminance;
      rgba[2] = luminance * (1.2f - 0.4f * y / 63.0f);
    }
  }
  return image;
}

void SweepTonemap() {
  std::cout << "case,bloom,replaced,exposure,nonblack_fraction,max_abs_difference_8bit,"
               "mean_abs_difference_8bit\n";
  struct Case {
    const char* name;
    float value;
    double fraction;  // of pixels set to `value` (every k-th pixel)
  };
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const Case cases[] = {
      {"clean", 0, 0},           {"zero-1%", 0, 0.01},         {"zero-50%", 0, 0.5},
      {"zero-all", 0, 1},        {"nan-1px", nan, -1},         {"nan-10%", nan, 0.1},
      {"nan-all", nan, 1},       {"inf-1px", inf, -1},         {"neg-inf-1px", -inf, -1},
      {"inf-10%", inf, 0.1},     {"flt-max-1px", FLT_MAX, -1}, {"huge-1e30-1px", 1e30f, -1},
      {"negative-1%", -5, 0.01},
  };
  for (const bool bloom : {false, true}) {
    ToneOptions options;
    if (bloom) options.bloom = BlurKind::kDual;
    const Image8 clean = RunTonePipeline(TestScene(), options).display;
    for (const Case& c : cases) {
      Image image = TestScene();
      const int64_t n = image.pixel_count();
      const int64_t step =
          c.fraction < 0 ? n : std::max<int64_t>(1, std::llround(1.0 / std::max(c.fraction, 1e-9)));
      for (int64_t i = c.fraction < 0 ? n / 2 + 32 : 0; i < n; i += step) {
        if (c.fraction == 0) break;
        for (int ch = 0; ch < 3; ++ch) image.rgba[i * Image::kChannels + ch] = c.value;
      }
      const int64_t replaced = ReplaceNonFinite(&image);
      const ToneResult result = RunTonePipeline(std::move(image), options);
      // Pixels untouched by the damage: how far did it travel?
      int64_t nonblack = 0;
      int max_difference = 0;
      double sum_difference = 0;
      const int64_t bytes = static_cast<int64_t>(result.display.rgb.size());
      for (int64_t b = 0; b < bytes; ++b) {
        const int difference = std::abs(int(result.display.rgb[b]) - int(clean.rgb[b]));
        max_difference = std::max(max_difference, difference);
        sum_difference += difference;
      }
      for (int64_t p = 0; p < n; ++p) {
        const uint8_t* px = &result.display.rgb[p * 3];
        nonblack += px[0] != 0 || px[1] != 0 || px[2] != 0;
      }
      std::printf("%s,%s,%lld,%.4g,%.4g,%d,%.4g\n", c.name, bloom ? "dual" : "none",
                  static_cast<long long>(replaced), result.exposure, double(nonblack) / n,
                  max_difference, sum_difference / bytes);
    }
  }
}

int Main(int argc, char** argv) {
  std::string sweep;
  for (int k = 1; k < argc; ++k) {
    const std::string argument = argv[k];
    if (argument == "--quick") {
      quick = true;
    } else if (argument.rfind("--plane=", 0) == 0) {
      plane_path = argument.substr(8);
    } else {
      sweep = argument;
    }
  }
  if (sweep == "exponent") {
    SweepExponent();
  } else if (sweep == "noise") {
    SweepNoise();
  } else if (sweep == "coverage") {
    SweepCoverage();
  } else if (sweep == "starts") {
    SweepStarts();
  } else if (sweep == "outliers") {
    SweepOutliers();
  } else if (sweep == "mismatch") {
    SweepMismatch();
  } else if (sweep == "integration") {
    SweepIntegration();
  } else if (sweep == "tonemap") {
    SweepTonemap();
  } else {
    std::cerr << "usage: stability_study exponent|noise|coverage|starts|outliers|mismatch|"
                 "integration|tonemap [--quick] [--plane=FILE]\n";
    return 2;
  }
  return 0;
}

}  // namespace
}  // namespace brdf

int main(int argc, char** argv) {
  try {
    return brdf::Main(argc, argv);
  } catch (const std::exception& error) {
    std::cerr << "stability_study: " << error.what() << "\n";
    return 1;
  }
}
