// Importance sampling of tabulated data (MERL tables, RGL-EPFL tensors) for the preview's
// environment estimate (DESIGN §8): a sampler built from the table's own values.
//
// For each of kIncidenceBins viewing angles theta_o (uniform in [0, pi/2), the bin's centre,
// phi_o = 0) a piecewise-constant density of the half vector h over kThetaBins x kPhiBins cells:
// rows uniform in u = sqrt(theta_h / (pi/2)) (MERL's own theta_h warp, which packs cells
// toward the specular peak: the first row ends at theta_h = 0.022 deg), columns uniform in
// phi_h - phi_o over [0, 2 pi). A cell's weight is the luminance of f(wi, wo) cos(theta_i)
// 4 (wo.h), the integrand of the reflected radiance in h (dwi = 4 (wo.h) dh), averaged over
// 2 x 2 points of the cell and times its solid angle; inside a cell h is uniform in solid
// angle. wi is the reflection of wo about h. A pixel uses the bin of its theta_o and turns the
// cells by its phi_o (isotropy; an anisotropic table is sampled as if isotropic, which costs
// noise, not bias: the density below is exact for what is drawn).
//
// Why the half vector and not, say, a 2D table of wi per incidence bin: a glossy lobe is
// narrow in h at every theta_o while its position in wi moves with wo, so one bin serves a
// range of wo without smearing the peak, and the sqrt warp resolves a chrome-like peak with
// cells far smaller than any fixed grid in wi could afford.
#pragma once

#include <functional>
#include <vector>

#include "core/float_math.h"
#include "core/vec.h"
#include "render/material.h"

namespace brdf {

class TableSampler : public DirectionSampler {
 public:
  static constexpr int kIncidenceBins = 32;
  static constexpr int kThetaBins = 64;
  static constexpr int kPhiBins = 64;

  // `brdf`: f(wi, wo) in sr^-1 above the horizon (NaN and negative values count as 0).
  explicit TableSampler(const std::function<Rgb(const Vec3& wi, const Vec3& wo)>& brdf);

  // wi from u in [0, 1)^2 for the view wo (unit, local frame); it may lie below the horizon
  // (the reflection of wo about a half vector), where it carries no weight.
  Vec3 Sample(const Vec3& wo, double u0, double u1) const;
  // The density of wi in solid angle (0 below the horizon or where the table has nothing).
  double Pdf(const Vec3& wo, const Vec3& wi) const;
  void SampleBatch(const Vec3f& wo, const float* u0, const float* u1, int count, float* x, float* y,
                   float* z) const override;
  void PdfBatch(const Vec3f& wo, const float* x, const float* y, const float* z, int count,
                float* pdf) const override;

  // The incidence bin of a viewing angle.
  static int IncidenceBin(double theta_o);
  // Whether bin `bin` has any weight (a table black at that theta_o has none).
  bool HasWeight(int bin) const { return bin_total_[bin] > 0.0; }

 private:
  // A view's bin and the turn of its plane (isotropy).
  struct View {
    Vec3 wo;
    int bin = 0;
    double phi_o = 0.0;
  };
  static View ViewOf(const Vec3& wo);
  Vec3 SampleIn(const View& view, double u0, double u1) const;
  double PdfIn(const View& view, const Vec3& wi) const;

  // Per bin: the cumulative row probabilities (kThetaBins + 1), per row the cumulative column
  // probabilities (kPhiBins + 1), and each cell's density of h per sr.
  std::vector<double> row_cdf_, column_cdf_, density_, bin_total_;
  // 1 - cos(theta_h) at the row edges (kThetaBins + 1).
  std::vector<double> one_minus_cos_edge_;
};

}  // namespace brdf
