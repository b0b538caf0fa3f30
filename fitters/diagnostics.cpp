#include "fitters/diagnostics.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <vector>

#include "core/angles.h"
#include "core/format.h"
#include "core/text.h"
#include "fitters/reading_nodes.h"

namespace brdf::fitters {
namespace {

constexpr double kRadToDeg = 180.0 / kPi;

// Lobe edges in units of the lobe's exponent term x = -e ln cos(offset) ~ e offset^2 / 2 (so
// x = (offset / sigma)^2 / 2). The flank runs from offset = sigma/2 (x = 1/8, the lobe at 88 %
// of its peak) to offset = 3 sigma (x = 4.5, the lobe at 1.1 % of its peak). Only there does the
// exponent change the data at first order: d ln(lobe)/d ln(e) = -x, which is below 1/8 nearer
// the peak (where the exponent changes only the normalization, which rho_s absorbs) and acts on
// a lobe below 1 % of its peak farther out (lost under the diffuse floor and the noise).
constexpr double kFlankStart = 1.0 / 8.0;
constexpr double kFlankEnd = 4.5;

// A lobe whose share of the albedo budget, A(e) rho_s, is below this in every channel has
// vanished: the fitter's logistic variable has run to its saturation (fit.cpp holds variables
// beyond |23|, logistic(-23) = 1e-10, out of the covariance), and no measurement resolves an
// albedo of 1e-9.
constexpr double kVanishedLobeShare = 1e-9;

// A lobe is more than noise when it lowers the residual sum of squares by more than the
// chi-square quantile of this normal deviate: z = 3.09 is the one-sided 0.1 % point, so a lobe
// fitted to noise alone passes one time in a thousand, or a few times that, since the fitter also
// chooses the lobe's width and direction among many (Davies, Biometrika 74(1), 1987).
constexpr double kLobeSignificanceZ = 3.09;

// Relative standard error beyond which a parameter is not identifiable: the 1-sigma interval
// of an albedo then includes 0, and an exponent (fitted as log e) is uncertain by more than a
// factor e, its lobe width by more than a factor sqrt(e) = 1.65.
constexpr double kMaxRelativeStderr = 1.0;

// Coverage: the data should see the projected hemisphere (∫ cos dω = π) up to 1 %, the same
// standard as the energy check's coverage warning (docs/energy.md). Directions beyond theta_max
// hold the fraction cos^2(theta_max) of it, so theta_max must reach acos(0.1) = 84.3 deg.
constexpr double kMaxUnseenProjectedFraction = 0.01;

// Outliers: under Gaussian noise of the robust scale, P(|z| > 5) = 5.7e-7. One residual in a
// thousand beyond 5 scales is 1700 times that, and even a million residuals expect fewer than
// one by chance, so noise alone never raises the warning.
constexpr double kOutlierScales = 5.0;
constexpr double kMaxOutlierFraction = 1e-3;
// Residuals below this fraction of the largest data value are rounding, not misfit (a
// noise-free fit leaves ~1e-13 relative), and are never counted as outliers.
constexpr double kRoundingFloor = 1e-9;

// Outliers or misfit: samples beyond 5 scales that neighbour each other in file order more
// often than independent flags would (expected pairs (n-1) p^2 for a flagged share p) by more
// than 5 standard deviations of that count form a region the model cannot follow. 5 sigma, as
// above, so that chance never decides it.
constexpr double kClusteringScore = 5.0;

// Mismatch: with honest sigmas the reduced chi-square is 1 +- sqrt(2/dof), 1 +- 0.01 for 20,000
// residuals. Stated sigmas are estimates themselves (an instrument's error budget is a model
// too; the virtual gonioreflectometer's includes the arm's positioning jitter, docs/gonio.md),
// so the check allows them to be off by a factor of two: it warns when the rms misfit is more
// than twice the stated uncertainty (chi-square > 4).
constexpr double kMaxReducedChiSquare = 4.0;

// Marks a channel without a residual score (scores are absolute values: never negative).
constexpr double kNoScore = -1.0;

// Samples per chunk of the diagnostics' parallel passes.
constexpr size_t kSamplesPerChunk = size_t{1} << 14;
// Scores per chunk of the radix histograms.
constexpr size_t kHistogramGrain = size_t{1} << 18;

// Histogram of bits [shift, shift + 16) of the scores that are not kNoScore and whose bits under
// `mask` equal `prefix`; chunks in parallel, their counts added (integers: any order gives the
// same histogram).
std::vector<size_t> ScoreHistogram(const std::vector<double>& scores, int shift, uint64_t mask,
                                   uint64_t prefix) {
  using Histogram = std::vector<size_t>;
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, scores.size(), kHistogramGrain), Histogram(),
      [&](const tbb::blocked_range<size_t>& range, Histogram histogram) {
        if (histogram.empty()) histogram.assign(size_t{1} << 16, 0);
        for (size_t k = range.begin(); k < range.end(); ++k) {
          const double score = scores[k];
          if (std::signbit(score)) continue;
          uint64_t bits;
          std::memcpy(&bits, &score, sizeof bits);
          if ((bits & mask) == prefix) ++histogram[(bits >> shift) & 0xFFFF];
        }
        return histogram;
      },
      [](Histogram a, const Histogram& b) {
        if (a.empty()) return b;
        for (size_t bucket = 0; bucket < b.size(); ++bucket) a[bucket] += b[bucket];
        return a;
      });
}

// The k-th smallest (from 0) of the scores that are not kNoScore, exactly, without reordering or
// copying them: a radix selection, 16 bits at a time from the top, on the IEEE bit patterns,
// which order non-negative doubles as their values. `top` is the histogram of the top 16 bits.
double KthSmallestScore(const std::vector<double>& scores, size_t k, std::vector<size_t> top) {
  uint64_t prefix = 0, mask = 0;
  std::vector<size_t> histogram = std::move(top);
  for (int shift = 48; shift >= 0; shift -= 16) {
    if (shift != 48) histogram = ScoreHistogram(scores, shift, mask, prefix);
    uint64_t bucket = 0;
    while (k >= histogram[bucket]) k -= histogram[bucket++];
    prefix |= bucket << shift;
    mask |= uint64_t{0xFFFF} << shift;
  }
  double value;
  std::memcpy(&value, &prefix, sizeof value);
  return value;
}

// x = -e ln cos(offset) of one sample: 0 at the lobe's centre, infinity where the lobe is 0.
double LobeExponentTerm(const LobeFrame& frame, double exponent, const Vec3& wi, const Vec3& wo) {
  const double cos_offset = frame.half_vector ? (wi + wo).normalized().z() : frame.Axis(wo).dot(wi);
  if (!(cos_offset > 0)) return std::numeric_limits<double>::infinity();
  return -exponent * std::log(std::min(cos_offset, 1.0));
}

// The diffuse part cannot be unresolved; only the lobes still there are checked. A lobe's weight
// is its share of the albedo (power cosine: A(e) rho_s; a microfacet lobe keeps Schlick's
// grazing rise even at f0 = 0, so it never vanishes).
bool LobeVanished(const Model& model, const LobeInfo& lobe) {
  return !(lobe.weight(model.params().data()) >= kVanishedLobeShare).any();
}

// Whether the lobe's width grows with its parameter (a roughness) or shrinks (an exponent).
bool WidthIsRoughness(const LobeInfo& lobe) {
  return lobe.shape_scale == models::ShapeScale::kRoughness;
}

// "lobe" for a model of one lobe; "first lobe", "second lobe" for a composition of two.
std::string LobeLabel(const Model& model, size_t index) {
  if (model.info().lobes.size() == 1) return "lobe";
  return std::string(index == 0 ? "first" : "second") + " lobe";
}

// "roughness alpha" or "exponent n": the lobe's width parameter.
std::string ShapeName(const Model& model, const LobeInfo& lobe) {
  return (WidthIsRoughness(lobe) ? "roughness " : "exponent ") +
         model.info().ParamAtSlot(lobe.shape_slot).name;
}

// "exponent n = 1e4" or "roughness alpha = 0.05": the lobe's width parameter as fitted.
std::string ShapeText(const Model& model, const LobeInfo& lobe) {
  return ShapeName(model, lobe) + " = " + Format("%.4g", model.params()[lobe.shape_slot]);
}

void CheckLobeResolution(const std::vector<FitSample>& samples, FitResult* result) {
  const Model& model = result->model;
  for (size_t index = 0; index < model.info().lobes.size(); ++index) {
    const LobeInfo& info = model.info().lobes[index];
    if (LobeVanished(model, info)) continue;
    const double exponent = info.equivalent_exponent(model.params().data());
    const LobeFrame frame = info.coordinates(model.params().data()).frame;
    const LobeResolution lobe = ResolveLobe(frame, exponent, samples);
    if (lobe.flank_samples > 0) continue;
    std::string nearest = std::isfinite(lobe.nearest_off_peak_deg)
                              ? Format("%.3g", lobe.nearest_off_peak_deg) + " deg"
                              : std::string("nowhere");
    result->warnings.push_back(
        "lobe narrower than the sample spacing: the fitted " + LobeLabel(model, index) + " (" +
        ShapeText(model, info) + ", half-width " + Format("%.3g", lobe.half_width_deg) +
        " deg in the " + frame.offset_name + ") has no sample on its flank (" +
        Format("%.3g", lobe.half_width_deg / 2) + " to " + Format("%.3g", 3 * lobe.half_width_deg) +
        " deg); the nearest sample off its peak is " + nearest +
        " away, so the data bound the lobe's sharpness from below but do not determine it");
  }
}

void CheckIdentifiability(FitResult* result) {
  const Model& model = result->model;
  if (!result->stderr_available) {
    result->warnings.push_back("not identifiable: " + result->stderr_note);
  }
  std::vector<int> vanished_shapes;  // the width of a vanished lobe: its error means nothing
  for (size_t index = 0; index < model.info().lobes.size(); ++index) {
    const LobeInfo& lobe = model.info().lobes[index];
    const std::string label = LobeLabel(model, index);
    if (LobeVanished(model, lobe)) {
      const ParamInfo& share = model.info().ParamAtSlot(lobe.first_slot);
      const bool alone = model.info().lobes.size() == 1;
      result->warnings.push_back("not identifiable: the " + label + " vanished (" + share.name +
                                 " = 0 in every channel), so its " + ShapeName(model, lobe) +
                                 " is arbitrary; the data show no " + label +
                                 (alone ? " (a lambert fit may be enough)" : ""));
      vanished_shapes.push_back(lobe.shape_slot);  // its box means nothing either
      continue;
    }
    // The box of the width parameter (the lobe's fit range, models/term.h): an exponent in
    // [1, 1e6], or a roughness alpha in [1e-3, 1.5]. Sharper means a larger exponent but a
    // smaller alpha.
    const bool roughness = WidthIsRoughness(lobe);
    const double value = model.params()[lobe.shape_slot];
    const double sharpest = roughness ? lobe.fit_shape_min : lobe.fit_shape_max;
    const double broadest = roughness ? lobe.fit_shape_max : lobe.fit_shape_min;
    const std::string name = ShapeName(model, lobe);
    const std::string whose = model.info().lobes.size() == 1 ? "" : " of the " + label;
    auto at = [&](double bound) { return std::abs(value - bound) <= 1e-3 * bound; };
    if (at(sharpest)) {
      result->warnings.push_back(
          "not identifiable: the " + name + whose + " sits at the fitter's " +
          (roughness ? "lower bound " : "upper bound ") + FormatNumber(sharpest, 6) +
          "; the data ask for a lobe at least this sharp and cannot say "
          "how much sharper");
    } else if (at(broadest)) {
      result->warnings.push_back(
          "not identifiable: the " + name + whose + " sits at the fitter's " +
          (roughness ? "upper bound " : "lower bound ") + FormatNumber(broadest, 6) +
          "; the data ask for a broader lobe than the model has");
    }
  }
  if (!result->stderr_available) return;
  for (const ParamInfo& param : model.info().params) {
    if (std::count(vanished_shapes.begin(), vanished_shapes.end(), param.slot) > 0) continue;
    for (int c = 0; c < param.channels; ++c) {
      const double value = model.params()[param.slot + c];
      const double error = result->stderr_values[param.slot + c];
      // NaN: the parameter sits at its bound (held out of the covariance, fit.cpp), reported
      // as "n/a" already.
      if (!std::isfinite(error) || !(value > 0)) continue;
      if (error > kMaxRelativeStderr * value) {
        std::string channel =
            param.channels == 1 ? std::string() : std::string(" (") + "rgb"[c] + ")";
        result->warnings.push_back("not identifiable: " + param.name + channel + " = " +
                                   Format("%.4g", value) + " +- " + Format("%.3g", error) +
                                   ", a standard error larger than the value");
      }
    }
  }
}

// The chi-square quantile for `dof` degrees of freedom at normal deviate z, by the cube-root
// approximation of Wilson & Hilferty (PNAS 17, 1931); within 1 % from 3 degrees of freedom.
double ChiSquareQuantile(double dof, double z) {
  const double v = 2.0 / (9.0 * dof);
  return dof * std::pow(1.0 - v + z * std::sqrt(v), 3);
}

// The lobe against the model's diffuse term fitted alone to the same samples, loss and weights:
// a likelihood-ratio (extra sum of squares) test, the residual variance estimated from the
// lobed fit, s^2 = RSS / (n - p). A lobe that lowers the RSS by less than the quantile in units of
// s^2 is what noise alone gives: its standard errors may still be smaller than its values, since
// the fit chose the lobe that fits the noise best.
void CheckLobeSignificance(const FitResult& diffuse_only, FitResult* result) {
  const double n = 3.0 * static_cast<double>(result->samples);
  const double rss = 2.0 * result->final_cost, rss_diffuse = 2.0 * diffuse_only.final_cost;
  const int extra = result->free_variables - diffuse_only.free_variables;
  if (!(rss > 0) || extra <= 0 || n <= result->free_variables) return;
  const double drop = (rss_diffuse - rss) / (rss / (n - result->free_variables));
  const double needed = ChiSquareQuantile(extra, kLobeSignificanceZ);
  if (drop >= needed) return;
  result->warnings.push_back(
      "not identifiable: the lobe is no more than noise; it lowers the residual sum of squares "
      "by " +
      Format("%.3g", drop) + " times the residual variance against " +
      result->model.info().diffuse + " alone, where noise fitted by " + std::to_string(extra) +
      " more variables gives up to " + Format("%.3g", needed) + " (0.1 %)");
}

void CheckCoverage(const std::vector<FitSample>& samples, FitResult* result) {
  if (samples.empty()) return;
  // The smallest cosine of either direction: the largest polar angle the data reach (a minimum,
  // the same in any order, so taken in parallel).
  const double min_cos = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, samples.size(), kSamplesPerChunk), 1.0,
      [&](const tbb::blocked_range<size_t>& range, double partial) {
        for (size_t k = range.begin(); k < range.end(); ++k) {
          partial = std::min({partial, samples[k].wi.z(), samples[k].wo.z()});
        }
        return partial;
      },
      [](double a, double b) { return std::min(a, b); });
  const double unseen = min_cos * min_cos;  // cos^2(theta_max): projected solid angle beyond
  if (unseen <= kMaxUnseenProjectedFraction) return;
  const double theta_max_deg = std::acos(std::clamp(min_cos, 0.0, 1.0)) * kRadToDeg;
  result->warnings.push_back(
      "coverage: the data reach theta = " + Format("%.3g", theta_max_deg) + " deg at most, so " +
      Format("%.2g", 100 * unseen) +
      " % of the projected hemisphere is unobserved: the model's grazing behaviour (Fresnel "
      "rise, shadowing) is extrapolated there, not fitted");
}

void CheckResidualWarnings(const PreparedSamples& prepared, FitResult* result) {
  const ResidualCheck check = CheckResiduals(result->model, prepared);
  if (check.residuals == 0) return;
  const double fraction = static_cast<double>(check.beyond_5_scale) / check.residuals;
  const bool clustered = check.clustering_z > kClusteringScore;
  if (fraction > kMaxOutlierFraction && clustered) {
    result->warnings.push_back(
        "model mismatch: " + std::to_string(check.flagged_samples) +
        " samples lie beyond 5 robust standard deviations of the fit in contiguous runs (" +
        std::to_string(check.adjacent_flagged_pairs) + " neighbouring pairs, " +
        Format("%.3g", check.clustering_z) +
        " standard deviations more than isolated outliers would give): a region the model "
        "cannot follow, not scattered bad readings");
  } else if (fraction > kMaxOutlierFraction) {
    const std::string what = check.has_sigma ? "z-scores" : "relative residuals";
    result->warnings.push_back(
        "outliers: " + std::to_string(check.beyond_5_scale) + " of " +
        std::to_string(check.residuals) + " values (" + Format("%.2g", 100 * fraction) +
        " %) lie beyond 5 robust standard deviations of the " + what +
        ", where Gaussian noise puts 6e-5 %" +
        (result->robust == Robust::kNone ? "; a robust loss (cauchy) bounds their pull" : ""));
  }
  if (!clustered && check.has_sigma && check.reduced_chi_square > kMaxReducedChiSquare) {
    result->warnings.push_back(
        "model mismatch: reduced chi-square " + Format("%.3g", check.reduced_chi_square) +
        " against the file's sigma (rms misfit " +
        Format("%.2g", std::sqrt(check.reduced_chi_square)) +
        " x the stated uncertainty): the model does not represent these data within their noise");
  }
}

}  // namespace

LobeResolution ResolveLobe(const LobeFrame& frame, double exponent,
                           const std::vector<FitSample>& samples) {
  LobeResolution lobe;
  lobe.half_width_deg = std::acos(std::exp(-0.5 / exponent)) * kRadToDeg;
  lobe.nearest_off_peak_deg = std::numeric_limits<double>::infinity();
  if (frame.AboutNormal()) return lobe;
  // The offset acos(exp(-x / e)) grows with x: the nearest sample off the peak is the one of
  // least x, so one offset is taken, not one a sample. Counts and a minimum are the same in any
  // order, so the samples are scanned in parallel.
  struct Scan {
    size_t peak = 0, flank = 0;
    double nearest_x = std::numeric_limits<double>::infinity();
  };
  const Scan scan = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, samples.size()), Scan{},
      [&](const tbb::blocked_range<size_t>& range, Scan partial) {
        for (size_t k = range.begin(); k < range.end(); ++k) {
          const double x = LobeExponentTerm(frame, exponent, samples[k].wi, samples[k].wo);
          if (x < kFlankStart) {
            ++partial.peak;
            continue;
          }
          if (x <= kFlankEnd) ++partial.flank;
          partial.nearest_x = std::min(partial.nearest_x, x);
        }
        return partial;
      },
      [](Scan a, const Scan& b) {
        a.peak += b.peak;
        a.flank += b.flank;
        a.nearest_x = std::min(a.nearest_x, b.nearest_x);
        return a;
      });
  lobe.peak_samples = scan.peak;
  lobe.flank_samples = scan.flank;
  const double nearest_x = scan.nearest_x;
  if (std::isfinite(nearest_x)) {
    lobe.nearest_off_peak_deg = std::acos(std::exp(-nearest_x / exponent)) * kRadToDeg;
  }
  return lobe;
}

ResidualCheck CheckResiduals(const Model& model, const PreparedSamples& prepared) {
  ResidualCheck check;
  check.has_sigma = !prepared.sigma.empty();
  const std::vector<FitSample>& samples = prepared.samples;
  const size_t usable = samples.size();
  // The largest value, for the rounding floor.
  const double largest = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, usable, kSamplesPerChunk), 0.0,
      [&](const tbb::blocked_range<size_t>& range, double partial) {
        for (size_t u = range.begin(); u < range.end(); ++u) {
          partial = std::max(partial, samples[u].value.abs().maxCoeff());
        }
        return partial;
      },
      [](double a, double b) { return std::max(a, b); });
  // |z| of each channel of each sample, in file order; kNoScore where a channel has none. The
  // model predicts each reading as the fit did: through the instrument when there is one.
  const SampleNodes nodes = prepared.instrument != nullptr
                                ? InstrumentNodes(*prepared.instrument, model, samples)
                                : SampleNodes{};
  const SampleNodes* through = prepared.instrument != nullptr ? &nodes : nullptr;
  std::vector<double> scores(3 * usable, kNoScore);
  const auto score_sample = [&](size_t u) {
    const FitSample& sample = samples[u];
    const Rgb f = PredictReading(model, samples, through, u);
    for (int c = 0; c < 3; ++c) {
      double difference = sample.value[c] - f[c];
      if (std::abs(difference) <= kRoundingFloor * largest) difference = 0;
      double score;
      if (check.has_sigma) {
        const double sigma = prepared.sigma[u][c];
        if (!(sigma > 0) || !std::isfinite(sigma)) continue;
        score = difference / sigma;
      } else {
        // Without sigma, relative residuals: the noise of an instrument that counts photons
        // grows with the signal, so relative errors are comparable from floor to peak.
        if (!(f[c] > 0)) continue;
        score = difference / f[c];
      }
      scores[3 * u + c] = std::abs(score);
    }
  };
  tbb::parallel_for(tbb::blocked_range<size_t>(0, usable, kSamplesPerChunk),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t u = range.begin(); u < range.end(); ++u) score_sample(u);
                    });
  std::vector<size_t> top = ScoreHistogram(scores, 48, 0, 0);
  check.residuals = std::accumulate(top.begin(), top.end(), size_t{0});
  if (check.residuals == 0) return check;
  check.robust_scale = 1.4826 * KthSmallestScore(scores, check.residuals / 2, std::move(top));
  // The chi-square is taken over the inliers, so that a few outliers (reported on their own)
  // do not pass for a misfit of the whole model. Runs in file order (the order an instrument
  // sweeps its detector): isolated outliers neighbour each other by chance, a misfit region in
  // runs.
  double chi_square = 0;
  size_t inliers = 0, pairs = 0;
  bool previous_flagged = false;
  for (size_t u = 0; u < usable; ++u) {
    bool flagged = false;
    for (int c = 0; c < 3; ++c) {
      const double score = scores[3 * u + c];
      if (std::signbit(score)) continue;
      if (score > 0 && score > kOutlierScales * check.robust_scale) {
        ++check.beyond_5_scale;
        flagged = true;
      } else {
        chi_square += score * score;
        ++inliers;
      }
    }
    check.flagged_samples += flagged;
    pairs += previous_flagged && flagged;
    previous_flagged = flagged;
  }
  if (check.has_sigma && inliers > 0) check.reduced_chi_square = chi_square / inliers;
  check.adjacent_flagged_pairs = pairs;
  if (usable > 1 && check.flagged_samples > 0) {
    const double p = static_cast<double>(check.flagged_samples) / usable;
    const double expected = (usable - 1) * p * p;
    check.clustering_z = (pairs - expected) / std::sqrt(expected * (1 - p * p) + 1e-300);
  }
  return check;
}

void AppendFitDiagnostics(const PreparedSamples& prepared, FitResult* result,
                          const FitResult* diffuse_only) {
  if (!result->converged) {
    result->warnings.push_back(
        "not converged: the final solve stopped without meeting its "
        "tolerances (" +
        result->termination + "); the parameters are the best found, not an optimum");
  }
  CheckIdentifiability(result);
  const Model& model = result->model;
  const auto& lobes = model.info().lobes;
  if (std::any_of(lobes.begin(), lobes.end(),
                  [&](const LobeInfo& lobe) { return !LobeVanished(model, lobe); })) {
    if (diffuse_only != nullptr) CheckLobeSignificance(*diffuse_only, result);
    if (prepared.instrument == nullptr) {
      CheckLobeResolution(prepared.samples, result);
    } else {
      // Through an instrument a reading sees every direction of its apertures: the lobe is
      // resolved where their quadrature nodes reach its flank (reading_nodes.h).
      const SampleNodes nodes =
          InstrumentNodes(*prepared.instrument, result->model, prepared.samples);
      std::vector<FitSample> seen(nodes.nodes.size());
      for (size_t n = 0; n < seen.size(); ++n) {
        seen[n].wi = nodes.nodes[n].wi;
        seen[n].wo = nodes.nodes[n].wo;
      }
      CheckLobeResolution(seen, result);
    }
  }
  CheckCoverage(prepared.samples, result);
  CheckResidualWarnings(prepared, result);
}

}  // namespace brdf::fitters
