// Trial of a two-lobe `ggx-coat` model against `ggx` on real measurements (docs/real-data.md):
// does a clear coat over a ggx base pay for its extra variable by BIC? Prints CSV on stdout, one
// row per file:
//   variant,file,samples,ggx_bic,ggx_log_rmse,coat_bic,coat_log_rmse,delta_bic,rho_d,f0,alpha,
//   coat_alpha,coat_f0,max_albedo,seconds
// `ggx` is fitted by `brdf fit`'s library (log loss, the real-data table's); the coat model by
// the same residuals (the same samples, weights and log transform), so the two BICs compare.
//
// The model (base ggx with rho_d, f0, alpha; a grey dielectric coat of f0_c = 0.04 and its own
// roughness alpha_c):
//   f = F_c(wi·h) D_c G2_c / (4 cos_i cos_o)
//       + (1 − F_c(cos_i)) (1 − F_c(cos_o)) [rho_d/π + F(wi·h) D G2 / (4 cos_i cos_o)],
// Schlick's F_c with f0_c = 0.04. The base is weighted by the light the coat transmits on the way
// in and on the way out, each at the macroscopic angle: symmetric in wi and wo, so reciprocal.
// Energy: a(wo) = E_c(wo) + (1 − F_c(cos_o)) ∫ (1 − F_c(cos_i)) f_base cos_i dwi
//               ≤ E_c(wo) + (1 − F_c(cos_o)) a_base(wo),
// the coat's own albedo plus the transmitted share of the base's. The trial does not bound it in
// the fit; it integrates the fitted model's albedo over 90 incidence angles (energy library,
// each term in its lobe's coordinates) and prints the largest, which must stay <= 1.
//
// Usage: coat_trial [--ordered] [--fit-coat-f0] FILE...   (bench/real_data's file list;
// docs/real-data.md has the commands). --ordered holds the coat at least as sharp as the base
// (alpha_c <= alpha, a clear coat over flakes); --fit-coat-f0 fits the coat's grey f0 (one more
// variable) instead of fixing it at 0.04.
#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/format.h"
#include "energy/lobe_quadrature.h"
#include "fitters/fit.h"
#include "fitters/fit_samples.h"
#include "io/formats.h"
#include "models/ggx.h"

namespace brdf {
namespace {

using models::Ggx;

constexpr double kCoatF0 = 0.04;  // a clear dielectric coat of index 1.5, unless fitted
// The microfacet rungs' own range of alpha.
constexpr double kMinAlpha = models::GgxLobe::kMinAlpha, kMaxAlpha = models::GgxLobe::kMaxAlpha;
constexpr int kSamplesPerBlock = 256;
constexpr size_t kStartSamples = 20000;
// rho_d (3), f0 (3), alpha, coat alpha; and the coat's f0 where it is fitted.
constexpr int kFreeVariables = 8;

// What the trial varies: whether the coat is held sharper than the base (alpha_c <= alpha), and
// whether its grey f0 is fitted rather than fixed at 0.04.
struct Variant {
  bool ordered = false;
  bool fit_coat_f0 = false;
};

// Blocks: rho_d[3], f0[3], alpha[1], coat_alpha[1], coat_f0[1]. `coat`, `lobe` and `diffuse`
// (1 or 0) keep or drop the coat's lobe, the transmitted base lobe and the transmitted diffuse
// term, for integrating each in its own coordinates.
template <typename T>
void EvalCoat(const T* rho_d, const T* f0, const T& alpha, const T& coat_alpha, const T& coat_f0,
              const Vec3& wi, const Vec3& wo, T* f, double coat = 1, double lobe = 1,
              double diffuse = 1) {
  const double cos_i = wi.z(), cos_o = wo.z();
  if (!(cos_i > 0 && cos_o > 0)) {
    for (int c = 0; c < 3; ++c) f[c] = T(0);
    return;
  }
  const Vec3 h = (wi + wo).normalized();
  const double cos_h = h.z(), cos_d = wi.dot(h);
  const T coat_lobe = T(coat) * models::SchlickFresnel(cos_d, coat_f0) *
                      models::GgxLobe::D<T>(cos_h, coat_alpha) /
                      (T(1) + models::GgxLobe::Lambda<T>(cos_i, coat_alpha) +
                       models::GgxLobe::Lambda<T>(cos_o, coat_alpha)) /
                      T(4 * cos_i * cos_o);
  const T transmitted = (T(1) - models::SchlickFresnel(cos_i, coat_f0)) *
                        (T(1) - models::SchlickFresnel(cos_o, coat_f0));
  const T base_lobe =
      models::GgxLobe::D<T>(cos_h, alpha) /
      (T(1) + models::GgxLobe::Lambda<T>(cos_i, alpha) + models::GgxLobe::Lambda<T>(cos_o, alpha)) /
      T(4 * cos_i * cos_o);
  for (int c = 0; c < 3; ++c) {
    f[c] = coat_lobe + transmitted * (T(diffuse) * rho_d[c] * T(kInvPi) +
                                      T(lobe) * models::SchlickFresnel(cos_d, f0[c]) * base_lobe);
  }
}

// The data as the log loss compares them, log(1 + f cos theta_i).
Rgb LogTarget(const fitters::FitSample& sample) {
  return fitters::LossTarget(fitters::Loss::kLog, sample.value, sample.cos_theta_i());
}

// The log loss's residuals, as fitters/residual.h forms them for every model.
// With `ordered`, the third block is alpha / alpha_c >= 1 rather than alpha: the coat is held
// sharper than the base, as a clear coat over metal flakes is.
struct CoatResidual {
  const fitters::FitSample* samples;
  int count;
  bool ordered;
  template <typename T>
  bool operator()(const T* rho_d, const T* f0, const T* alpha, const T* coat_alpha,
                  const T* coat_f0, T* residuals) const {
    using std::log;
    const T base_alpha = ordered ? alpha[0] * coat_alpha[0] : alpha[0];
    for (int k = 0; k < count; ++k) {
      const fitters::FitSample& sample = samples[k];
      T f[3];
      EvalCoat(rho_d, f0, base_alpha, coat_alpha[0], coat_f0[0], sample.wi, sample.wo, f);
      const Rgb target = LogTarget(sample);
      for (int c = 0; c < 3; ++c) {
        residuals[3 * k + c] =
            (log(T(1) + f[c] * sample.cos_theta_i()) - target[c]) * sample.scale[c];
      }
    }
    return true;
  }
};

struct CoatParams {
  double rho_d[3], f0[3], alpha, coat_alpha, coat_f0 = kCoatF0;
};

// Solves from `start` on `samples`; returns the final cost (half the weighted RSS).
double Solve(const std::vector<fitters::FitSample>& samples, int iterations, Variant variant,
             CoatParams* p) {
  const bool ordered = variant.ordered;
  if (ordered) p->alpha = std::max(1.0, p->alpha / p->coat_alpha);  // the ratio
  ceres::Problem problem;
  for (size_t begin = 0; begin < samples.size(); begin += kSamplesPerBlock) {
    const int count = static_cast<int>(std::min<size_t>(kSamplesPerBlock, samples.size() - begin));
    auto* cost = new ceres::AutoDiffCostFunction<CoatResidual, ceres::DYNAMIC, 3, 3, 1, 1, 1>(
        new CoatResidual{samples.data() + begin, count, ordered}, 3 * count);
    problem.AddResidualBlock(cost, nullptr, p->rho_d, p->f0, &p->alpha, &p->coat_alpha,
                             &p->coat_f0);
  }
  if (variant.fit_coat_f0) {
    problem.SetParameterLowerBound(&p->coat_f0, 0, 0.0);
    problem.SetParameterUpperBound(&p->coat_f0, 0, 1.0);
  } else {
    problem.SetParameterBlockConstant(&p->coat_f0);
  }
  for (int c = 0; c < 3; ++c) {
    problem.SetParameterLowerBound(p->rho_d, c, 0.0);
    problem.SetParameterUpperBound(p->rho_d, c, 1.0);
    problem.SetParameterLowerBound(p->f0, c, 0.0);
    problem.SetParameterUpperBound(p->f0, c, 1.0);
  }
  problem.SetParameterLowerBound(&p->coat_alpha, 0, kMinAlpha);
  problem.SetParameterUpperBound(&p->coat_alpha, 0, kMaxAlpha);
  // Ordered, the ratio is bounded, not the base's alpha itself (which may pass kMaxAlpha).
  problem.SetParameterLowerBound(&p->alpha, 0, ordered ? 1.0 : kMinAlpha);
  problem.SetParameterUpperBound(&p->alpha, 0, ordered ? kMaxAlpha / kMinAlpha : kMaxAlpha);
  ceres::Solver::Options options;
  options.max_num_iterations = iterations;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (ordered) p->alpha *= p->coat_alpha;
  return summary.final_cost;
}

double Rss(const std::vector<fitters::FitSample>& samples, const CoatParams& p) {
  double rss = 0;
  for (const fitters::FitSample& sample : samples) {
    double f[3];
    EvalCoat(p.rho_d, p.f0, p.alpha, p.coat_alpha, p.coat_f0, sample.wi, sample.wo, f);
    const Rgb target = LogTarget(sample);
    for (int c = 0; c < 3; ++c) {
      const double r = (std::log(1 + f[c] * sample.cos_theta_i()) - target[c]) * sample.scale[c];
      rss += r * r;
    }
  }
  return rss;
}

// log_rmse as fitters' metrics define it: solid-angle-weighted, over samples and channels.
double LogRmse(const std::vector<fitters::FitSample>& samples, const CoatParams& p) {
  double weight = 0, sum = 0;
  for (const fitters::FitSample& sample : samples) {
    double f[3];
    EvalCoat(p.rho_d, p.f0, p.alpha, p.coat_alpha, p.coat_f0, sample.wi, sample.wo, f);
    const Rgb target = LogTarget(sample);
    for (int c = 0; c < 3; ++c) {
      const double d = std::log(1 + f[c] * sample.cos_theta_i()) - target[c];
      sum += sample.weight * d * d;
    }
    weight += 3 * sample.weight;
  }
  return std::sqrt(sum / weight);
}

// The largest directional albedo over 90 incidence angles (0 to 89 deg), per channel maximum:
// the coat lobe, the transmitted base lobe and the transmitted diffuse term each integrated in
// their own lobe coordinates.
double MaxAlbedo(const CoatParams& p) {
  const auto term = [&p](double coat, double lobe, double diffuse) -> BrdfFunction {
    return [&p, coat, lobe, diffuse](const Vec3& wi, const Vec3& wo) {
      double f[3];
      EvalCoat(p.rho_d, p.f0, p.alpha, p.coat_alpha, p.coat_f0, wi, wo, f, coat, lobe, diffuse);
      BrdfSample sample;
      sample.value = Rgb(f[0], f[1], f[2]);
      return sample;
    };
  };
  const LobeCoordinates coat_lobe{kHalfVectorFrame, p.coat_alpha,
                                  &models::GgxLobe::kLobeDistribution};
  const LobeCoordinates base_lobe{kHalfVectorFrame, p.alpha, &models::GgxLobe::kLobeDistribution};
  const LobeQuadratureOptions options;
  double worst = 0;
  for (int k = 0; k < 90; ++k) {
    const double theta = DegToRad(k);
    const Vec3 wo(std::sin(theta), 0, std::cos(theta));
    AlbedoEstimate albedo = IntegrateInLobeCoordinates(term(1, 0, 0), wo, coat_lobe, options);
    albedo += IntegrateInLobeCoordinates(term(0, 1, 0), wo, base_lobe, options);
    albedo += IntegrateInLobeCoordinates(term(0, 0, 1), wo, LobeCoordinates{}, options);
    worst = std::max(worst, albedo.albedo.maxCoeff());
  }
  return worst;
}

}  // namespace
}  // namespace brdf

int main(int argc, char** argv) {
  using namespace brdf;
  std::printf(
      "variant,file,samples,ggx_bic,ggx_log_rmse,coat_bic,coat_log_rmse,delta_bic,rho_d,f0,alpha,"
      "coat_alpha,coat_f0,max_albedo,seconds\n");
  Variant variant;
  std::vector<std::string> paths;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--ordered") {
      variant.ordered = true;
    } else if (arg == "--fit-coat-f0") {
      variant.fit_coat_f0 = true;
    } else {
      paths.push_back(arg);
    }
  }
  const std::string variant_name =
      std::string(variant.ordered ? "ordered" : "free") + (variant.fit_coat_f0 ? "+coat_f0" : "");
  for (const std::string& path : paths) {
    const auto start = std::chrono::steady_clock::now();
    const Measurement measurement = ReadMeasurement(path);
    fitters::FitOptions options;
    options.loss = fitters::Loss::kLog;
    const fitters::FitResult ggx = fitters::FitModel(measurement, "ggx", options);
    const fitters::PreparedSamples prepared = fitters::PrepareSamples(measurement);
    const std::vector<fitters::FitSample> subset =
        fitters::Subsample(prepared.samples, kStartSamples, 1);
    // Starts: the ggx fit as the base under a coat of each roughness, and the ggx lobe taken
    // over by the coat above a broader base.
    const double* g = ggx.model.params().data();
    std::vector<CoatParams> starts;
    for (double coat_alpha : {0.02, 0.05, 0.12}) {
      for (double base_alpha : {g[Ggx::kAlpha], 0.3}) {
        starts.push_back({{g[0], g[1], g[2]}, {g[3], g[4], g[5]}, base_alpha, coat_alpha});
      }
    }
    starts.push_back({{g[0], g[1], g[2]}, {g[3], g[4], g[5]}, 0.3, g[Ggx::kAlpha]});
    CoatParams best = starts.front();
    double best_cost = INFINITY;
    for (CoatParams candidate : starts) {
      for (int c = 0; c < 3; ++c) {
        candidate.rho_d[c] = std::clamp(candidate.rho_d[c], 0.0, 1.0);
        candidate.f0[c] = std::clamp(candidate.f0[c], 0.0, 1.0);
      }
      candidate.alpha = std::clamp(candidate.alpha, kMinAlpha, kMaxAlpha);
      candidate.coat_alpha = std::clamp(candidate.coat_alpha, kMinAlpha, kMaxAlpha);
      const double cost = Solve(subset, 60, variant, &candidate);
      if (cost < best_cost) {
        best_cost = cost;
        best = candidate;
      }
    }
    Solve(prepared.samples, 200, variant, &best);
    const double n = 3.0 * prepared.samples.size();
    // The residuals here are the fitter's: the ggx fit's BIC recomputed from them must agree.
    double ggx_rss = 0;
    for (const fitters::FitSample& sample : prepared.samples) {
      const Rgb f = ggx.model.Eval(sample.wi, sample.wo);
      const Rgb target = LogTarget(sample);
      for (int c = 0; c < 3; ++c) {
        const double r = (std::log(1 + f[c] * sample.cos_theta_i()) - target[c]) * sample.scale[c];
        ggx_rss += r * r;
      }
    }
    const double ggx_bic = n * std::log(ggx_rss / n) + ggx.free_variables * std::log(n);
    if (!(std::abs(ggx_bic - ggx.bic) <= 1e-6 * std::abs(ggx.bic))) {
      std::fprintf(stderr,
                   "coat_trial: %s: the BIC of the ggx fit recomputes to %.10g, not %.10g\n",
                   path.c_str(), ggx_bic, ggx.bic);
      return 1;
    }
    const double coat_bic = n * std::log(std::max(Rss(prepared.samples, best), 1e-300) / n) +
                            (kFreeVariables + variant.fit_coat_f0) * std::log(n);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s,%s,%zu,%.8g,%.5g,%.8g,%.5g,%.4g,%s,%s,%.4g,%.4g,%.4g,%.4f,%.1f\n",
                variant_name.c_str(), path.c_str(), prepared.samples.size(), ggx.bic,
                ggx.metrics.log_rmse, coat_bic, LogRmse(prepared.samples, best), coat_bic - ggx.bic,
                Format("%.4g;%.4g;%.4g", best.rho_d[0], best.rho_d[1], best.rho_d[2]).c_str(),
                Format("%.4g;%.4g;%.4g", best.f0[0], best.f0[1], best.f0[2]).c_str(), best.alpha,
                best.coat_alpha, best.coat_f0, MaxAlbedo(best), seconds);
    std::fflush(stdout);
  }
  return 0;
}
