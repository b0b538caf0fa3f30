#include "render/material.h"

#include <sys/stat.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/angles.h"
#include "core/errors.h"
#include "energy/measured.h"
#include "io/formats.h"
#include "models/model_source.h"

namespace brdf {
namespace {

class ModelMaterial : public Material {
 public:
  explicit ModelMaterial(Model model) : model_(std::move(model)) {}
  Rgb Eval(const Vec3& wi, const Vec3& wo) const override { return model_.Eval(wi, wo); }
  std::string Describe() const override { return model_.ToString(); }

 private:
  Model model_;
};

// A MERL table, looked up cell by cell through the shared measured-data integrand
// (energy/measured.h); NaN where the cell is missing.
class MerlMaterial : public Material {
 public:
  explicit MerlMaterial(MeasuredBrdf measured) : measured_(std::move(measured)) {}
  Rgb Eval(const Vec3& wi, const Vec3& wo) const override {
    if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
    return measured_.brdf(wi, wo).value;
  }
  std::string Describe() const override { return measured_.source + " (MERL table lookup)"; }

 private:
  MeasuredBrdf measured_;
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
  }

  Rgb Eval(const Vec3& wi, const Vec3& wo) const override {
    if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
    const HalfDiff hd = ToHalfDiff(wi, wo);
    const double coordinates[3] = {hd.theta_h, hd.theta_d, std::fmod(hd.phi_d + 2 * kPi, kPi)};
    int index[3];
    for (int d = 0; d < 3; ++d) {
      index[d] = std::clamp(static_cast<int>(coordinates[d] / kRange[d] * kBins), 0, kBins - 1);
    }
    return cells_[(index[0] * kBins + index[1]) * kBins + index[2]];
  }
  std::string Describe() const override { return description_; }

 private:
  static constexpr double kRange[3] = {kPi / 2, kPi / 2, kPi};

  std::string description_;
  std::vector<Rgb> cells_;
};

// Any existing path is data, even a directory or a device: the reader then says what is wrong
// with it instead of "not a model string".
bool PathExists(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0;
}

}  // namespace

std::unique_ptr<Material> LoadMaterial(const std::string& spec) {
  if (IsFitReportPath(spec)) return std::make_unique<ModelMaterial>(LoadModel(spec));
  if (!PathExists(spec)) {
    const std::string name = spec.substr(0, spec.find(':'));
    for (const ModelInfo& info : ModelRegistry()) {
      if (info.name == name) return std::make_unique<ModelMaterial>(LoadModel(spec));
    }
    throw InputError(spec,
                     "no such file, and not a model string (models: lambert, phong, "
                     "blinn-phong, blinn-phong-exact)");
  }
  const FileFormat& format = DetectFormat(spec);
  if (format.name == "merl") return std::make_unique<MerlMaterial>(LoadMeasuredBrdf(spec));
  return std::make_unique<TabulatedMaterial>(ReadMeasurement(spec));
}

}  // namespace brdf
