#include "render/material.h"

#include <sys/stat.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/angles.h"
#include "core/errors.h"
#include "io/formats.h"
#include "io/merl.h"
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

class MerlMaterial : public Material {
 public:
  MerlMaterial(std::string path, MerlTable table)
      : path_(std::move(path)), table_(std::move(table)) {}
  Rgb Eval(const Vec3& wi, const Vec3& wo) const override {
    if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
    return table_.Lookup(wi, wo);
  }
  std::string Describe() const override { return path_ + " (MERL table lookup)"; }

 private:
  std::string path_;
  MerlTable table_;
};

// Nearest neighbour on a half/difference grid (see material.h).
class NearestNeighbourMaterial : public Material {
 public:
  static constexpr int kBins = 32;

  NearestNeighbourMaterial(const Measurement& measurement)
      : description_(measurement.source + " (" + measurement.format +
                     ", nearest neighbour on a 32^3 half/difference grid)") {
    std::vector<std::array<double, 3>> coordinates;
    std::vector<Rgb> values;
    for (const Sample& sample : measurement.samples) {
      if (sample.missing || !sample.value.allFinite()) continue;
      if (sample.wi.z() <= 0.0 || sample.wo.z() <= 0.0) continue;
      coordinates.push_back(Coordinates(sample.wi, sample.wo));
      values.push_back(sample.value);
    }
    if (values.empty()) {
      throw InputError(measurement.source, "no present sample above the horizon to render");
    }
    cells_.resize(kBins * kBins * kBins);
    tbb::parallel_for(0, kBins * kBins * kBins, [&](int cell) {
      const std::array<double, 3> centre = CellCentre(cell);
      double best = std::numeric_limits<double>::infinity();
      for (size_t k = 0; k < coordinates.size(); ++k) {
        double distance = 0.0;
        for (int d = 0; d < 3; ++d) {
          distance += (coordinates[k][d] - centre[d]) * (coordinates[k][d] - centre[d]);
        }
        if (distance < best) {
          best = distance;
          cells_[cell] = values[k];
        }
      }
    });
  }

  Rgb Eval(const Vec3& wi, const Vec3& wo) const override {
    if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb::Zero();
    return cells_[CellOf(Coordinates(wi, wo))];
  }
  std::string Describe() const override { return description_; }

 private:
  static constexpr double kRange[3] = {kPi / 2, kPi / 2, kPi};

  static std::array<double, 3> Coordinates(const Vec3& wi, const Vec3& wo) {
    const HalfDiff hd = ToHalfDiff(wi, wo);
    return {hd.theta_h, hd.theta_d, std::fmod(hd.phi_d + 2 * kPi, kPi)};
  }
  static std::array<double, 3> CellCentre(int cell) {
    const int index[3] = {cell / (kBins * kBins), (cell / kBins) % kBins, cell % kBins};
    std::array<double, 3> centre;
    for (int d = 0; d < 3; ++d) centre[d] = (index[d] + 0.5) / kBins * kRange[d];
    return centre;
  }
  static int CellOf(const std::array<double, 3>& coordinates) {
    int index[3];
    for (int d = 0; d < 3; ++d) {
      index[d] = std::clamp(static_cast<int>(coordinates[d] / kRange[d] * kBins), 0, kBins - 1);
    }
    return (index[0] * kBins + index[1]) * kBins + index[2];
  }

  std::string description_;
  std::vector<Rgb> cells_;
};

bool IsRegularFile(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

}  // namespace

std::unique_ptr<Material> LoadMaterial(const std::string& spec) {
  if (IsFitReportPath(spec)) return std::make_unique<ModelMaterial>(LoadModel(spec));
  if (!IsRegularFile(spec)) {
    const std::string name = spec.substr(0, spec.find(':'));
    for (const ModelInfo& info : ModelRegistry()) {
      if (info.name == name) return std::make_unique<ModelMaterial>(LoadModel(spec));
    }
    throw InputError(spec,
                     "no such file, and not a model string (models: lambert, phong, "
                     "blinn-phong, blinn-phong-exact)");
  }
  const FileFormat& format = DetectFormat(spec);
  if (format.name == "merl") return std::make_unique<MerlMaterial>(spec, MerlTable::Read(spec));
  return std::make_unique<NearestNeighbourMaterial>(ReadMeasurement(spec));
}

}  // namespace brdf
