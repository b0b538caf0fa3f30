// Turning a Measurement into the samples a fit uses: which samples count, how much each
// weighs, and the transformed targets of each loss (DESIGN §6).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/measurement.h"
#include "core/vec.h"
#include "gonio/instrument.h"

namespace brdf::fitters {

enum class Loss {
  kL2,        // f_model - f_data
  kLog,       // log(1 + f_model cos theta_i) - log(1 + f_data cos theta_i)  (Löw et al. 2012)
  kCosineL2,  // (f_model - f_data) cos theta_i  (Ngan, Durand & Matusik 2005)
  kSqrt,      // sqrt(f_model cos theta_i + e) - sqrt(f_data cos theta_i + e)  (residual.h)
  kImage,     // sqrt's, on the pixels of rendered spheres (data with an evaluator only)
  kAuto,      // one of the above, by what the data are: ResolveLoss
};
Loss ParseLoss(const std::string& name);
const char* LossName(Loss loss);

// The loss a fit of `measurement` uses for `loss` (DESIGN §6; the benchmark behind it is in
// docs/real-data.md). `auto` is:
//  * `image` for data that can be rendered (an evaluator, Measurement::tabulated: MERL and
//    RGL-EPFL tables): the loss whose fits render closest to the measurement's own render;
//  * `l2` for readings that state their noise (a sigma column, as `brdf measure` writes): the
//    chi-square, whose optimum is the maximum-likelihood one, weighted by the noise the model
//    predicts (fit_composition.h);
//  * `sqrt` otherwise: a sample counts in proportion to its radiance, as in a render.
// Any other loss is itself, except that `image` on data without an evaluator is an InputError
// naming the file.
Loss ResolveLoss(Loss loss, const Measurement& measurement);

// 104 bytes: a MERL table has a million of them. What follows from these (cos theta_i, the
// loss's target) is computed where it is used rather than stored.
struct FitSample {
  Vec3 wi = Vec3::UnitZ(), wo = Vec3::UnitZ();
  Rgb value = Rgb::Zero();  // the data in sr^-1
  Rgb scale = Rgb::Ones();  // sqrt(weight) / sigma per channel: the residual multiplier
  double weight = 1;        // solid-angle weight times the file's weight (mean 1 over the set)

  double cos_theta_i() const { return wi.z(); }
};

// The floor e of the sqrt loss, sr^-1: keeps its derivative finite where f cos theta_i is zero,
// far below the diffuse floor of the darkest real material (rho_d 0.01 gives f 0.003).
inline constexpr double kSqrtLossFloor = 1e-4;

// The data as the loss compares them: f (l2), log(1 + f cos theta_i) (log; values below
// -1/cos theta_i would have no logarithm, and out-of-gamut RGB is only slightly negative, so
// clamping there changes nothing real), f cos theta_i (cosine-l2) or sqrt(f cos theta_i + e)
// (sqrt; negative values clamped to zero likewise).
inline Rgb LossTarget(Loss loss, const Rgb& value, double cos_theta_i) {
  switch (loss) {
    case Loss::kSqrt:
    case Loss::kImage:
      return ((value * cos_theta_i).max(0.0) + kSqrtLossFloor).sqrt();
    case Loss::kLog:
      return (1.0 + (value * cos_theta_i).max(-0.999)).log();
    case Loss::kCosineL2:
      return value * cos_theta_i;
    case Loss::kL2:
    case Loss::kAuto:  // resolved before any sample is compared (ResolveLoss)
      break;
  }
  return value;
}

// Whether a fit uses a measurement's sample: present, finite, both directions above the horizon.
inline bool UsableForFit(const Sample& sample) {
  return !sample.missing && sample.value.allFinite() && sample.wi.z() > 0 && sample.wo.z() > 0;
}

struct PreparedSamples {
  std::vector<FitSample> samples;
  // The file's sigma of each of `samples`, when it has a sigma column (else empty): the residual
  // check's z-scores (diagnostics.h).
  std::vector<Rgb> sigma;
  size_t skipped_missing = 0;  // flagged missing
  size_t skipped_invalid = 0;  // NaN/Inf values, or a direction at or below the horizon
  std::string weighting;       // how the solid-angle weights were found
  bool designed = false;       // a designed schedule's (equal weights; may crowd onto a lobe)
  // The instrument the measurement records (kInstrumentKey), through which the fit predicts
  // every reading (reading_nodes.h); null: the model at the nominal directions.
  std::shared_ptr<const gonio::Instrument> instrument;
};

// The metadata key under which a measurement records its instrument as JSON (`brdf measure`
// writes it; `brdf fit --instrument` sets or, with "none", removes it).
inline constexpr const char* kInstrumentKey = "instrument_json";

// Frees the samples (the counts and names stay) and hands their pages back to the system, once
// the fit and its diagnostics are done with them (a MERL table's samples are 114 MB).
void Release(PreparedSamples* prepared);

// Selects the usable samples and weights each by the solid angle it represents. Weights:
//  * MERL grid: the exact measure of the cell, 4 cos(theta_d) sin(theta_h) sin(theta_d)
//    dtheta_h dtheta_d dphi_d (dwi dwo in half/difference angles; Rusinkiewicz 1998), with
//    the sqrt-warped theta_h widths.
//  * a designed schedule (Measurement::equal_weighting, e.g. `brdf plan`'s): equal weights;
//    the geometries were chosen for what they tell, not to tile the hemisphere.
//  * scattered data: per incidence direction, the area of the detector directions closest to
//    each sample, estimated from the distance to its k-th nearest neighbour (k = 4).
// Weights are normalized to mean 1; the file's weight column multiplies them and its sigma
// columns divide the residuals (the fit then weighs by sigmas predicted from the model:
// fit_composition.h). The samples are the same for every loss: each loss transforms
// the data where it compares them (LossTarget).
//
// Under the `image` loss (a resolved loss: ResolveLoss), the samples are instead the
// measurement's evaluator at the pixels of rendered spheres (image_error.h: ImageLossSamples),
// each standing for itself (equal weights).
PreparedSamples PrepareSamples(const Measurement& measurement, Loss loss = Loss::kL2);

// Unbiased weights (DESIGN §6). A reading's stated sigma is often estimated from the reading
// itself (photon counts, a Monte Carlo estimate's spread): a reading that came out low states
// a smaller sigma and weighs more, which pulls the fit down (Neyman's chi-square; a traced
// surface's lobe came out 6 % too sharp). The fit weighs by the sigma the model predicts
// instead, iteratively. Per channel, the variance the file states as a function of the value,
// v(x) = a + b x + c x^2 (a, b, c >= 0: read, shot and relative noise), is fitted to all
// (value, sigma^2) pairs once. At a model's prediction F_k, how much the stated variances follow
// the readings' own noise is the share lambda in [0, 1] of the least squares
//   sigma_k^2 - v(F_k) = lambda (v(value_k) - v(F_k))
// (pooled over all samples: 1 when every sigma was computed from its reading, 0 when the
// sigmas were computed from noise-free expectations, as `brdf measure` does for model:
// samples), and sample k is weighted by the variance sigma_k^2 - lambda (v(value_k) - v(F_k)):
// what its sigma owes to its own reading is replaced by what the model predicts, what does not
// depend on the value (positioning noise on a lobe's flank) stays.
struct VarianceFunction {
  Rgb a = Rgb::Zero(), b = Rgb::Zero(), c = Rgb::Zero();
  Rgb At(const Rgb& value) const {
    const Rgb x = value.max(0.0);
    return a + b * x + c * x * x;
  }
};
// The variance function of `prepared`'s stated sigma (PreparedSamples::sigma, which must not
// be empty), by least squares of v(value_k) / sigma_k^2 - 1.
VarianceFunction FitVarianceFunction(const PreparedSamples& prepared);
// `samples` with every residual multiplier rescaled from the `stated` sigma (one per sample, in
// their order) to the one predicted at `predicted` (see above); `followed`, when given,
// receives lambda per channel.
std::vector<FitSample> ModelWeighted(const std::vector<FitSample>& samples,
                                     const std::vector<Rgb>& stated,
                                     const VarianceFunction& variance,
                                     const std::vector<Rgb>& predicted, Rgb* followed = nullptr);

// The incidence of every sample (samples of equal wi share one), numbered 0, 1, ... in order of
// first appearance; *count receives the number of incidences.
std::vector<int> IncidenceGroups(const std::vector<FitSample>& samples, int* count);

// A deterministic stratified subsample of at most `max_samples`: every sample in the top 1% by
// luminance (the specular peak, which a uniform draw would miss) plus a seeded uniform draw of
// the rest, whose weights are scaled by the inverse of their inclusion probability so the
// subsample's objective estimates the full one.
std::vector<FitSample> Subsample(const std::vector<FitSample>& samples, size_t max_samples,
                                 uint64_t seed);

}  // namespace brdf::fitters
