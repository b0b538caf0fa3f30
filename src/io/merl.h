// The MERL isotropic BRDF table (Matusik et al., "A Data-Driven Reflectance Model", TOG 22(3),
// 2003): three little-endian int32 dimensions (90, 90, 180), then 90*90*180 doubles per channel
// (all red, then green, then blue), indexed by (theta_h, theta_d, phi_d) with phi_d fastest.
// Stored values times 1/1500, 1.15/1500, 1.66/1500 give the BRDF in sr^-1; negative values
// mark missing samples. theta_h is sampled non-linearly: index = sqrt(theta_h / (pi/2)) * 90,
// denser near the specular peak; phi_d covers [0, pi) because reciprocity makes f(phi_d) =
// f(phi_d + pi) for an isotropic material.
#pragma once

#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/mapped_file.h"
#include "core/measurement.h"
#include "io/formats.h"

namespace brdf {

class MerlTable {
 public:
  static constexpr int kThetaHalfBins = 90;
  static constexpr int kThetaDiffBins = 90;
  static constexpr int kPhiDiffBins = 180;
  // The cells of one theta_h bin (one row of the table), and of the whole table.
  static constexpr int64_t kRowCells = int64_t{kThetaDiffBins} * kPhiDiffBins;
  static constexpr int64_t kCells = kThetaHalfBins * kRowCells;
  static constexpr int64_t kHeaderBytes = 12;
  static constexpr int64_t kFileBytes = kHeaderBytes + kCells * 3 * 8;  // 34,992,012
  // Raw value * scale = BRDF in sr^-1, per channel (MERL's BRDFRead.cpp constants).
  static const Rgb kScale;

  // A table with every cell missing.
  MerlTable();

  // Reads and validates a file: exact size for the dimensions, dimensions 90 90 180, finite
  // values. Throws ByteError naming the offset of the first problem. The values stay in the
  // file's pages where it can be mapped (core/mapped_file.h): nothing is copied.
  static MerlTable Read(const std::string& path);
  // Writes the table atomically (temporary file, then rename).
  void Write(const std::string& path) const;

  // Bins a measurement's present, above-horizon samples into cells (mean per cell); cells with
  // no sample stay missing. Warnings say how many samples were off the cell centres and how
  // many cells are empty.
  static MerlTable FromMeasurement(const Measurement& measurement, WriteReport* report);
  // Every cell valued by `brdf` (sr^-1) at its centre directions, phi_h = 0, including cells
  // below the horizon (the function decides what to return there).
  static MerlTable Tabulate(const std::function<Rgb(const Vec3& wi, const Vec3& wo)>& brdf);

  // One sample per cell at the cell centre, phi_h = 0. Cells with a negative value, or whose
  // centre directions fall at or below the horizon, are flagged missing.
  Measurement ToMeasurement() const;
  // Those samples of cells [begin, end) (cell indices, CellIndex order) written to out[0, end -
  // begin).
  void MakeSamples(int64_t begin, int64_t end, Sample* out) const;

  static int ThetaHalfIndex(double theta_h);
  static int ThetaDiffIndex(double theta_d);
  static int PhiDiffIndex(double phi_d);  // folds phi_d into [0, pi)
  static int64_t CellIndex(int theta_h_index, int theta_diff_index, int phi_diff_index);
  static HalfDiff CellCentre(int theta_h_index, int theta_diff_index, int phi_diff_index);
  static int64_t CellOf(const Vec3& wi, const Vec3& wo);
  // dwi dwo of the cell holding (wi, wo): 4 cos(theta_d) dw_h dw_d with phi_h integrated out
  // (isotropy), theta_h bins of width ((i+1)^2 - i^2) / 90^2 * pi/2.
  static double CellMeasure(const Vec3& wi, const Vec3& wo);

  // Stored (unscaled) value of a cell; negative means missing.
  double raw(int channel, int64_t cell) const {
    const int64_t index = channel * kCells + cell;
    if (file_ == nullptr) return owned_[index];
    // The file's doubles follow a 12-byte header, so they are not 8-byte aligned in its pages.
    double value;
    std::memcpy(&value, file_->data() + kHeaderBytes + 8 * index, sizeof(value));
    return value;
  }
  // A table read from a mapped file copies its values into memory of its own first (so the
  // first write to a mapped table must not race with other reads or writes of it).
  double& raw(int channel, int64_t cell) {
    if (file_ != nullptr) Detach();
    return owned_[channel * kCells + cell];
  }
  // Copies the values of a table read from a mapped file into memory of its own (nothing for a
  // table that has its own): for a table kept while its file may be rewritten in place, whose
  // mapped pages would then vanish under it.
  void Detach();
  // Whether the values are still the mapped file's pages (Read, where files can be mapped).
  bool InFilePages() const { return file_ != nullptr; }
  // BRDF (sr^-1) in the cell containing (wi, wo); NaN where the cell is missing.
  Rgb Lookup(const Vec3& wi, const Vec3& wo) const;

 private:
  struct Unfilled {};
  explicit MerlTable(Unfilled) {}
  // The stored values, 3 * kCells channel-major as in the file: the mapped file itself (Read),
  // or else owned_.
  std::shared_ptr<const MappedFile> file_;
  std::vector<double> owned_;
};

// The table as a reader's evaluator (DESIGN §4): nearest-cell lookup (Lookup), NaN in missing
// cells; the cell measure above. The description counts the missing cells.
std::shared_ptr<const TabulatedBrdf> MerlTabulated(std::shared_ptr<const MerlTable> table);
// The grid's cell measure (MerlTable::CellMeasure) as the capability readers hand out with it.
std::shared_ptr<const CellMeasure> MerlCellMeasure();
// Whether every sample above the horizon sits at a MERL cell centre (within 1e-6 rad): samples
// of a MERL table written by another format, which then stand for their cells as the table's do.
bool OnMerlGrid(const std::vector<Sample>& samples);

}  // namespace brdf
