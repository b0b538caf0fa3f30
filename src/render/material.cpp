#include "render/material.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/angles.h"
#include "core/colour.h"
#include "core/errors.h"
#include "energy/measured.h"
#include "io/formats.h"
#include "models/model_source.h"

namespace brdf {
namespace {

class ModelMaterial : public Material {
 public:
  explicit ModelMaterial(Model model) : model_(std::move(model)) {
    // The model knows its own lobe: frame and density (models/lobe.h).
    if (model_.info().has_lobe() && model_.LobeWeight().maxCoeff() > 0.0) lobe_ = model_.Lobe();
  }
  Rgb Eval(const Vec3& wi, const Vec3& wo) const override { return model_.Eval(wi, wo); }
  std::string Describe() const override { return model_.ToString(); }
  std::optional<LobeCoordinates> SpecularLobe() const override { return lobe_; }

 private:
  Model model_;
  std::optional<LobeCoordinates> lobe_;
};

// Dense tabulated data (MERL, RGL-EPFL) through the reader's evaluator (Measurement::tabulated,
// wrapped by energy/measured.h); NaN where a MERL cell is missing.
class MeasuredTableMaterial : public Material {
 public:
  MeasuredTableMaterial(MeasuredBrdf measured, std::string lookup_name)
      : measured_(std::move(measured)), lookup_name_(std::move(lookup_name)) {}
  Rgb Eval(const Vec3& wi, const Vec3& wo) const override {
    if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
    return measured_.brdf(wi, wo).value;
  }
  std::string Describe() const override { return measured_.source + " (" + lookup_name_ + ")"; }

 private:
  MeasuredBrdf measured_;
  std::string lookup_name_;
};

// Scattered data: the shared inverse-distance interpolant (energy/measured.h), tabulated once
// at the centres of a 32^3 half/difference grid so that a preview's millions of lookups cost
// one index each (see material.h).
class TabulatedMaterial : public Material {
 public:
  static constexpr int kBins = 32;

  TabulatedMaterial(const Measurement& measurement)
      : description_(measurement.source + " (" + measurement.format +
                     ", inverse-distance interpolation tabulated on a 32^3 half/difference "
                     "grid)") {
    const MeasuredBrdf measured = ScatteredMeasuredBrdf(measurement);
    cells_.resize(kBins * kBins * kBins);
    tbb::parallel_for(0, kBins * kBins * kBins, [&](int cell) {
      const int index[3] = {cell / (kBins * kBins), (cell / kBins) % kBins, cell % kBins};
      HalfDiff centre;
      centre.theta_h = (index[0] + 0.5) / kBins * kRange[0];
      centre.theta_d = (index[1] + 0.5) / kBins * kRange[1];
      centre.phi_d = (index[2] + 0.5) / kBins * kRange[2];
      Vec3 wi, wo;
      FromHalfDiff(centre, &wi, &wo);
      // A cell whose centre lies below the horizon still holds above-horizon pairs near its
      // edge: fill it too, from the nearest data (the interpolant accepts any directions).
      cells_[cell] = measured.brdf(wi, wo).value;
    });
    lobe_ = EstimateLobe();
  }

  Rgb Eval(const Vec3& wi, const Vec3& wo) const override {
    if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
    const HalfDiff hd = ToHalfDiff(wi, wo);
    const double coordinates[3] = {hd.theta_h, hd.theta_d, std::fmod(hd.phi_d + 2 * kPi, kPi)};
    // Trilinear between cell centres (nearest-cell lookups drew the grid as rings around a
    // highlight). theta_h and theta_d clamp at the ends; phi_d is periodic with period pi.
    int low[3], high[3];
    double t[3];
    for (int d = 0; d < 3; ++d) {
      const double u = coordinates[d] / kRange[d] * kBins - 0.5;
      const int below = static_cast<int>(std::floor(u));
      t[d] = u - below;
      if (d == 2) {
        low[d] = (below + kBins) % kBins;
        high[d] = (below + 1) % kBins;
      } else {
        low[d] = std::clamp(below, 0, kBins - 1);
        high[d] = std::clamp(below + 1, 0, kBins - 1);
      }
      if (!(t[d] >= 0.0 && t[d] <= 1.0)) t[d] = 0.0;  // NaN directions: any corner
    }
    Rgb value = Rgb::Zero();
    for (int corner = 0; corner < 8; ++corner) {
      double weight = 1.0;
      int index[3];
      for (int d = 0; d < 3; ++d) {
        const bool upper = (corner >> d) & 1;
        index[d] = upper ? high[d] : low[d];
        weight *= upper ? t[d] : 1.0 - t[d];
      }
      if (weight > 0.0) value += weight * cells_[(index[0] * kBins + index[1]) * kBins + index[2]];
    }
    return value;
  }
  std::string Describe() const override { return description_; }
  std::optional<LobeCoordinates> SpecularLobe() const override { return lobe_; }

 private:
  static constexpr double kRange[3] = {kPi / 2, kPi / 2, kPi};

  // A half-vector lobe for the renderer to draw from, read off the table: the luminance
  // profile over theta_h (averaged over phi_d and theta_d below 45 deg, away from grazing)
  // falls from its peak at theta_h = 0 to half its height above the floor at theta_half; the
  // power cosine with cos^m(theta_half) = 1/2 has the same half width. Any density keeps the
  // estimate unbiased (MIS); a matching one only lowers the noise. None when the profile has no
  // peak worth the name (less than twice its floor): a diffuse sample needs only the cosine.
  std::optional<LobeCoordinates> EstimateLobe() const {
    std::vector<double> profile(kBins, 0.0);
    for (int h = 0; h < kBins; ++h) {
      for (int d = 0; d < kBins / 2; ++d) {
        for (int p = 0; p < kBins; ++p) {
          profile[h] += Luminance(cells_[(h * kBins + d) * kBins + p]);
        }
      }
    }
    const double peak = profile[0];
    const double floor = *std::min_element(profile.begin(), profile.end());
    if (!(peak > 2.0 * floor) || !std::isfinite(peak)) return std::nullopt;
    int h = 0;
    while (h < kBins && profile[h] - floor > 0.5 * (peak - floor)) ++h;
    const double bin = kRange[0] / kBins;
    const double theta_half = std::max(h * bin, 0.5 * bin);
    const double exponent = std::max(1.0, std::log(0.5) / std::log(std::cos(theta_half)));
    return LobeCoordinates{LobeFrame::kHalfVector, exponent};
  }

  std::string description_;
  std::vector<Rgb> cells_;
  std::optional<LobeCoordinates> lobe_;
};

}  // namespace

std::unique_ptr<Material> ModelMaterialOf(Model model) {
  return std::make_unique<ModelMaterial>(std::move(model));
}

std::unique_ptr<Material> MeasurementMaterialOf(const Measurement& measurement) {
  if (measurement.tabulated != nullptr) {
    const std::string lookup_name = measurement.tabulated->LookupName();
    return std::make_unique<MeasuredTableMaterial>(MeasuredBrdfOf(measurement), lookup_name);
  }
  return std::make_unique<TabulatedMaterial>(measurement);
}

std::unique_ptr<Material> LoadMaterial(const std::string& spec) {
  if (IsModelSpec(spec)) return ModelMaterialOf(LoadModel(spec));
  return MeasurementMaterialOf(ReadMeasurement(spec));
}

}  // namespace brdf
