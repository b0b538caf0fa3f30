#include "render/material.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/angles.h"
#include "core/colour.h"
#include "core/errors.h"
#include "core/simd.h"
#include "energy/measured.h"
#include "io/formats.h"
#include "models/model_source.h"
#include "render/table_sampler.h"

namespace brdf {
namespace {

// A model's formula in float (its templated Eval, models/common.h), for EvalFloat, and for a
// batch of wi (EvalFloatBatch: one indirect call a batch, the formula inlined in its loop).
using FloatModelEval = RgbF (*)(const float* params, const Vec3f& wi, const Vec3f& wo);
using FloatModelBatchEval = void (*)(const float* params, const float* wi_x, const float* wi_y,
                                     const float* wi_z, const Vec3f& wo, int count, RgbF* f);
template <typename M>
RgbF EvalModelInFloat(const float* params, const Vec3f& wi, const Vec3f& wo) {
  return M::template Eval<float>(params, wi, wo);
}

// The same for a composition, term by term in two loops: first the part of the term that
// depends on the angles alone (models/term.h: Angular), in a loop that vectorizes (8 lanes where
// the processor has AVX2, else 4: the same float operations, so the same numbers, as Eval's);
// then its colours (Colour), added to the sum where both directions are above the horizon. The
// power cosines' c^e goes through ClampedPow's polynomial power.
constexpr int kModelChunk = 16;
template <typename Term>
BRDF_LANE_FUNCTION void AngularParts(const float* params, const float* wi_x, const float* wi_y,
                                     const float* wi_z, const Vec3f& wo, int n,
                                     typename Term::template Part<float>* __restrict parts) {
  for (int k = 0; k < n; ++k) {
    parts[k] = Term::template Angular<float, float>(params, Vec3f(wi_x[k], wi_y[k], wi_z[k]), wo);
  }
}
template <typename Term>
void AngularPartsBaseline(const float* params, const float* wi_x, const float* wi_y,
                          const float* wi_z, const Vec3f& wo, int n,
                          typename Term::template Part<float>* parts) {
  AngularParts<Term>(params, wi_x, wi_y, wi_z, wo, n, parts);
}
template <typename Term>
BRDF_AVX2 void AngularPartsAvx2(const float* params, const float* wi_x, const float* wi_y,
                                const float* wi_z, const Vec3f& wo, int n,
                                typename Term::template Part<float>* parts) {
  AngularParts<Term>(params, wi_x, wi_y, wi_z, wo, n, parts);
}
template <typename M>
void EvalTermsBatchInFloat(const float* params, const float* wi_x, const float* wi_y,
                           const float* wi_z, const Vec3f& wo, int count, RgbF* f) {
  const bool avx2 = Avx2Enabled();
  for (int first = 0; first < count; first += kModelChunk) {
    const int n = std::min(kModelChunk, count - first);
    bool above[kModelChunk];
    for (int k = 0; k < n; ++k) {
      above[k] = models::AboveHorizon(Vec3f(wi_x[first + k], wi_y[first + k], wi_z[first + k]), wo);
      f[first + k] = RgbF::Zero();
    }
    M::ForEachTerm([&](auto term, auto index) {
      using Term = decltype(term);
      const float* p = params + M::kOffsets[index];
      typename Term::template Part<float> parts[kModelChunk];
      (avx2 ? AngularPartsAvx2<Term> : AngularPartsBaseline<Term>)(p, wi_x + first, wi_y + first,
                                                                   wi_z + first, wo, n, parts);
      for (int k = 0; k < n; ++k) {
        if (above[k]) f[first + k] += Term::Colour(p, parts[k]);
      }
    });
  }
}

// Float keeps a relative rounding error of about e 2^-24 in cos^e (the cosine's last bit,
// raised to the power e); at most 1e-3, a thousandth of a sample's own noise, float serves.
// Sharper lobes (e > 16,777) evaluate in double.
constexpr double kFloatExponentLimit = 1e-3 * 0x1.0p24;

class ModelMaterial : public Material {
 public:
  explicit ModelMaterial(Model model) : model_(std::move(model)) {
    // The model knows its lobes: frame and density (models/lobe.h). The renderer draws from
    // one, the sharpest that has any weight, in whatever order the composition names them: a
    // broader lobe is found by the cosine technique, and a sharp lobe left to it would show as
    // fireflies (sphere.cpp).
    const double* params = model_.params().data();
    double drawn_exponent = -1;
    for (const LobeInfo& lobe : model_.info().lobes) {
      const double exponent = lobe.equivalent_exponent(params);
      if (lobe.weight(params).maxCoeff() > 0.0 && exponent > drawn_exponent) {
        drawn_exponent = exponent;
        lobe_ = lobe.coordinates(params);
      }
    }
    params_float_.assign(model_.params().begin(), model_.params().end());
    double sharpest = 0;
    for (const LobeInfo& lobe : model_.info().lobes) {
      sharpest = std::max(sharpest, lobe.equivalent_exponent(model_.params().data()));
    }
    if (sharpest <= kFloatExponentLimit) {
      eval_float_ = VisitModelType(model_.name(), [](auto model_type) -> FloatModelEval {
        return &EvalModelInFloat<decltype(model_type)>;
      });
      eval_float_batch_ = VisitModelType(model_.name(), [](auto model_type) -> FloatModelBatchEval {
        return &EvalTermsBatchInFloat<decltype(model_type)>;
      });
    }
  }
  Rgb Eval(const Vec3& wi, const Vec3& wo) const override { return model_.Eval(wi, wo); }
  RgbF EvalFloat(const Vec3f& wi, const Vec3f& wo) const override {
    if (eval_float_ == nullptr) return Material::EvalFloat(wi, wo);
    return eval_float_(params_float_.data(), wi, wo);
  }
  void EvalFloatBatch(const float* wi_x, const float* wi_y, const float* wi_z, const Vec3f& wo,
                      int count, RgbF* f) const override {
    if (eval_float_batch_ == nullptr)
      return Material::EvalFloatBatch(wi_x, wi_y, wi_z, wo, count, f);
    eval_float_batch_(params_float_.data(), wi_x, wi_y, wi_z, wo, count, f);
  }
  std::string Describe() const override { return model_.ToString(7); }
  std::optional<LobeCoordinates> SpecularLobe() const override { return lobe_; }

 private:
  Model model_;
  std::optional<LobeCoordinates> lobe_;
  std::vector<float> params_float_;
  FloatModelEval eval_float_ = nullptr;
  FloatModelBatchEval eval_float_batch_ = nullptr;
};

// Dense tabulated data (MERL, RGL-EPFL) through the reader's preview evaluator, else its
// evaluator (Measurement::tabulated, wrapped by energy/measured.h); importance-sampled by a
// TableSampler built from the same values.
class MeasuredTableMaterial : public Material {
 public:
  MeasuredTableMaterial(MeasuredBrdf measured, std::string lookup_name)
      : measured_(std::move(measured)), lookup_name_(std::move(lookup_name)) {}
  Rgb Eval(const Vec3& wi, const Vec3& wo) const override {
    if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
    return measured_.brdf(wi, wo).value;
  }
  std::string Describe() const override { return measured_.source + " (" + lookup_name_ + ")"; }
  std::unique_ptr<DirectionSampler> MakeSampler() const override {
    return std::make_unique<TableSampler>(
        [this](const Vec3& wi, const Vec3& wo) { return Eval(wi, wo); });
  }

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
    padded_ = Padded<double>(cells_);
    padded_float_ = Padded<float>(cells_);
  }

  Rgb Eval(const Vec3& wi, const Vec3& wo) const override {
    if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
    const HalfDiff hd = ToHalfDiff(wi, wo);
    const double coordinates[3] = {hd.theta_h, hd.theta_d, std::fmod(hd.phi_d + 2 * kPi, kPi)};
    return Interpolate(coordinates, padded_);
  }

  RgbF EvalFloat(const Vec3f& wi, const Vec3f& wo) const override {
    if (!(wi.z() > 0.0f) || !(wo.z() > 0.0f)) return RgbF::Zero();
    float coordinates[3];
    HalfDiffFloat(wi.x(), wi.y(), wi.z(), wo, &coordinates[0], &coordinates[1], &coordinates[2]);
    return Interpolate(coordinates, padded_float_);
  }
  // The angles, the cells' places and the corners' weights first, a batch at a time (a loop
  // that vectorizes: 8 lanes where the processor has AVX2, else 4, the same numbers), then the
  // blends, which gather.
  void EvalFloatBatch(const float* wi_x, const float* wi_y, const float* wi_z, const Vec3f& wo,
                      int count, RgbF* f) const override {
    alignas(32) int base[kChunk];
    alignas(32) float weights[8][kChunk];
    const bool avx2 = Avx2Enabled();
    for (int first = 0; first < count; first += kChunk) {
      const int n = std::min(kChunk, count - first);
      if (avx2) {
        PlacesAvx2(wi_x + first, wi_y + first, wi_z + first, wo, n, base, weights);
      } else {
        Places(wi_x + first, wi_y + first, wi_z + first, wo, n, base, weights);
      }
      for (int k = 0; k < n; ++k) {
        const float corner_weights[8] = {weights[0][k], weights[1][k], weights[2][k],
                                         weights[3][k], weights[4][k], weights[5][k],
                                         weights[6][k], weights[7][k]};
        f[first + k] = wi_z[first + k] > 0.0f && wo.z() > 0.0f
                           ? Blend(base[k], corner_weights, padded_float_)
                           : RgbF::Zero();
      }
    }
  }
  std::string Describe() const override { return description_; }
  std::optional<LobeCoordinates> SpecularLobe() const override { return lobe_; }

 private:
  static constexpr double kRange[3] = {kPi / 2, kPi / 2, kPi};

  // For n <= kChunk directions wi (and wo): the lower corners' indices in the padded table
  // and the corners' weights (Locate) of their half/difference angles.
  static constexpr int kChunk = 16;
  BRDF_LANE_FUNCTION static void PlacesOf(const float* wi_x, const float* wi_y, const float* wi_z,
                                          const Vec3f& wo, int n, int* base,
                                          float (*weights)[kChunk]) {
    for (int k = 0; k < n; ++k) {
      float coordinates[3], corner_weights[8];
      HalfDiffFloat(wi_x[k], wi_y[k], wi_z[k], wo, &coordinates[0], &coordinates[1],
                    &coordinates[2]);
      base[k] = Locate(coordinates, corner_weights);
      for (int corner = 0; corner < 8; ++corner) weights[corner][k] = corner_weights[corner];
    }
  }
  static void Places(const float* wi_x, const float* wi_y, const float* wi_z, const Vec3f& wo,
                     int n, int* base, float (*weights)[kChunk]) {
    PlacesOf(wi_x, wi_y, wi_z, wo, n, base, weights);
  }
  BRDF_AVX2 static void PlacesAvx2(const float* wi_x, const float* wi_y, const float* wi_z,
                                   const Vec3f& wo, int n, int* base, float (*weights)[kChunk]) {
    PlacesOf(wi_x, wi_y, wi_z, wo, n, base, weights);
  }

  // ToHalfDiff (core/angles.h) in float for wi and wo above the horizon, written out: with
  // h = (sin theta_h cos phi_h, sin theta_h sin phi_h, cos theta_h), rotating wi by -phi_h
  // about z and then by -theta_h about y expresses it in the frame
  // (Rz(phi_h) Ry(theta_h) x, Rz(phi_h) y, h). Selects instead of branches (render/
  // float_math.h), so that a loop over a batch vectorizes; phi_d comes folded into [0, pi).
  BRDF_LANE_FUNCTION static void HalfDiffFloat(float wi_x, float wi_y, float wi_z, const Vec3f& wo,
                                               float* theta_h, float* theta_d, float* phi_d) {
    const float sum_x = wi_x + wo.x(), sum_y = wi_y + wo.y(), sum_z = wi_z + wo.z();
    const float norm = std::sqrt(sum_x * sum_x + sum_y * sum_y + sum_z * sum_z);
    const float h_x = sum_x / norm, h_y = sum_y / norm, h_z = sum_z / norm;
    const float sin_theta_h = std::sqrt(h_x * h_x + h_y * h_y);
    // At the pole phi_h = 0, as Phi() gives.
    const float at_pole = static_cast<float>(!(sin_theta_h > 0.0f));
    const float divisor = std::max(sin_theta_h, 1.17549435e-38f);  // FLT_MIN: no 0 / 0
    const float cos_phi_h = at_pole + (1.0f - at_pole) * (h_x / divisor);
    const float sin_phi_h = (1.0f - at_pole) * (h_y / divisor);
    const float along_phi_h = cos_phi_h * wi_x + sin_phi_h * wi_y;
    const float diff_x = h_z * along_phi_h - sin_theta_h * wi_z;
    const float diff_y = cos_phi_h * wi_y - sin_phi_h * wi_x;
    const float diff_z = wi_x * h_x + wi_y * h_y + wi_z * h_z;
    // [-pi, pi], folded into [0, pi) by reciprocity.
    float phi = Atan2(diff_y, diff_x);
    phi += static_cast<float>(phi < 0.0f) * kPiF;
    phi -= static_cast<float>(phi >= kPiF) * kPiF;
    *theta_h = Atan2(sin_theta_h, h_z);
    *theta_d = Atan2(std::sqrt(diff_x * diff_x + diff_y * diff_y), diff_z);
    *phi_d = phi;
  }
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
    return LobeCoordinates{kHalfVectorFrame, exponent};
  }

  // The table for the lookups: a cell is four aligned lanes (red, green, blue, 0), so that a
  // blend reads and weighs a corner at once (a four-lane loop the compiler vectorizes), and the
  // table has one more cell at each end of every axis (clamped copies in theta_h and theta_d,
  // periodic ones in phi_d), so that the eight corners of any point lie at fixed offsets from the
  // lower one, without clamps or wrap-arounds.
  static constexpr int kPadded = kBins + 3;  // the lower corner's index runs over 0..kBins + 1
  template <typename T>
  struct alignas(4 * sizeof(T)) Cell {
    T lane[4];
  };
  template <typename T>
  static std::vector<Cell<T>> Padded(const std::vector<Rgb>& cells) {
    // Padded index i is cell i - 1 of the axis.
    auto of = [](int d, int i) {
      return d == 2 ? (i - 1 + kBins) % kBins : std::clamp(i - 1, 0, kBins - 1);
    };
    std::vector<Cell<T>> padded(kPadded * kPadded * kPadded);
    for (int h = 0; h < kPadded; ++h) {
      for (int d = 0; d < kPadded; ++d) {
        for (int p = 0; p < kPadded; ++p) {
          const Rgb& cell = cells[(of(0, h) * kBins + of(1, d)) * kBins + of(2, p)];
          padded[(h * kPadded + d) * kPadded + p] =
              Cell<T>{T(cell[0]), T(cell[1]), T(cell[2]), T(0)};
        }
      }
    }
    return padded;
  }

  // Trilinear between cell centres (nearest-cell lookups drew the grid as rings around a
  // highlight) at (theta_h, theta_d, phi_d in [0, pi)). theta_h and theta_d clamp at the ends;
  // phi_d is periodic with period pi. Locate gives the lower corner's index in the padded
  // table and the eight corners' weights (corner bit d set: the upper one along axis d);
  // without branches, so that a loop over a batch vectorizes.
  template <typename T>
  BRDF_LANE_FUNCTION static int Locate(const T coordinates[3], T weights[8]) {
    int index = 0;
    T t[3];
    for (int d = 0; d < 3; ++d) {
      // u in [-1/2, kBins - 1/2] for directions above the horizon (NaN directions: -1/2);
      // truncating u + 1 floors it without a libm call.
      T u = coordinates[d] / T(kRange[d]) * T(kBins) - T(0.5);
      u = u >= T(-0.5) ? std::min(u, T(kBins)) : T(-0.5);
      const int below = static_cast<int>(u + T(1)) - 1;  // -1..kBins
      const T fraction = u - T(below);
      t[d] = ((fraction >= T(0)) & (fraction <= T(1))) ? fraction : T(0);  // NaN: any corner
      index = index * kPadded + below + 1;
    }
    for (int corner = 0; corner < 8; ++corner) {
      T weight = T(1);
      for (int d = 0; d < 3; ++d) weight *= (corner >> d) & 1 ? t[d] : T(1) - t[d];
      weights[corner] = weight;
    }
    return index;
  }
  template <typename T>
  static RgbT<T> Blend(int base, const T weights[8], const std::vector<Cell<T>>& cells) {
    T value[4] = {};
    for (int corner = 0; corner < 8; ++corner) {
      const int offset =
          (corner & 1 ? kPadded * kPadded : 0) + (corner & 2 ? kPadded : 0) + (corner & 4 ? 1 : 0);
      const T weight = weights[corner];
      const Cell<T>& cell = cells[base + offset];
      // A corner of weight 0 adds nothing, whatever its value (as a branch would skip it).
      for (int c = 0; c < 4; ++c) value[c] += weight > T(0) ? weight * cell.lane[c] : T(0);
    }
    return RgbT<T>(value[0], value[1], value[2]);
  }
  template <typename T>
  static RgbT<T> Interpolate(const T coordinates[3], const std::vector<Cell<T>>& cells) {
    T weights[8];
    const int base = Locate(coordinates, weights);
    return Blend(base, weights, cells);
  }

  std::string description_;
  std::vector<Rgb> cells_;
  std::vector<Cell<double>> padded_;       // the same, padded, for Eval
  std::vector<Cell<float>> padded_float_;  // and in float, for EvalFloat
  std::optional<LobeCoordinates> lobe_;
};

}  // namespace

void Material::EvalFloatBatch(const float* wi_x, const float* wi_y, const float* wi_z,
                              const Vec3f& wo, int count, RgbF* f) const {
  for (int k = 0; k < count; ++k) f[k] = EvalFloat(Vec3f(wi_x[k], wi_y[k], wi_z[k]), wo);
}

std::unique_ptr<Material> ModelMaterialOf(Model model) {
  return std::make_unique<ModelMaterial>(std::move(model));
}

std::unique_ptr<Material> MeasurementMaterialOf(const Measurement& measurement) {
  if (measurement.tabulated != nullptr) {
    // The preview's own evaluator where the reader has one (no holes; see material.h).
    std::shared_ptr<const TabulatedBrdf> table = measurement.tabulated->PreviewEvaluator();
    if (table == nullptr) table = measurement.tabulated;
    return std::make_unique<MeasuredTableMaterial>(TabulatedMeasuredBrdf(table, measurement.source),
                                                   table->LookupName());
  }
  return std::make_unique<TabulatedMaterial>(measurement);
}

std::unique_ptr<Material> LoadMaterial(const std::string& spec) {
  if (IsModelSpec(spec)) return ModelMaterialOf(LoadModel(spec));
  // A table renders through its evaluator alone: its samples are not made.
  if (std::optional<Measurement> table = ReadEvaluator(spec)) return MeasurementMaterialOf(*table);
  return MeasurementMaterialOf(ReadMeasurement(spec));
}

}  // namespace brdf
