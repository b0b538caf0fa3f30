#include "io/merl.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/text.h"
#include "io/merl_preview.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the MERL reader copies little-endian bytes directly");

namespace brdf {
namespace {

constexpr double kHalfPi = 0.5 * kPi;
constexpr int32_t kDimensions[3] = {MerlTable::kThetaHalfBins, MerlTable::kThetaDiffBins,
                                    MerlTable::kPhiDiffBins};
// A sample counts as lying on the grid when its angles are this close to a cell centre.
constexpr double kOnGridTolerance = 1e-6;

int ClampIndex(int index, int bins) { return std::clamp(index, 0, bins - 1); }

class MerlEvaluator : public TabulatedBrdf {
 public:
  explicit MerlEvaluator(std::shared_ptr<const MerlTable> table) : table_(std::move(table)) {
    for (int64_t cell = 0; cell < MerlTable::kCells; ++cell) missing_ += table_->raw(0, cell) < 0.0;
  }
  Rgb Eval(const Vec3& wi, const Vec3& wo) const override { return table_->Lookup(wi, wo); }
  std::string Describe() const override {
    return "MERL table: nearest-cell lookup (Matusik et al. 2003 grid); " +
           std::to_string(missing_) + " of " + std::to_string(MerlTable::kCells) +
           " cells missing count as zero";
  }
  std::string LookupName() const override { return "MERL table lookup"; }
  std::shared_ptr<const TabulatedBrdf> PreviewEvaluator() const override {
    return MerlPreviewTabulated(*table_);  // io/merl_preview.h
  }

 private:
  std::shared_ptr<const MerlTable> table_;
  int64_t missing_ = 0;
};

// The grid's measure alone: it holds none of the table's values.
class MerlGridMeasure : public CellMeasure {
 public:
  double Measure(const Vec3& wi, const Vec3& wo) const override {
    return MerlTable::CellMeasure(wi, wo);
  }
  std::string Name() const override { return "MERL cell measure 4 cos(theta_d) dw_h dw_d"; }
};

}  // namespace

std::shared_ptr<const TabulatedBrdf> MerlTabulated(std::shared_ptr<const MerlTable> table) {
  return std::make_shared<const MerlEvaluator>(std::move(table));
}

std::shared_ptr<const CellMeasure> MerlCellMeasure() {
  static const std::shared_ptr<const CellMeasure> measure = std::make_shared<MerlGridMeasure>();
  return measure;
}

namespace {

// The measure of every (theta_h, theta_d) bin of the MERL grid (MerlTable::CellMeasure), computed
// once: a fit asks for a million cells.
const std::vector<double>& BinMeasures() {
  using T = MerlTable;
  static const std::vector<double> measures = [] {
    std::vector<double> table(T::kThetaHalfBins * T::kThetaDiffBins);
    for (int i = 0; i < T::kThetaHalfBins; ++i) {
      for (int j = 0; j < T::kThetaDiffBins; ++j) {
        const HalfDiff centre = T::CellCentre(i, j, 0);
        const double n = T::kThetaHalfBins;
        const double d_theta_h = ((i + 1) * (i + 1) - i * i) / (n * n) * (0.5 * kPi);
        const double d_theta_d = 0.5 * kPi / T::kThetaDiffBins;
        const double d_phi_d = kPi / T::kPhiDiffBins;
        table[i * T::kThetaDiffBins + j] = 4.0 * std::cos(centre.theta_d) *
                                           std::sin(centre.theta_h) * std::sin(centre.theta_d) *
                                           d_theta_h * d_theta_d * d_phi_d;
      }
    }
    return table;
  }();
  return measures;
}

}  // namespace

double MerlTable::CellMeasure(const Vec3& wi, const Vec3& wo) {
  // Only theta_h and theta_d are needed: cos theta_h = h.z and cos theta_d = wi.h.
  const Vec3 half_vector = (wi + wo).normalized();
  const int i = ThetaHalfIndex(std::acos(std::clamp(half_vector.z(), -1.0, 1.0)));
  const int j = ThetaDiffIndex(std::acos(std::clamp(wi.dot(half_vector), -1.0, 1.0)));
  return BinMeasures()[i * kThetaDiffBins + j];
}

const Rgb MerlTable::kScale(1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0);

MerlTable::MerlTable() : owned_(3 * kCells, -1.0) {}

void MerlTable::Detach() {
  if (file_ == nullptr) return;
  std::vector<double> values(3 * kCells);
  std::memcpy(values.data(), file_->data() + kHeaderBytes, values.size() * sizeof(double));
  owned_ = std::move(values);
  file_ = nullptr;
}

int MerlTable::ThetaHalfIndex(double theta_h) {
  if (theta_h <= 0.0) return 0;
  return ClampIndex(static_cast<int>(std::sqrt(theta_h / kHalfPi) * kThetaHalfBins),
                    kThetaHalfBins);
}

int MerlTable::ThetaDiffIndex(double theta_d) {
  return ClampIndex(static_cast<int>(theta_d / kHalfPi * kThetaDiffBins), kThetaDiffBins);
}

int MerlTable::PhiDiffIndex(double phi_d) {
  // Reciprocity for isotropic materials: phi_d and phi_d + pi are the same configuration.
  phi_d = std::fmod(phi_d, kPi);
  if (phi_d < 0.0) phi_d += kPi;
  return ClampIndex(static_cast<int>(phi_d / kPi * kPhiDiffBins), kPhiDiffBins);
}

int64_t MerlTable::CellIndex(int theta_h_index, int theta_diff_index, int phi_diff_index) {
  return phi_diff_index +
         int64_t{kPhiDiffBins} * (theta_diff_index + int64_t{kThetaDiffBins} * theta_h_index);
}

HalfDiff MerlTable::CellCentre(int theta_h_index, int theta_diff_index, int phi_diff_index) {
  HalfDiff hd;
  const double u = (theta_h_index + 0.5) / kThetaHalfBins;
  hd.theta_h = u * u * kHalfPi;  // inverse of the square-root warp
  hd.phi_h = 0.0;
  hd.theta_d = (theta_diff_index + 0.5) / kThetaDiffBins * kHalfPi;
  hd.phi_d = (phi_diff_index + 0.5) / kPhiDiffBins * kPi;
  return hd;
}

int64_t MerlTable::CellOf(const Vec3& wi, const Vec3& wo) {
  const HalfDiff hd = ToHalfDiff(wi, wo);
  return CellIndex(ThetaHalfIndex(hd.theta_h), ThetaDiffIndex(hd.theta_d), PhiDiffIndex(hd.phi_d));
}

Rgb MerlTable::Lookup(const Vec3& wi, const Vec3& wo) const {
  const int64_t cell = CellOf(wi, wo);
  Rgb value;
  for (int c = 0; c < 3; ++c) {
    const double stored = raw(c, cell);
    value[c] = stored < 0.0 ? std::numeric_limits<double>::quiet_NaN() : stored * kScale[c];
  }
  return value;
}

MerlTable MerlTable::Read(const std::string& path) {
  // The size is checked against the header before anything large is allocated, so a hostile
  // file never drives an allocation; the doubles are then mapped, or read into the table.
  const int64_t size = RegularFileSize(path);
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw InputError(path, "cannot open for reading");
  int32_t dims[3] = {0, 0, 0};
  stream.read(reinterpret_cast<char*>(dims), sizeof(dims));
  if (stream.gcount() < kHeaderBytes) {
    throw ByteError(path, stream.gcount(),
                    "file ends inside the 12-byte MERL header (three int32 dimensions)");
  }
  for (int k = 0; k < 3; ++k) {
    if (dims[k] != kDimensions[k]) {
      throw ByteError(path, 4 * k,
                      "MERL dimension " + std::to_string(k + 1) + " is " + std::to_string(dims[k]) +
                          ", expected 90 90 180");
    }
  }
  if (size != kFileBytes) {
    throw ByteError(path, size,
                    "dimensions 90x90x180 need " + std::to_string(kFileBytes) +
                        " bytes, the file has " + std::to_string(size) +
                        (size < kFileBytes ? " (truncated)" : ""));
  }
  MerlTable table(Unfilled{});
  table.file_ = MappedFile::Open(path);
  if (table.file_ != nullptr && table.file_->size() != static_cast<size_t>(kFileBytes)) {
    throw ByteError(path, static_cast<int64_t>(table.file_->size()),
                    "file changed while read: it now has " + std::to_string(table.file_->size()) +
                        " bytes, expected " + std::to_string(kFileBytes));
  }
  if (table.file_ == nullptr) {  // no mapping here: the doubles read straight into the table
    table.owned_.resize(3 * kCells);
    const std::streamsize payload = static_cast<std::streamsize>(table.owned_.size() * 8);
    stream.read(reinterpret_cast<char*>(table.owned_.data()), payload);
    if (stream.gcount() != payload) {
      throw ByteError(path, kHeaderBytes + stream.gcount(), "read failed (file changed?)");
    }
  }
  // Every value finite, checked in parallel by rows of one channel; the error names the first
  // value that is not.
  const MerlTable& values = table;  // read without copying the mapped values (raw's const form)
  constexpr int64_t kValues = 3 * kCells;
  const int64_t first_bad = tbb::parallel_reduce(
      tbb::blocked_range<int64_t>(0, kValues / kRowCells), kValues,
      [&](const tbb::blocked_range<int64_t>& rows, int64_t first) {
        for (int64_t row = rows.begin(); row < rows.end(); ++row) {
          const int channel = static_cast<int>(row / kThetaHalfBins);
          const int64_t begin = (row % kThetaHalfBins) * kRowCells;
          for (int64_t cell = begin; cell < begin + kRowCells; ++cell) {
            if (std::isfinite(values.raw(channel, cell))) continue;
            first = std::min(first, int64_t{channel} * kCells + cell);
            break;
          }
        }
        return first;
      },
      [](int64_t a, int64_t b) { return std::min(a, b); });
  if (first_bad < kValues) {
    throw ByteError(path, kHeaderBytes + 8 * first_bad,
                    "value is NaN or infinite, expected a finite BRDF value (negative for "
                    "missing)");
  }
  return table;
}

void MerlTable::Write(const std::string& path) const {
  WriteFileAtomically(
      path,
      [&](std::ostream& out) {
        out.write(reinterpret_cast<const char*>(kDimensions), sizeof(kDimensions));
        const char* values = file_ != nullptr
                                 ? reinterpret_cast<const char*>(file_->data() + kHeaderBytes)
                                 : reinterpret_cast<const char*>(owned_.data());
        out.write(values, static_cast<std::streamsize>(3 * kCells * sizeof(double)));
      },
      /*binary=*/true);
}

MerlTable MerlTable::Tabulate(const std::function<Rgb(const Vec3& wi, const Vec3& wo)>& brdf) {
  MerlTable table;
  tbb::parallel_for(0, kThetaHalfBins, [&](int h) {
    for (int d = 0; d < kThetaDiffBins; ++d) {
      for (int p = 0; p < kPhiDiffBins; ++p) {
        Vec3 wi, wo;
        FromHalfDiff(CellCentre(h, d, p), &wi, &wo);
        const Rgb value = brdf(wi, wo);
        for (int c = 0; c < 3; ++c) table.raw(c, CellIndex(h, d, p)) = value[c] / kScale[c];
      }
    }
  });
  return table;
}

namespace {

// Sines and cosines of the cell-centre angles of each bin: the cell-centre directions follow
// from them by the same rotation as FromHalfDiff (wi = Ry(theta_h) d with phi_h = 0;
// wo = 2 (wi.h) h - wi) without 1.4 million sets of trig calls, which made the conversion four
// times slower than reading the file.
struct CellAngles {
  struct SinCos {
    double sin, cos;
  };
  std::vector<SinCos> theta_h, theta_d, phi_d;

  static const CellAngles& Get() {
    static const CellAngles angles = [] {
      auto tabulate = [](int bins, auto angle_of_bin) {
        std::vector<SinCos> table(bins);
        for (int k = 0; k < bins; ++k)
          table[k] = {std::sin(angle_of_bin(k)), std::cos(angle_of_bin(k))};
        return table;
      };
      CellAngles made;
      made.theta_h = tabulate(MerlTable::kThetaHalfBins,
                              [](int k) { return MerlTable::CellCentre(k, 0, 0).theta_h; });
      made.theta_d = tabulate(MerlTable::kThetaDiffBins,
                              [](int k) { return MerlTable::CellCentre(0, k, 0).theta_d; });
      made.phi_d = tabulate(MerlTable::kPhiDiffBins,
                            [](int k) { return MerlTable::CellCentre(0, 0, k).phi_d; });
      return made;
    }();
    return angles;
  }
};

void AddGridMetadata(Measurement* measurement) {
  measurement->metadata["units"] =
      "BRDF in sr^-1 (stored values times 1/1500, 1.15/1500, 1.66/1500)";
  measurement->metadata["grid"] =
      "MERL 90x90x180 (theta_h sqrt-warped, theta_d, phi_d in [0, pi)); one sample per cell "
      "centre, phi_h = 0";
  measurement->metadata["missing"] =
      "cells with a negative stored value, or whose centre lies below the horizon";
}

}  // namespace

void MerlTable::MakeSamples(int64_t begin, int64_t end, Sample* out) const {
  const CellAngles& angles = CellAngles::Get();
  for (int64_t cell = begin; cell < end; ++cell) {
    const int phi_diff_index = static_cast<int>(cell % kPhiDiffBins);
    const int theta_diff_index = static_cast<int>(cell / kPhiDiffBins % kThetaDiffBins);
    const int theta_h_index = static_cast<int>(cell / kRowCells);
    const CellAngles::SinCos h = angles.theta_h[theta_h_index];
    const CellAngles::SinCos d = angles.theta_d[theta_diff_index];
    const CellAngles::SinCos p = angles.phi_d[phi_diff_index];
    const Vec3 half_vector(h.sin, 0.0, h.cos);
    const Vec3 diff(d.sin * p.cos, d.sin * p.sin, d.cos);
    Sample& sample = out[cell - begin];
    sample.wi =
        Vec3(h.cos * diff.x() + h.sin * diff.z(), diff.y(), -h.sin * diff.x() + h.cos * diff.z());
    sample.wo = 2.0 * sample.wi.dot(half_vector) * half_vector - sample.wi;
    bool missing = sample.wi.z() <= 0.0 || sample.wo.z() <= 0.0;
    for (int c = 0; c < 3; ++c) {
      const double stored = raw(c, cell);
      missing = missing || stored < 0.0;
      sample.value[c] = stored * kScale[c];
    }
    sample.missing = missing;
  }
}

Measurement MerlTable::ToMeasurement() const {
  Measurement measurement;
  measurement.samples.resize(kCells);
  tbb::parallel_for(0, kThetaHalfBins, [&](int theta_h_index) {
    const int64_t first = theta_h_index * kRowCells;
    MakeSamples(first, first + kRowCells, measurement.samples.data() + first);
  });
  AddGridMetadata(&measurement);
  return measurement;
}

MerlTable MerlTable::FromMeasurement(const Measurement& measurement, WriteReport* report) {
  std::vector<Rgb> sum(kCells, Rgb::Zero());
  std::vector<int> count(kCells, 0);
  size_t off_centre = 0, used = 0;
  for (const Sample& sample : measurement.samples) {
    if (sample.missing || sample.wi.z() <= 0.0 || sample.wo.z() <= 0.0) continue;
    if (!sample.value.isFinite().all()) continue;
    const HalfDiff hd = ToHalfDiff(sample.wi, sample.wo);
    const int h = ThetaHalfIndex(hd.theta_h), d = ThetaDiffIndex(hd.theta_d),
              p = PhiDiffIndex(hd.phi_d);
    const HalfDiff centre = CellCentre(h, d, p);
    const double phi_d_folded = std::fmod(hd.phi_d, kPi);
    if (std::abs(hd.theta_h - centre.theta_h) > kOnGridTolerance ||
        std::abs(hd.theta_d - centre.theta_d) > kOnGridTolerance ||
        std::abs(phi_d_folded - centre.phi_d) > kOnGridTolerance) {
      ++off_centre;
    }
    const int64_t cell = CellIndex(h, d, p);
    sum[cell] += sample.value;
    ++count[cell];
    ++used;
  }
  MerlTable table;
  int64_t empty = 0;
  for (int64_t cell = 0; cell < kCells; ++cell) {
    if (count[cell] == 0) {
      ++empty;
      continue;
    }
    for (int c = 0; c < 3; ++c) table.raw(c, cell) = sum[cell][c] / count[cell] / kScale[c];
  }
  if (report != nullptr) {
    if (off_centre > 0) {
      report->warnings.push_back(std::to_string(off_centre) + " of " + std::to_string(used) +
                                 " samples are not at MERL cell centres and were binned "
                                 "(averaged per cell)");
    }
    if (empty > 0) {
      report->warnings.push_back(std::to_string(empty) + " of " + std::to_string(kCells) +
                                 " cells have no sample and are written as missing (-1)");
    }
  }
  return table;
}

bool SniffMerl(std::string_view head, int64_t file_size) {
  if (head.size() < MerlTable::kHeaderBytes || file_size != MerlTable::kFileBytes) return false;
  int32_t dims[3];
  std::memcpy(dims, head.data(), sizeof(dims));
  return dims[0] == kDimensions[0] && dims[1] == kDimensions[1] && dims[2] == kDimensions[2];
}

void CopyMerl(const std::string& from, const std::string& to) { MerlTable::Read(from).Write(to); }

namespace {

// The table of `path`, with values of its own: the evaluator may live long after this read (a
// Python session), and a file rewritten in place meanwhile cannot pull its pages away.
std::shared_ptr<const MerlTable> ReadDetached(const std::string& path) {
  MerlTable table = MerlTable::Read(path);
  table.Detach();
  return std::make_shared<const MerlTable>(std::move(table));
}

// `measurement` with the table's evaluator and cell measure.
Measurement WithEvaluator(Measurement measurement, std::shared_ptr<const MerlTable> table) {
  measurement.cell_measure = MerlCellMeasure();
  measurement.tabulated = MerlTabulated(std::move(table));
  return measurement;
}

}  // namespace

Measurement ReadMerl(const std::string& path, const ReadOptions&) {
  std::shared_ptr<const MerlTable> table = ReadDetached(path);
  Measurement measurement = table->ToMeasurement();
  return WithEvaluator(std::move(measurement), std::move(table));
}

Measurement ReadMerlEvaluator(const std::string& path, const ReadOptions&) {
  Measurement measurement;
  AddGridMetadata(&measurement);
  return WithEvaluator(std::move(measurement), ReadDetached(path));
}

bool OnMerlGrid(const std::vector<Sample>& samples) {
  if (samples.empty()) return false;
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, samples.size()), true,
      [&](const tbb::blocked_range<size_t>& range, bool on_grid) {
        for (size_t k = range.begin(); on_grid && k < range.end(); ++k) {
          const Sample& sample = samples[k];
          if (sample.wi.z() <= 0.0 || sample.wo.z() <= 0.0) continue;  // no cell to sit in
          const HalfDiff hd = ToHalfDiff(sample.wi, sample.wo);
          const HalfDiff centre = MerlTable::CellCentre(MerlTable::ThetaHalfIndex(hd.theta_h),
                                                        MerlTable::ThetaDiffIndex(hd.theta_d),
                                                        MerlTable::PhiDiffIndex(hd.phi_d));
          on_grid = std::abs(hd.theta_h - centre.theta_h) <= kOnGridTolerance &&
                    std::abs(hd.theta_d - centre.theta_d) <= kOnGridTolerance &&
                    std::abs(std::fmod(hd.phi_d, kPi) - centre.phi_d) <= kOnGridTolerance;
        }
        return on_grid;
      },
      [](bool a, bool b) { return a && b; });
}

WriteReport WriteMerl(const Measurement& measurement, const std::string& path) {
  WriteReport report;
  if (measurement.tabulated == nullptr) {
    MerlTable::FromMeasurement(measurement, &report).Write(path);
    return report;
  }
  // Dense data with an evaluator: each cell valued at its centre (for a MERL table this gives
  // the same numbers as binning its own samples). Centres at or below the horizon, and cells
  // without a value, are written missing (-1).
  MerlTable table = MerlTable::Tabulate([&](const Vec3& wi, const Vec3& wo) {
    if (wi.z() <= 0.0 || wo.z() <= 0.0) return Rgb(Rgb::Constant(-1.0) * MerlTable::kScale);
    const Rgb value = measurement.tabulated->Eval(wi, wo);
    return value.allFinite() ? value : Rgb(Rgb::Constant(-1.0) * MerlTable::kScale);
  });
  int64_t missing = 0;
  for (int64_t cell = 0; cell < MerlTable::kCells; ++cell) missing += table.raw(0, cell) < 0.0;
  report.warnings.push_back("tabulated at the " + std::to_string(MerlTable::kCells) +
                            " MERL cell centres through the input's evaluator (" +
                            measurement.tabulated->LookupName() + "); " + std::to_string(missing) +
                            " cells (below the horizon or without a "
                            "value) written as missing (-1)");
  table.Write(path);
  return report;
}

}  // namespace brdf
