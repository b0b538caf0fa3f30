// What a fit can and cannot say: checks of a finished fit against the data it was fitted to,
// each turned into a sentence in FitResult::warnings (the report's "warnings"). They catch the
// failure modes of docs/stability.md:
//
//   * the lobe is narrower than the sample spacing near the peak (no sample on its flank);
//   * a parameter is not identifiable (rank-deficient covariance, a vanished lobe, a lobe that
//     lowers the residuals no more than noise would, an exponent at the box of [1, 1e6], or a
//     standard error larger than the value);
//   * the data do not reach grazing angles (the model is extrapolated there);
//   * the final solve did not converge;
//   * outliers (far more samples beyond 5 robust standard deviations than noise gives);
//   * model mismatch: such samples in contiguous runs, or the inliers off the file's stated
//     uncertainty (reduced chi-square).
//
// Every threshold is derived in diagnostics.cpp, next to the check that uses it.
#pragma once

#include <string>
#include <vector>

#include "core/measurement.h"
#include "fitters/fit.h"
#include "fitters/fit_samples.h"

namespace brdf::fitters {

// How well the samples resolve a lobe in the given frame with the given (power-cosine, or
// equivalent: ModelInfo::equivalent_exponent) exponent. The lobe's offset is the angle between
// wo and the mirror direction of wi (phong) or the half-vector angle theta_h (Blinn family,
// microfacet models); its shape is cos^e(offset) ~ exp(-e offset^2 / 2), a Gaussian of
// half-width sigma = 1/sqrt(e) radians in the offset.
struct LobeResolution {
  double half_width_deg = 0;  // sigma = acos(exp(-1/(2e))) ~ 1/sqrt(e), in degrees
  size_t peak_samples = 0;    // offset < sigma/2: the lobe within 12 % of its peak
  size_t flank_samples = 0;   // sigma/2 <= offset <= 3 sigma: the samples that fix the width
  // Smallest offset at or beyond sigma/2 over all samples, degrees (the spacing seen from the
  // peak); infinity when there is none.
  double nearest_off_peak_deg = 0;
};
LobeResolution ResolveLobe(const LobeFrame& frame, double exponent,
                           const std::vector<FitSample>& samples);

// Statistics of the fitted model's residuals against the values it was fitted to (the fit's
// prepared samples, with the file's sigma where it has one).
struct ResidualCheck {
  size_t residuals = 0;               // channel values compared
  bool has_sigma = false;             // z-scores use the file's sigma; else relative residuals
  double robust_scale = 0;            // 1.4826 x median |z|
  size_t beyond_5_scale = 0;          // |z| > 5 robust_scale (and above the rounding floor)
  double reduced_chi_square = 0;      // mean z^2 of the inliers with the file's sigma (0 without)
  size_t flagged_samples = 0;         // samples with a channel beyond 5 robust_scale
  size_t adjacent_flagged_pairs = 0;  // neighbours in file order both flagged
  // (pairs - expected) / sd for independently flagged samples: large when the flagged samples
  // come in runs (a misfit region) rather than scattered (outliers).
  double clustering_z = 0;
};
ResidualCheck CheckResiduals(const Model& model, const PreparedSamples& prepared);

// Appends every applicable warning to result->warnings, from the fitted model and the samples
// it was fitted to; `diffuse_only`, when given, is the model's diffuse term fitted alone to the
// same samples under the same options, against which a lobe must be more than noise.
void AppendFitDiagnostics(const PreparedSamples& prepared, FitResult* result,
                          const FitResult* diffuse_only = nullptr);

}  // namespace brdf::fitters
