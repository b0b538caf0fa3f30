#include "io/warp_2d.h"

#include <algorithm>
#include <cmath>

namespace brdf {
namespace {

// The largest i in [0, size - 2] with predicate(i) true, for a predicate that is true then
// false along i; 0 when it is false everywhere.
template <typename Predicate>
int64_t FindInterval(int64_t size, const Predicate& predicate) {
  int64_t low = 0, high = size - 2;  // answer in [low, high]
  while (low < high) {
    const int64_t middle = (low + high + 1) / 2;
    if (predicate(middle)) {
      low = middle;
    } else {
      high = middle - 1;
    }
  }
  return low;
}

// The t in [0, 1] with integral_0^t ((1 - s) a + s b) ds = area: a t + (b - a) t^2 / 2 = area.
// The root in the rationalized form 2 area / (a + sqrt(a^2 + 2 area (b - a))), which stays
// accurate as b - a -> 0 (no separate near-constant branch) and is 0 where there is no density.
double SolveLinearCdf(double a, double b, double area) {
  const double denominator = a + std::sqrt(std::max(0.0, a * a + 2.0 * area * (b - a)));
  if (!(denominator > 0.0)) return 0.0;
  return std::clamp(2.0 * area / denominator, 0.0, 1.0);
}

}  // namespace

int64_t Warp2D::FirstEmptySlice(int cols, int rows, const std::vector<double>& values) {
  const int64_t slice_size = int64_t{cols} * rows;
  for (int64_t slice = 0; slice * slice_size < static_cast<int64_t>(values.size()); ++slice) {
    double sum = 0.0;
    for (int64_t k = 0; k < slice_size; ++k) sum += values[slice * slice_size + k];
    if (!(sum > 0.0)) return slice;
  }
  return -1;
}

Warp2D::Warp2D(int cols, int rows, std::vector<double> values,
               std::vector<std::vector<double>> parameter_nodes, bool density)
    : cols_(cols),
      rows_(rows),
      parameter_nodes_(std::move(parameter_nodes)),
      data_(std::move(values)),
      density_(density) {
  parameter_strides_.assign(parameter_nodes_.size(), 0);
  int64_t slices = 1;
  for (int d = static_cast<int>(parameter_nodes_.size()) - 1; d >= 0; --d) {
    parameter_strides_[d] = slices;
    slices *= static_cast<int64_t>(parameter_nodes_[d].size());
  }
  if (!density_) return;
  const int64_t slice_size = int64_t{cols_} * rows_;
  marginal_cdf_.assign(slices * rows_, 0.0);
  conditional_cdf_.assign(slices * slice_size, 0.0);
  for (int64_t slice = 0; slice < slices; ++slice) {
    double* data = data_.data() + slice * slice_size;
    double* conditional = conditional_cdf_.data() + slice * slice_size;
    double* marginal = marginal_cdf_.data() + slice * rows_;
    // Along each row the bilinear patches integrate by the trapezoid rule (in patch units).
    for (int y = 0; y < rows_; ++y) {
      const int64_t row = int64_t{y} * cols_;
      for (int x = 0; x + 1 < cols_; ++x) {
        conditional[row + x + 1] = conditional[row + x] + 0.5 * (data[row + x] + data[row + x + 1]);
      }
    }
    // Across rows, the row integrals (the last conditional entry) by the same rule.
    for (int y = 0; y + 1 < rows_; ++y) {
      marginal[y + 1] = marginal[y] + 0.5 * (conditional[int64_t{y + 1} * cols_ - 1] +
                                             conditional[int64_t{y + 2} * cols_ - 1]);
    }
    const double normalization = 1.0 / marginal[rows_ - 1];
    for (int64_t k = 0; k < slice_size; ++k) {
      conditional[k] *= normalization;
      data[k] *= normalization;
    }
    for (int y = 0; y < rows_; ++y) marginal[y] *= normalization;
  }
}

Warp2D::SliceBlend Warp2D::Blend(const double* parameters) const {
  SliceBlend blend;
  blend.count = 1;
  blend.slice[0] = 0;
  blend.weight[0] = 1.0;
  for (size_t d = 0; d < parameter_nodes_.size(); ++d) {
    const std::vector<double>& nodes = parameter_nodes_[d];
    if (nodes.size() == 1) continue;
    const double value = parameters[d];
    const int64_t low = FindInterval(static_cast<int64_t>(nodes.size()),
                                     [&](int64_t k) { return nodes[k] <= value; });
    const double t = std::clamp((value - nodes[low]) / (nodes[low + 1] - nodes[low]), 0.0, 1.0);
    // Each slice so far splits into the two neighbours along this parameter.
    for (int k = blend.count - 1; k >= 0; --k) {
      blend.slice[2 * k + 1] = blend.slice[k] + (low + 1) * parameter_strides_[d];
      blend.weight[2 * k + 1] = blend.weight[k] * t;
      blend.slice[2 * k] = blend.slice[k] + low * parameter_strides_[d];
      blend.weight[2 * k] = blend.weight[k] * (1.0 - t);
    }
    blend.count *= 2;
  }
  return blend;
}

double Warp2D::Lookup(const std::vector<double>& table, int64_t slice_size, int64_t index,
                      const SliceBlend& blend) {
  double value = 0.0;
  for (int k = 0; k < blend.count; ++k) {
    if (blend.weight[k] != 0.0)
      value += blend.weight[k] * table[blend.slice[k] * slice_size + index];
  }
  return value;
}

double Warp2D::Eval(const Vec2& point, const double* parameters) const {
  const SliceBlend blend = Blend(parameters);
  const int64_t slice_size = int64_t{cols_} * rows_;
  const double x = std::clamp(point.x(), 0.0, 1.0) * (cols_ - 1);
  const double y = std::clamp(point.y(), 0.0, 1.0) * (rows_ - 1);
  const int px = std::min(static_cast<int>(x), cols_ - 2);
  const int py = std::min(static_cast<int>(y), rows_ - 2);
  const double tx = x - px, ty = y - py;
  const int64_t index = px + int64_t{py} * cols_;
  const double v00 = Lookup(data_, slice_size, index, blend);
  const double v10 = Lookup(data_, slice_size, index + 1, blend);
  const double v01 = Lookup(data_, slice_size, index + cols_, blend);
  const double v11 = Lookup(data_, slice_size, index + cols_ + 1, blend);
  const double value = (1 - ty) * ((1 - tx) * v00 + tx * v10) + ty * ((1 - tx) * v01 + tx * v11);
  // A density's patches are in patch units; per unit area of the square they are this much
  // denser.
  return density_ ? value * (cols_ - 1) * (rows_ - 1) : value;
}

Vec2 Warp2D::Sample(const Vec2& uniform, const double* parameters, double* pdf) const {
  const SliceBlend blend = Blend(parameters);
  const int64_t slice_size = int64_t{cols_} * rows_;
  // Kept off the square's edges so that an edge maps to the edge of the density's support,
  // not into rows or columns of zero density (where every point would collapse onto one).
  constexpr double kEdge = 1e-9;
  double sample_x = std::clamp(uniform.x(), kEdge, 1.0 - kEdge);
  double sample_y = std::clamp(uniform.y(), kEdge, 1.0 - kEdge);

  // The row: the marginal CDF at row nodes, then the position inside the row interval.
  auto marginal = [&](int64_t y) { return Lookup(marginal_cdf_, rows_, y, blend); };
  const int64_t row = FindInterval(rows_, [&](int64_t y) { return marginal(y) < sample_y; });
  sample_y -= marginal(row);
  const int64_t row_start = row * cols_;
  const double r0 = Lookup(conditional_cdf_, slice_size, row_start + cols_ - 1, blend);
  const double r1 = Lookup(conditional_cdf_, slice_size, row_start + 2 * cols_ - 1, blend);
  const double ty = SolveLinearCdf(r0, r1, sample_y);

  // The column, conditioned on that row position.
  sample_x *= (1 - ty) * r0 + ty * r1;
  auto conditional = [&](int64_t x) {
    return (1 - ty) * Lookup(conditional_cdf_, slice_size, row_start + x, blend) +
           ty * Lookup(conditional_cdf_, slice_size, row_start + cols_ + x, blend);
  };
  const int64_t col = FindInterval(cols_, [&](int64_t x) { return conditional(x) < sample_x; });
  sample_x -= conditional(col);
  const int64_t index = row_start + col;
  const double v00 = Lookup(data_, slice_size, index, blend);
  const double v10 = Lookup(data_, slice_size, index + 1, blend);
  const double v01 = Lookup(data_, slice_size, index + cols_, blend);
  const double v11 = Lookup(data_, slice_size, index + cols_ + 1, blend);
  const double c0 = (1 - ty) * v00 + ty * v01, c1 = (1 - ty) * v10 + ty * v11;
  const double tx = SolveLinearCdf(c0, c1, sample_x);
  if (pdf != nullptr) *pdf = ((1 - tx) * c0 + tx * c1) * (cols_ - 1) * (rows_ - 1);
  return Vec2((col + tx) / (cols_ - 1), (row + ty) / (rows_ - 1));
}

Vec2 Warp2D::Invert(const Vec2& point, const double* parameters, double* pdf) const {
  const SliceBlend blend = Blend(parameters);
  const int64_t slice_size = int64_t{cols_} * rows_;
  const double x = std::clamp(point.x(), 0.0, 1.0) * (cols_ - 1);
  const double y = std::clamp(point.y(), 0.0, 1.0) * (rows_ - 1);
  const int px = std::min(static_cast<int>(x), cols_ - 2);
  const int py = std::min(static_cast<int>(y), rows_ - 2);
  const double tx = x - px, ty = y - py;
  const int64_t index = px + int64_t{py} * cols_;
  const double v00 = Lookup(data_, slice_size, index, blend);
  const double v10 = Lookup(data_, slice_size, index + 1, blend);
  const double v01 = Lookup(data_, slice_size, index + cols_, blend);
  const double v11 = Lookup(data_, slice_size, index + cols_ + 1, blend);
  const double c0 = (1 - ty) * v00 + ty * v01, c1 = (1 - ty) * v10 + ty * v11;
  if (pdf != nullptr) *pdf = ((1 - tx) * c0 + tx * c1) * (cols_ - 1) * (rows_ - 1);

  // Column: the CDF up to the patch, plus the patch's integral from its left edge to tx, over
  // the row's total, all interpolated to the row position ty.
  const double row_start = (1 - ty) * Lookup(conditional_cdf_, slice_size, index, blend) +
                           ty * Lookup(conditional_cdf_, slice_size, index + cols_, blend);
  const double inside = tx * (c0 + 0.5 * tx * (c1 - c0));
  const int64_t row_begin = int64_t{py} * cols_;
  const double r0 = Lookup(conditional_cdf_, slice_size, row_begin + cols_ - 1, blend);
  const double r1 = Lookup(conditional_cdf_, slice_size, row_begin + 2 * cols_ - 1, blend);
  const double row_total = (1 - ty) * r0 + ty * r1;
  const double uniform_x = row_total > 0.0 ? (row_start + inside) / row_total : 0.0;
  // Row: the marginal CDF up to the row interval plus the interval's integral up to ty.
  const double uniform_y =
      Lookup(marginal_cdf_, rows_, py, blend) + ty * (r0 + 0.5 * ty * (r1 - r0));
  return Vec2(uniform_x, uniform_y);
}

}  // namespace brdf
