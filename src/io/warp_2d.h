// A piecewise-bilinear function on the unit square, tabulated on a cols x rows grid of nodes
// (node (x, y) at (x / (cols - 1), y / (rows - 1))), in one or more "slices" selected by up to
// three parameters with linear interpolation between slices. As a density it also maps uniform
// points of the square to points distributed like it and back, by the inversion method:
// marginal over rows, then conditional over columns, each CDF integrating the bilinear patches
// exactly (a quadratic per patch). This is the warp of Dupuy & Jakob 2018, section 5, which the
// RGL-EPFL material files store their samples in (the "Marginal2D" of the paper's reference code
// and of Mitsuba 3's include/mitsuba/core/distr_2d.h; written here from the description).
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

namespace brdf {

using Vec2 = Eigen::Vector2d;  // (x, y): x along the columns (the last axis), y along the rows

class Warp2D {
 public:
  static constexpr int kMaxParameters = 3;

  // `values`: the slices one after another, each rows x cols in C order (x fastest); the
  // slices are indexed by the parameters in C order (the last parameter fastest), and
  // `parameter_nodes[d]` lists the values of parameter d at its slices (increasing).
  // With `density`, each slice is scaled to integrate to one and the CDFs are built; every
  // slice must then be non-negative with a positive integral (the caller checks: DensityError).
  Warp2D(int cols, int rows, std::vector<double> values,
         std::vector<std::vector<double>> parameter_nodes, bool density);
  Warp2D() = default;

  // Index of the first slice (in `values` order) whose integral is not positive, or -1.
  static int64_t FirstEmptySlice(int cols, int rows, const std::vector<double>& values);

  // The bilinear interpolant at `point` (a density when built as one: it integrates to 1).
  double Eval(const Vec2& point, const double* parameters = nullptr) const;
  // A uniform point of the square -> a point distributed like the density; `*pdf` its density.
  Vec2 Sample(const Vec2& uniform, const double* parameters, double* pdf) const;
  // The inverse of Sample: a point -> the uniform point that maps to it; `*pdf` as in Sample.
  Vec2 Invert(const Vec2& point, const double* parameters, double* pdf) const;

  int cols() const { return cols_; }
  int rows() const { return rows_; }

 private:
  // Up to 2^3 slices and their interpolation weights for given parameter values.
  struct SliceBlend {
    std::array<int64_t, 1 << kMaxParameters> slice{};
    std::array<double, 1 << kMaxParameters> weight{};
    int count = 0;
  };
  SliceBlend Blend(const double* parameters) const;
  // `table`'s entry `index` (within one slice of `slice_size`) blended over the slices.
  static double Lookup(const std::vector<double>& table, int64_t slice_size, int64_t index,
                       const SliceBlend& blend);

  int cols_ = 0, rows_ = 0;
  std::vector<std::vector<double>> parameter_nodes_;
  std::vector<int64_t> parameter_strides_;
  std::vector<double> data_;
  std::vector<double> marginal_cdf_;     // per slice: rows entries
  std::vector<double> conditional_cdf_;  // per slice: rows x cols entries
  bool density_ = false;
};

}  // namespace brdf
