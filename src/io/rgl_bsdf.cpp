#include "io/rgl_bsdf.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/angles.h"
#include "core/colour.h"
#include "core/errors.h"
#include "core/text.h"

namespace brdf {
namespace {

// The unit-square coordinates of the paper (section 5.1): u_theta = sqrt(2 theta / pi) puts
// more nodes near the normal and near the mirror direction; u_phi = (phi + pi) / (2 pi).
double ThetaToUnit(double theta) { return std::sqrt(std::max(0.0, theta) * (2.0 / kPi)); }
double PhiToUnit(double phi) { return (phi + kPi) / (2.0 * kPi); }
double UnitToTheta(double u) { return u * u * (0.5 * kPi); }
double UnitToPhi(double u) { return (2.0 * u - 1.0) * kPi; }

// cos(89.9 deg): incidence nodes beyond this are grazing.
constexpr double kGrazingCos = 1.7e-3;

std::string Degrees(const std::vector<double>& radians) {
  std::string text;
  for (double angle : radians) {
    text += (text.empty() ? "" : ", ") + FormatNumber(RadToDeg(angle), 4);
  }
  return text;
}

// The first non-finite value of a field (or -1).
int64_t FirstNonFinite(const std::vector<double>& values) {
  for (size_t k = 0; k < values.size(); ++k) {
    if (!std::isfinite(values[k])) return static_cast<int64_t>(k);
  }
  return -1;
}

class FieldChecker {
 public:
  explicit FieldChecker(const TensorFile& file) : file_(file) {}

  // The values of a required numeric field of rank `ndim`, all finite.
  std::vector<double> Finite(const TensorField& field) const {
    std::vector<double> values = file_.Values(field);
    const int64_t bad = FirstNonFinite(values);
    if (bad >= 0) {
      Fail(TensorFile::ElementOffset(field, bad),
           "field '" + field.name + "' element " + std::to_string(bad) +
               " is NaN or infinite, expected a finite value");
    }
    return values;
  }
  void ExpectExtent(const TensorField& field, size_t axis, uint64_t extent,
                    const std::string& why) const {
    if (field.shape[axis] != extent) {
      Fail(field.entry_offset, "field '" + field.name + "' has shape " + field.ShapeText() +
                                   ", expected " + std::to_string(extent) + " along axis " +
                                   std::to_string(axis) + " (" + why + ")");
    }
  }
  void ExpectAtLeast(const TensorField& field, size_t axis, uint64_t extent) const {
    if (field.shape[axis] < extent) {
      Fail(field.entry_offset, "field '" + field.name + "' has shape " + field.ShapeText() +
                                   ", expected at least " + std::to_string(extent) +
                                   " along axis " + std::to_string(axis));
    }
  }
  [[noreturn]] void Fail(int64_t offset, const std::string& what) const {
    throw ByteError(file_.path(), offset, what);
  }

 private:
  const TensorFile& file_;
};

// Nodes of an incidence parameter: at least one, finite, strictly increasing, within range.
void CheckNodes(const FieldChecker& check, const TensorField& field,
                const std::vector<double>& nodes, double low, double high) {
  for (size_t k = 0; k < nodes.size(); ++k) {
    if (nodes[k] < low - 1e-6 || nodes[k] > high + 1e-6) {
      check.Fail(TensorFile::ElementOffset(field, k),
                 "field '" + field.name + "' value " + FormatNumber(nodes[k]) +
                     " rad is outside [" + FormatNumber(low, 4) + ", " + FormatNumber(high, 4) +
                     "]");
    }
    if (k > 0 && !(nodes[k] > nodes[k - 1])) {
      check.Fail(
          TensorFile::ElementOffset(field, k),
          "field '" + field.name + "' is not strictly increasing at element " + std::to_string(k));
    }
  }
}

}  // namespace

std::shared_ptr<const RglBrdf> RglBrdf::FromTensor(const TensorFile& file,
                                                   const ReadOptions& options) {
  std::shared_ptr<RglBrdf> brdf(new RglBrdf());
  brdf->source_ = file.path();
  brdf->reciprocal_ = options.reciprocal;
  const FieldChecker check(file);

  if (const TensorField* description = file.Find("description")) {
    brdf->description_ = PrintableText(file.Text(*description));
  }
  const TensorField& theta_i = file.Require("theta_i", 1);
  const TensorField& phi_i = file.Require("phi_i", 1);
  check.ExpectAtLeast(theta_i, 0, 1);
  check.ExpectAtLeast(phi_i, 0, 1);
  brdf->theta_i_ = check.Finite(theta_i);
  brdf->phi_i_ = check.Finite(phi_i);
  CheckNodes(check, theta_i, brdf->theta_i_, 0.0, 0.5 * kPi);
  CheckNodes(check, phi_i, brdf->phi_i_, -2.0 * kPi, 2.0 * kPi);
  const uint64_t n_phi = phi_i.shape[0], n_theta = theta_i.shape[0];
  // The reference code's rule: up to two azimuth nodes mean an isotropic material.
  brdf->isotropic_ = n_phi <= 2;
  if (!brdf->isotropic_) {
    const double span = brdf->phi_i_.back() - brdf->phi_i_.front();
    if (std::abs(span - 2.0 * kPi) > 1e-3) {
      check.Fail(phi_i.entry_offset,
                 "anisotropic phi_i spans " + FormatNumber(RadToDeg(span), 4) +
                     " deg; only files covering the full 360 deg (no symmetry reduction) are "
                     "supported");
    }
  }

  // ndf and sigma: 2D tables over the unit square, rows along phi, columns along theta.
  const TensorField& ndf = file.Require("ndf", 2);
  const TensorField& sigma = file.Require("sigma", 2);
  for (const TensorField* field : {&ndf, &sigma}) {
    check.ExpectAtLeast(*field, 0, 2);
    check.ExpectAtLeast(*field, 1, 2);
  }
  brdf->ndf_ = Warp2D(static_cast<int>(ndf.shape[1]), static_cast<int>(ndf.shape[0]),
                      check.Finite(ndf), {}, false);
  brdf->sigma_ = Warp2D(static_cast<int>(sigma.shape[1]), static_cast<int>(sigma.shape[0]),
                        check.Finite(sigma), {}, false);
  const std::vector<double> sigma_values = file.Values(sigma);
  for (size_t k = 0; k < sigma_values.size(); ++k) {
    if (!(sigma_values[k] > 0.0)) {
      check.Fail(TensorFile::ElementOffset(sigma, k),
                 "field 'sigma' element " + std::to_string(k) + " is " +
                     FormatNumber(sigma_values[k]) +
                     ", expected a positive projected area (it divides the value)");
    }
  }

  // The visible-normal density per incidence, as a warp.
  const TensorField& vndf = file.Require("vndf", 4);
  check.ExpectExtent(vndf, 0, n_phi, "one slice per phi_i");
  check.ExpectExtent(vndf, 1, n_theta, "one slice per theta_i");
  check.ExpectAtLeast(vndf, 2, 2);
  check.ExpectAtLeast(vndf, 3, 2);
  std::vector<double> vndf_values = check.Finite(vndf);
  for (size_t k = 0; k < vndf_values.size(); ++k) {
    if (vndf_values[k] < 0.0) {
      check.Fail(TensorFile::ElementOffset(vndf, k),
                 "field 'vndf' element " + std::to_string(k) + " is negative, expected a density");
    }
  }
  const int vndf_cols = static_cast<int>(vndf.shape[3]),
            vndf_rows = static_cast<int>(vndf.shape[2]);
  const int64_t empty = Warp2D::FirstEmptySlice(vndf_cols, vndf_rows, vndf_values);
  if (empty >= 0) {
    check.Fail(TensorFile::ElementOffset(vndf, empty * vndf_cols * vndf_rows),
               "field 'vndf' slice " + std::to_string(empty) +
                   " is all zero, expected a density with a positive integral");
  }
  brdf->vndf_ =
      Warp2D(vndf_cols, vndf_rows, std::move(vndf_values), {brdf->phi_i_, brdf->theta_i_}, true);

  // The measurement: rgb, or spectra converted to RGB once, node by node.
  const TensorField* rgb = file.Find("rgb");
  const TensorField* spectra = file.Find("spectra");
  const TensorField* colour_field = rgb != nullptr ? rgb : spectra;
  if (colour_field == nullptr) {
    check.Fail(file.table_end(), "the field table has neither 'rgb' nor 'spectra' (required)");
  }
  if (colour_field->shape.size() != 5) {
    check.Fail(colour_field->entry_offset,
               "field '" + colour_field->name + "' has shape " + colour_field->ShapeText() +
                   ", expected 5 dimensions [phi_i, theta_i, channels, rows, cols]");
  }
  check.ExpectExtent(*colour_field, 0, n_phi, "one slice per phi_i");
  check.ExpectExtent(*colour_field, 1, n_theta, "one slice per theta_i");
  check.ExpectAtLeast(*colour_field, 3, 2);
  check.ExpectAtLeast(*colour_field, 4, 2);
  brdf->rows_ = static_cast<int>(colour_field->shape[3]);
  brdf->cols_ = static_cast<int>(colour_field->shape[4]);
  const int64_t grid = int64_t{brdf->rows_} * brdf->cols_;
  const int64_t incidences = static_cast<int64_t>(n_phi * n_theta);
  std::vector<double> stored = check.Finite(*colour_field);
  if (rgb != nullptr) {
    check.ExpectExtent(*rgb, 2, 3, "red, green, blue");
    brdf->rgb_values_ = std::move(stored);
    brdf->colour_source_ = "rgb field (linear sRGB)";
  } else {
    const TensorField& wavelengths = file.Require("wavelengths", 1);
    check.ExpectExtent(*spectra, 2, wavelengths.shape[0], "one channel per wavelength");
    check.ExpectAtLeast(wavelengths, 0, 2);
    const std::vector<double> nm = check.Finite(wavelengths);
    CheckNodes(check, wavelengths, nm, 1.0, 1e5);
    const SpectrumToRgb to_rgb(nm, options.illuminant);
    const int64_t n_lambda = static_cast<int64_t>(nm.size());
    brdf->rgb_values_.assign(incidences * 3 * grid, 0.0);
    std::vector<double> spectrum(n_lambda);
    for (int64_t incidence = 0; incidence < incidences; ++incidence) {
      for (int64_t node = 0; node < grid; ++node) {
        for (int64_t l = 0; l < n_lambda; ++l) {
          spectrum[l] = stored[(incidence * n_lambda + l) * grid + node];
        }
        const Rgb value = to_rgb(spectrum.data());
        for (int c = 0; c < 3; ++c) brdf->rgb_values_[(incidence * 3 + c) * grid + node] = value[c];
      }
    }
    brdf->colour_source_ = "spectra field (" + std::to_string(n_lambda) + " wavelengths, " +
                           FormatNumber(nm.front(), 4) + ".." + FormatNumber(nm.back(), 4) +
                           " nm) through the CIE 1931 observer under " +
                           IlluminantName(options.illuminant);
  }
  brdf->stored_min_ = Rgb::Constant(std::numeric_limits<double>::infinity());
  brdf->stored_max_ = -brdf->stored_min_;
  for (int64_t incidence = 0; incidence < incidences; ++incidence) {
    for (int c = 0; c < 3; ++c) {
      for (int64_t node = 0; node < grid; ++node) {
        const double value = brdf->rgb_values_[(incidence * 3 + c) * grid + node];
        brdf->clipped_negative_ += value < 0.0;
        brdf->stored_min_[c] = std::min(brdf->stored_min_[c], value);
        brdf->stored_max_[c] = std::max(brdf->stored_max_[c], value);
      }
    }
  }
  brdf->rgb_ = Warp2D(brdf->cols_, brdf->rows_, brdf->rgb_values_,
                      {brdf->phi_i_, brdf->theta_i_, {0.0, 1.0, 2.0}}, false);

  const TensorField& jacobian = file.Require("jacobian", 1);
  check.ExpectExtent(jacobian, 0, 1, "one flag");
  const double flag = file.Values(jacobian)[0];
  if (flag != 0.0 && flag != 1.0) {
    check.Fail(TensorFile::ElementOffset(jacobian, 0),
               "field 'jacobian' is " + FormatNumber(flag) + ", expected 0 or 1");
  }
  brdf->jacobian_ = flag == 1.0;
  return brdf;
}

std::shared_ptr<const TabulatedBrdf> RglBrdf::PreviewEvaluator() const {
  if (!jacobian_) return nullptr;  // the stored values are f cos(theta_o) already
  std::shared_ptr<RglBrdf> preview(new RglBrdf(*this));
  const int n_phi = static_cast<int>(phi_i_.size()), n_theta = static_cast<int>(theta_i_.size());
  for (int p = 0; p < n_phi; ++p) {
    for (int t = 0; t < n_theta; ++t) {
      for (int row = 0; row < rows_; ++row) {
        for (int col = 0; col < cols_; ++col) {
          const double factor = GridNode(p, t, row, col).jacobian_factor;
          for (int c = 0; c < 3; ++c) {
            const int64_t slice = (int64_t{p} * n_theta + t) * 3 + c;
            preview->rgb_values_[(slice * rows_ + row) * cols_ + col] *= factor;
          }
        }
      }
    }
  }
  preview->rgb_ =
      Warp2D(cols_, rows_, preview->rgb_values_, {phi_i_, theta_i_, {0.0, 1.0, 2.0}}, false);
  preview->factor_in_table_ = true;
  return preview;
}

double RglBrdf::StoredChannel(int phi_index, int theta_index, int channel, int row, int col) const {
  const int64_t grid = int64_t{rows_} * cols_;
  const int64_t slice =
      (int64_t{phi_index} * static_cast<int64_t>(theta_i_.size()) + theta_index) * 3 + channel;
  return rgb_values_[slice * grid + int64_t{row} * cols_ + col];
}

Rgb RglBrdf::EvalCosine(const Vec3& wi, const Vec3& wo) const {
  if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
  const Vec3 wm = (wi + wo).normalized();
  const double theta_i = Theta(wi), phi_i = std::atan2(wi.y(), wi.x());
  const double theta_m = Theta(wm), phi_m = std::atan2(wm.y(), wm.x());
  const Vec2 u_wi(ThetaToUnit(theta_i), PhiToUnit(phi_i));
  // Isotropic files tabulate the half vector's azimuth relative to the incidence azimuth.
  Vec2 u_wm(ThetaToUnit(theta_m), PhiToUnit(isotropic_ ? phi_m - phi_i : phi_m));
  u_wm.y() -= std::floor(u_wm.y());
  const double incidence[2] = {phi_i, theta_i};
  const Vec2 sample = vndf_.Invert(u_wm, incidence, nullptr);
  Rgb value;
  for (int c = 0; c < 3; ++c) {
    const double parameters[3] = {phi_i, theta_i, static_cast<double>(c)};
    // Out-of-gamut colours are slightly negative; the reference code clips them after the
    // interpolation, per channel.
    value[c] = std::max(0.0, rgb_.Eval(sample, parameters));
  }
  if (jacobian_ && !factor_in_table_) value *= ndf_.Eval(u_wm) / (4.0 * sigma_.Eval(u_wi));
  return value;
}

Rgb RglBrdf::Eval(const Vec3& wi, const Vec3& wo) const {
  if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
  // The file holds f cos(theta_o); see the header for the two readings.
  if (!reciprocal_ || wo.z() >= wi.z()) return EvalCosine(wi, wo) / wo.z();
  return EvalCosine(wo, wi) / wi.z();
}

RglBrdf::Node RglBrdf::GridNode(int phi_index, int theta_index, int row, int col) const {
  Node node;
  const double phi_i = phi_i_[phi_index], theta_i = theta_i_[theta_index];
  node.wi = SphericalDirection(theta_i, phi_i);
  const double incidence[2] = {phi_i, theta_i};
  node.u_wm =
      vndf_.Sample(Vec2(double(col) / (cols_ - 1), double(row) / (rows_ - 1)), incidence, nullptr);
  const double theta_m = UnitToTheta(node.u_wm.x());
  const double phi_m = UnitToPhi(node.u_wm.y()) + (isotropic_ ? phi_i : 0.0);
  const Vec3 wm = SphericalDirection(theta_m, phi_m);
  node.wo = 2.0 * node.wi.dot(wm) * wm - node.wi;
  for (int c = 0; c < 3; ++c) {
    node.stored[c] = std::max(0.0, StoredChannel(phi_index, theta_index, c, row, col));
  }
  if (jacobian_) {
    const Vec2 u_wi(ThetaToUnit(Theta(node.wi)), PhiToUnit(std::atan2(node.wi.y(), node.wi.x())));
    node.jacobian_factor = ndf_.Eval(node.u_wm) / (4.0 * sigma_.Eval(u_wi));
  }
  return node;
}

double RglBrdf::Measure(const Vec3& wi, const Vec3& wo) const {
  if (wi.z() <= 0.0 || wo.z() <= 0.0) return 0.0;
  // The incidence band: from the midpoint to the previous theta_i node to the midpoint to the
  // next (the last band as wide above its node as below, up to the horizon).
  const double theta_i = Theta(wi);
  const int n = static_cast<int>(theta_i_.size());
  int t = 0;
  for (int k = 1; k < n; ++k) {
    if (std::abs(theta_i_[k] - theta_i) < std::abs(theta_i_[t] - theta_i)) t = k;
  }
  double band_low = t > 0 ? 0.5 * (theta_i_[t - 1] + theta_i_[t]) : 0.0;
  double band_high =
      t + 1 < n ? 0.5 * (theta_i_[t] + theta_i_[t + 1])
                : (n > 1 ? theta_i_[t] + 0.5 * (theta_i_[t] - theta_i_[t - 1]) : 0.5 * kPi);
  band_high = std::min(band_high, 0.5 * kPi);
  band_low = std::min(band_low, band_high);
  const double incidence_measure = 2.0 * kPi / static_cast<double>(isotropic_ ? 1 : phi_i_.size()) *
                                   (std::cos(band_low) - std::cos(band_high));

  // The outgoing cell: the node nearest to where (wi, wo) falls in the square before the warp,
  // its cell (clipped to the square) carried through the warp at the cell's centre:
  // dwo = area / pdf(u) * |d wo / d u|, with |d wm / d u| = 2 pi^2 u_theta sin(theta_m) (from
  // theta = u^2 pi / 2, phi = 2 pi u) and dwo = 4 (wi . wm) dwm (reflection).
  const Vec3 wm = (wi + wo).normalized();
  const double phi_i = std::atan2(wi.y(), wi.x());
  Vec2 u_wm(ThetaToUnit(Theta(wm)), PhiToUnit(isotropic_ ? std::atan2(wm.y(), wm.x()) - phi_i
                                                         : std::atan2(wm.y(), wm.x())));
  u_wm.y() -= std::floor(u_wm.y());
  const double incidence[2] = {phi_i, theta_i};
  const Vec2 sample = vndf_.Invert(u_wm, incidence, nullptr);
  const double dx = 1.0 / (cols_ - 1), dy = 1.0 / (rows_ - 1);
  const double col = std::round(sample.x() / dx), row = std::round(sample.y() / dy);
  const double x0 = std::max(0.0, (col - 0.5) * dx), x1 = std::min(1.0, (col + 0.5) * dx);
  const double y0 = std::max(0.0, (row - 0.5) * dy), y1 = std::min(1.0, (row + 0.5) * dy);
  double pdf = 0.0;
  const Vec2 u = vndf_.Sample(Vec2(0.5 * (x0 + x1), 0.5 * (y0 + y1)), incidence, &pdf);
  if (!(pdf > 0.0)) return 0.0;
  const double theta_m = UnitToTheta(u.x());
  const Vec3 centre_wm = SphericalDirection(theta_m, UnitToPhi(u.y()) + (isotropic_ ? phi_i : 0.0));
  const double outgoing_measure = (x1 - x0) * (y1 - y0) / pdf * 2.0 * kPi * kPi * u.x() *
                                  std::sin(theta_m) * 4.0 * std::max(0.0, wi.dot(centre_wm));
  return incidence_measure * outgoing_measure;
}

std::string RglBrdf::Name() const {
  return "RGL grid cell measure (warped node cell solid angle times the theta_i band)";
}

std::string RglBrdf::LookupName() const {
  return factor_in_table_
             ? "RGL-EPFL tensor through the inverse VNDF warp, f cos(theta_o) interpolated"
             : "RGL-EPFL tensor through the inverse VNDF warp";
}

std::string RglBrdf::Describe() const {
  return "RGL-EPFL tensor (Dupuy & Jakob 2018): half vector -> inverse VNDF warp -> " +
         std::to_string(rows_) + "x" + std::to_string(cols_) +
         " table, bilinear, linear between the " + std::to_string(theta_i_.size()) +
         " theta_i nodes; negative channels clipped to 0; f = stored value" +
         (!jacobian_         ? ""
          : factor_in_table_ ? " x ndf/(4 sigma) at the nodes"
                             : " x ndf/(4 sigma)") +
         " / cos(theta_o), " +
         (reciprocal_ ? std::string("read with the more grazing direction as the light "
                                    "(the reciprocal reading, on request)")
                      : std::string("wi the tensor's incidence (the reference reading of the "
                                    "format's authors and Mitsuba 3)"));
}

bool SniffRglBsdf(std::string_view head, int64_t) { return IsTensorFile(head); }

Measurement ReadRglBsdf(const std::string& path, const ReadOptions& options) {
  const TensorFile file = TensorFile::Read(path);
  std::shared_ptr<const RglBrdf> brdf = RglBrdf::FromTensor(file, options);
  Measurement measurement;
  const int n_phi = static_cast<int>(brdf->phi_i().size());
  const int n_theta = static_cast<int>(brdf->theta_i().size());
  measurement.samples.reserve(static_cast<size_t>(n_phi) * n_theta * brdf->rows() * brdf->cols());
  int64_t below_horizon = 0, grazing_nodes = 0;
  for (int p = 0; p < n_phi; ++p) {
    for (int t = 0; t < n_theta; ++t) {
      for (int row = 0; row < brdf->rows(); ++row) {
        for (int col = 0; col < brdf->cols(); ++col) {
          const RglBrdf::Node node = brdf->GridNode(p, t, row, col);
          Sample sample;
          sample.wi = node.wi;
          sample.wo = node.wo;
          // A 90-degree incidence node (paper_white has one) is grazing light that no
          // instrument measures: its values are the fit's extrapolation, not data.
          const bool grazing = node.wi.z() < kGrazingCos;
          sample.missing = node.wo.z() <= 0.0 || grazing;
          below_horizon += node.wo.z() <= 0.0 && !grazing;
          grazing_nodes += grazing;
          // The node's own value; with the reciprocal reading, where the view is the more
          // grazing direction, the evaluator's, so that samples and evaluator agree everywhere.
          if (!sample.missing) {
            sample.value = !brdf->reciprocal() || node.wo.z() >= node.wi.z()
                               ? Rgb(node.stored * node.jacobian_factor / node.wo.z())
                               : brdf->Eval(node.wi, node.wo);
          }
          measurement.samples.push_back(sample);
        }
      }
    }
  }
  auto& metadata = measurement.metadata;
  if (!brdf->description().empty()) metadata["description"] = brdf->description();
  metadata["instrument"] =
      "RGL-EPFL goniophotometer, adaptive parameterization (Dupuy & Jakob 2018)";
  metadata["units"] =
      "BRDF in sr^-1: the file stores f cos(theta_o) (times ndf/(4 sigma) with the jacobian "
      "flag); brdfkit divides by cos(theta_o)";
  metadata["colour"] = brdf->colour_source();
  metadata["grid"] = std::to_string(brdf->rows()) + "x" + std::to_string(brdf->cols()) +
                     " nodes per incidence (rgb), vndf " +
                     std::to_string(file.Find("vndf")->shape[2]) + "x" +
                     std::to_string(file.Find("vndf")->shape[3]) + ", ndf " +
                     file.Find("ndf")->ShapeText() + ", sigma " + file.Find("sigma")->ShapeText();
  metadata["incidence"] = std::to_string(n_theta) + " theta_i (" + Degrees(brdf->theta_i()) +
                          " deg) x " + std::to_string(n_phi) + " phi_i (" + Degrees(brdf->phi_i()) +
                          " deg)" + (brdf->isotropic() ? ", isotropic" : ", anisotropic");
  metadata["samples"] =
      std::string(
          "every grid node of every incidence, carried through the VNDF warp (the "
          "stored value / cos(theta_o)") +
      (brdf->reciprocal() ? " where theta_o <= theta_i, else the reciprocal reading, as the "
                            "evaluation); "
                          : "); ") +
      std::to_string(below_horizon) +
      " nodes whose wo falls at or below the horizon are flagged missing" +
      (grazing_nodes > 0 ? ", and the " + std::to_string(grazing_nodes) +
                               " nodes of the theta_i = 90 deg incidence"
                         : std::string());
  const char* channels[] = {"r", "g", "b"};
  std::string ranges;
  for (int c = 0; c < 3; ++c) {
    ranges += std::string(c ? ", " : "") + channels[c] + " " +
              FormatNumber(brdf->stored_min()[c], 4) + ".." +
              FormatNumber(brdf->stored_max()[c], 4);
  }
  metadata["stored_range"] = ranges + " (as stored, before the jacobian factor and cosine)";
  const int64_t stored_values = int64_t{3} * n_phi * n_theta * brdf->rows() * brdf->cols();
  metadata["clipped_negative"] = std::to_string(brdf->clipped_negative()) + " of " +
                                 std::to_string(stored_values) +
                                 " stored channel values are negative (out of gamut) and are "
                                 "clipped to 0";
  metadata["evaluation"] = brdf->Describe();
  measurement.tabulated = brdf;
  measurement.cell_measure = brdf;
  return measurement;
}

}  // namespace brdf
