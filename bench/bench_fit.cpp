// Fitting speed and accuracy (docs/fitting.md, docs/speed-accuracy.md). Prints CSV on stdout,
// one row per configuration, the median wall time of `--repetitions` runs:
//   case,samples,loss,max_samples,median_s,max_relative_error,converged,is_default
// Cases: "merl" fits a full 90x90x180 MERL table tabulated from an analytic blinn-phong (the
// cells above the horizon); "random" fits N uniformly random (wi, wo) pairs, as libbsdf's
// lbfit draws 100,000 random samples. Both are noise-free; "merl-ggx", "random-ggx",
// "merl-beckmann" and "random-beckmann" are the same for the microfacet rungs. The sweeps that
// follow add Gaussian noise, so their error measures what the sample count and the loss buy:
// "noisy", 1% of each value (multiplicative, as from a calibration or a gain), and "additive", 1%
// of the mean value (as from a detector's read noise); "noisy-ggx" and "noisy-beckmann" are the
// multiplicative sweep of the microfacet truths with the default and the log loss, one draw of the
// noise per repetition and the median error over the draws. `is_default` is 1 when the loss and the
// subsample size are FitOptions' defaults (what `brdf fit` runs).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "core/angles.h"
#include "fitters/fit.h"
#include "io/merl.h"
#include "models/model_string.h"

namespace brdf {
namespace {

const char* kTruth = "blinn-phong:rho_d=0.3,0.2,0.1:rho_s=0.2,0.25,0.3:m=300";
// The microfacet rungs on the same two tables (a glossy dielectric coat over a coloured base).
const char* kMicrofacetTruths[] = {"ggx:rho_d=0.3,0.2,0.1:f0=0.04,0.05,0.06:alpha=0.15",
                                   "beckmann:rho_d=0.3,0.2,0.1:f0=0.04,0.05,0.06:alpha=0.15"};

Measurement MerlMeasurement(const Model& truth) {
  const MerlTable table =
      MerlTable::Tabulate([&](const Vec3& wi, const Vec3& wo) { return truth.Eval(wi, wo); });
  Measurement measurement = table.ToMeasurement();
  measurement.format = "merl";
  return measurement;
}

Vec3 UniformHemisphere(std::mt19937_64& random) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double z = uniform(random), phi = 2 * kPi * uniform(random);
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

enum class Noise { kRelative, kAdditive };

// Gaussian noise of one standard deviation `noise` times the value (kRelative) or times the
// channel's mean value over the samples (kAdditive).
Measurement RandomMeasurement(const Model& truth, size_t count, uint64_t seed, double noise,
                              Noise kind = Noise::kRelative) {
  Measurement measurement;
  measurement.format = "random";
  std::mt19937_64 random(seed);
  std::normal_distribution<double> gaussian;
  std::vector<Rgb> draws;  // standard normal, one per channel and sample
  Rgb mean = Rgb::Zero();
  for (size_t k = 0; k < count; ++k) {
    Sample sample;
    sample.wi = UniformHemisphere(random);
    sample.wo = UniformHemisphere(random);
    sample.value = truth.Eval(sample.wi, sample.wo);
    Rgb draw;
    for (int c = 0; c < 3; ++c) draw[c] = gaussian(random);
    draws.push_back(draw);
    mean += sample.value / static_cast<double>(count);
    measurement.samples.push_back(sample);
  }
  for (size_t k = 0; k < count; ++k) {
    Sample& sample = measurement.samples[k];
    for (int c = 0; c < 3; ++c) {
      const double scale = kind == Noise::kRelative ? sample.value[c] : mean[c];
      sample.value[c] += noise * scale * draws[k][c];
    }
  }
  return measurement;
}

double MaxRelativeError(const Model& fitted, const Model& truth) {
  double worst = 0;
  for (size_t p = 0; p < truth.params().size(); ++p) {
    worst = std::max(worst, std::abs(fitted.params()[p] / truth.params()[p] - 1));
  }
  return worst;
}

// Repetition r fits draws[r % draws.size()]: one measurement timed repeatedly, or one draw of
// the noise per repetition, whose errors' median is printed (a parameter the samples pin
// poorly scatters by its standard error from draw to draw; one draw would show that scatter
// rather than the trend with the sample count).
void Run(const char* name, const std::vector<Measurement>& draws, const Model& truth,
         fitters::Loss loss, size_t max_samples, int repetitions) {
  fitters::FitOptions options;
  options.loss = loss;
  options.max_samples = max_samples;
  std::vector<double> times, errors;
  bool converged = true;
  size_t samples = 0;
  for (int r = 0; r < repetitions; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const fitters::FitResult fit =
        fitters::FitModel(draws[r % draws.size()], truth.name(), options);
    times.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    errors.push_back(MaxRelativeError(fit.model, truth));
    converged = converged && fit.converged;
    samples = fit.samples;
  }
  std::sort(times.begin(), times.end());
  std::sort(errors.begin(), errors.end());
  const double error = errors[errors.size() / 2];
  const fitters::FitOptions defaults;
  const bool is_default = loss == defaults.loss && max_samples == defaults.max_samples;
  std::printf("%s,%zu,%s,%zu,%.4f,%.3g,%d,%d\n", name, samples, fitters::LossName(loss),
              max_samples, times[times.size() / 2], error, converged ? 1 : 0, is_default ? 1 : 0);
  std::fflush(stdout);
}
void Run(const char* name, const Measurement& measurement, const Model& truth, fitters::Loss loss,
         size_t max_samples, int repetitions) {
  Run(name, std::vector<Measurement>{measurement}, truth, loss, max_samples, repetitions);
}

}  // namespace
}  // namespace brdf

int main(int argc, char** argv) {
  using namespace brdf;
  int repetitions = 5;
  bool quick = false;
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--quick") == 0) quick = true;
    if (std::strncmp(argv[k], "--repetitions=", 14) == 0) repetitions = std::atoi(argv[k] + 14);
  }
  const Model truth = ParseModel(kTruth);
  const fitters::FitOptions defaults;
  std::printf("case,samples,loss,max_samples,median_s,max_relative_error,converged,is_default\n");
  Run("merl", MerlMeasurement(truth), truth, defaults.loss, defaults.max_samples, repetitions);
  Run("random", RandomMeasurement(truth, 100000, 11, 0.0), truth, defaults.loss,
      defaults.max_samples, repetitions);
  // The same cases for ggx and beckmann, in the same run: their time next to blinn-phong's.
  for (const char* text : kMicrofacetTruths) {
    const Model microfacet = ParseModel(text);
    const std::string merl = "merl-" + microfacet.name();
    const std::string random = "random-" + microfacet.name();
    Run(merl.c_str(), MerlMeasurement(microfacet), microfacet, defaults.loss, defaults.max_samples,
        repetitions);
    Run(random.c_str(), RandomMeasurement(microfacet, 100000, 11, 0.0), microfacet, defaults.loss,
        defaults.max_samples, repetitions);
  }
  // Time and error against sample count, per loss, on data with 1% noise, without
  // subsampling (every solve on all samples) and with the default subsample + polish.
  // --quick keeps the two smallest counts and one run each: a smoke test of the sweep.
  const std::vector<size_t> counts =
      quick ? std::vector<size_t>{1000, 3000}
            : std::vector<size_t>{1000, 3000, 10000, 30000, 100000, 300000, 1000000};
  const int sweep_repetitions = quick ? 1 : std::max(1, (repetitions + 1) / 2);  // 5 -> 3
  const auto sweep = [&](const char* name, const std::vector<size_t>& sample_counts, Noise noise) {
    for (size_t count : sample_counts) {
      const Measurement random = RandomMeasurement(truth, count, 13, 0.01, noise);
      for (fitters::Loss loss :
           {fitters::Loss::kL2, fitters::Loss::kLog, fitters::Loss::kCosineL2}) {
        // Up to max_samples the subsample is every sample: the two settings are the same fit.
        if (count > defaults.max_samples) Run(name, random, truth, loss, 0, sweep_repetitions);
        Run(name, random, truth, loss, defaults.max_samples, sweep_repetitions);
      }
    }
  };
  sweep("noisy", counts, Noise::kRelative);
  // The losses under the other noise, at three sizes (the full sweep above shows the trend).
  sweep("additive", quick ? std::vector<size_t>{1000} : std::vector<size_t>{1000, 10000, 100000},
        Noise::kAdditive);
  // The microfacet rungs under the same multiplicative noise, with the default loss and the log
  // loss (its maximum-likelihood estimate): what the sample count, the subsample and the loss
  // buy them ("noisy-ggx", "noisy-beckmann"). Their l2 fits are ruled by the few brightest
  // samples (grazing peaks of 1e3 sr^-1, whose noise is largest), so one draw's error scatters
  // widely: each repetition fits its own draw of the noise (seeds 13, 14, ...), and the error is
  // the median over the draws.
  for (const char* text : kMicrofacetTruths) {
    const Model microfacet = ParseModel(text);
    const std::string name = "noisy-" + microfacet.name();
    for (size_t count : counts) {
      std::vector<Measurement> draws;
      for (int r = 0; r < sweep_repetitions; ++r) {
        draws.push_back(RandomMeasurement(microfacet, count, 13 + r, 0.01, Noise::kRelative));
      }
      for (fitters::Loss loss : {defaults.loss, fitters::Loss::kLog}) {
        if (count > defaults.max_samples) {
          Run(name.c_str(), draws, microfacet, loss, 0, sweep_repetitions);
        }
        Run(name.c_str(), draws, microfacet, loss, defaults.max_samples, sweep_repetitions);
      }
    }
  }
  return 0;
}
