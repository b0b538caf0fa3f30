// RGL-EPFL material files (Dupuy & Jakob, "An Adaptive Parameterization for Efficient Material
// Acquisition and Rendering", TOG 37(6), 2018; rgl.epfl.ch/materials): a tensor_file
// (io/tensor_file.h) whose fields are
//   description  u8 text             theta_i, phi_i  f32 incidence nodes (radians)
//   ndf, sigma   f32 [phi, theta]    the microfacet distribution D(wm) and the projected area
//                                    sigma(wi) = ∫ D(wm) <wi, wm> dwm, tabulated in the unit
//                                    square (u_theta = sqrt(2 theta / pi), u_phi = (phi + pi) /
//                                    (2 pi))
//   vndf         f32 [phi_i, theta_i, rows, cols]  the visible-normal density per incidence,
//                                    whose warp (io/warp_2d.h) maps the unit square onto u_wm
//   rgb          f32 [phi_i, theta_i, 3, N, N]     the measurement, at the nodes of the square
//                                    before that warp (or `spectra` [.., n, N, N] plus
//                                    `wavelengths` for spectral files)
//   jacobian     u8 [1]              1: the values leave out the warp's ndf / (4 sigma) factor
//   luminance, valid                 for importance sampling / bookkeeping; not used here.
// The stored value, times ndf(wm) / (4 sigma(wi)), is f cos(theta_o) (the reference code
// rgl-epfl/brdf-loader documents its eval as "f_r * cos"); brdfkit reports f (DESIGN §1).
// Evaluation, after the paper and its reference code: half vector wm -> u_wm (isotropic files
// measure phi_m from phi_i) -> the vndf warp inverted at u_wm, conditioned on (phi_i, theta_i)
// -> the rgb table interpolated there (bilinearly, and linearly between incidence nodes) ->
// negative (out-of-gamut) channels clipped to 0 -> times ndf(u_wm) / (4 sigma(u_wi)).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/measurement.h"
#include "io/formats.h"
#include "io/tensor_file.h"
#include "io/warp_2d.h"

namespace brdf {

class RglBrdf : public TabulatedBrdf, public CellMeasure {
 public:
  // Validates the fields (ranks, dtypes, shapes that agree, finite values, non-empty vndf
  // slices). Throws ByteError naming the field's table entry or the offending value.
  static std::shared_ptr<const RglBrdf> FromTensor(const TensorFile& file,
                                                   const ReadOptions& options = {});

  // f in sr^-1, as the format's authors and Mitsuba 3's `measured` plugin evaluate it (DESIGN
  // §4): wi is the tensor's incidence and f = the stored f cos(theta_o) / cos(theta_o). Measured
  // data are not reciprocal at grazing, so f(wi, wo) and f(wo, wi) can differ. With
  // ReadOptions::reciprocal the table is read with the more grazing direction as the light
  // instead, f(wi, wo) = f(wo, wi) by construction: the stored value is then divided by the
  // larger of the two cosines, never by a vanishing one (a grazing view divides a small, noisy
  // value by it), at the price of not being the measurement where the light is the more grazing.
  Rgb Eval(const Vec3& wi, const Vec3& wo) const override;
  bool reciprocal() const { return reciprocal_; }
  // What the file stores, in its own orientation (wi the light): f cos(theta_o), zero below
  // the horizon.
  Rgb EvalCosine(const Vec3& wi, const Vec3& wo) const;
  std::string Describe() const override;
  std::string LookupName() const override;
  // For previews (DESIGN §8): the table of f cos(theta_o) at the nodes, the jacobian factor
  // included, interpolated as the stored values are. The nodes keep their values; between
  // them the reference interpolates the stored value and multiplies by ndf(wm), whose fall
  // over a cell the stored values undo at the nodes only, which scallops f between the nodes
  // into rings on a sphere (docs/hdr.md).
  // Made on each call (a render or a view asks once): reads, fits and energy never pay for it.
  std::shared_ptr<const TabulatedBrdf> PreviewEvaluator() const override;
  double Measure(const Vec3& wi, const Vec3& wo) const override;  // CellMeasure
  std::string Name() const override;

  // One node of the stored grid: incidence (phi_index, theta_index), grid position (row, col).
  struct Node {
    Vec3 wi, wo;
    Rgb stored;                    // the file's value, negative channels clipped to 0
    double jacobian_factor = 1.0;  // ndf(u_wm) / (4 sigma(u_wi)), or 1 without the flag
    Vec2 u_wm;                     // where the warp puts the node
  };
  Node GridNode(int phi_index, int theta_index, int row, int col) const;

  const std::vector<double>& theta_i() const { return theta_i_; }
  const std::vector<double>& phi_i() const { return phi_i_; }
  int rows() const { return rows_; }
  int cols() const { return cols_; }
  bool isotropic() const { return isotropic_; }
  bool jacobian() const { return jacobian_; }
  const std::string& description() const { return description_; }
  int64_t clipped_negative() const { return clipped_negative_; }  // stored channel values < 0
  Rgb stored_min() const { return stored_min_; }
  Rgb stored_max() const { return stored_max_; }
  const std::string& colour_source() const { return colour_source_; }

 private:
  RglBrdf() = default;
  double StoredChannel(int phi_index, int theta_index, int channel, int row, int col) const;

  std::string source_;
  std::string description_;
  std::string colour_source_;  // "rgb" or how spectra became RGB
  std::vector<double> theta_i_, phi_i_;
  int rows_ = 0, cols_ = 0;
  bool isotropic_ = true, jacobian_ = true, reciprocal_ = false;
  bool factor_in_table_ = false;  // rgb_ holds stored x jacobian factor (the preview's table)
  Warp2D ndf_, sigma_, vndf_, rgb_;
  std::vector<double> rgb_values_;  // [phi_i, theta_i, 3, rows, cols], as stored
  int64_t clipped_negative_ = 0;
  Rgb stored_min_ = Rgb::Zero(), stored_max_ = Rgb::Zero();
};

// The reader registered in formats.cpp: the samples are the tensor's own grid nodes, every
// node of every incidence as (wi, wo, f); the evaluator is attached as `tabulated`.
Measurement ReadRglBsdf(const std::string& path, const ReadOptions& options);
bool SniffRglBsdf(std::string_view head, int64_t file_size);

}  // namespace brdf
