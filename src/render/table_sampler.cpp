#include "render/table_sampler.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/angles.h"
#include "core/colour.h"

namespace brdf {
namespace {

constexpr double kHalfPi = 0.5 * kPi;
constexpr double kPhiStep = 2.0 * kPi / TableSampler::kPhiBins;
constexpr int kCellsPerBin = TableSampler::kThetaBins * TableSampler::kPhiBins;

// theta_h at u = sqrt(theta_h / (pi/2)), and 1 - cos of it without cancellation.
double ThetaOfU(double u) { return u * u * kHalfPi; }
double OneMinusCos(double theta) {
  const double s = std::sin(0.5 * theta);
  return 2.0 * s * s;
}

// The half vector at (1 - cos theta_h, phi_h).
Vec3 HalfVector(double one_minus_cos, double phi) {
  const double cos_theta = 1.0 - one_minus_cos;
  const double sin_theta = std::sqrt(std::max(0.0, one_minus_cos * (2.0 - one_minus_cos)));
  return Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
}

// The first index k in [0, n) with cdf[k + 1] > u (cdf has n + 1 entries, cdf[n] = 1).
int FindInterval(const double* cdf, int n, double u) {
  const int k = static_cast<int>(std::upper_bound(cdf + 1, cdf + n + 1, u) - (cdf + 1));
  return std::min(k, n - 1);
}

}  // namespace

int TableSampler::IncidenceBin(double theta_o) {
  return std::clamp(static_cast<int>(theta_o / kHalfPi * kIncidenceBins), 0, kIncidenceBins - 1);
}

TableSampler::TableSampler(const std::function<Rgb(const Vec3& wi, const Vec3& wo)>& brdf)
    : row_cdf_(kIncidenceBins * (kThetaBins + 1), 0.0),
      column_cdf_(kIncidenceBins * kThetaBins * (kPhiBins + 1), 0.0),
      density_(kIncidenceBins * kCellsPerBin, 0.0),
      bin_total_(kIncidenceBins, 0.0),
      one_minus_cos_edge_(kThetaBins + 1) {
  for (int row = 0; row <= kThetaBins; ++row) {
    one_minus_cos_edge_[row] = OneMinusCos(ThetaOfU(double(row) / kThetaBins));
  }
  tbb::parallel_for(0, kIncidenceBins, [&](int bin) {
    const double theta_o = (bin + 0.5) / kIncidenceBins * kHalfPi;
    const Vec3 wo = SphericalDirection(theta_o, 0.0);
    std::vector<double> weight(kCellsPerBin, 0.0);
    for (int row = 0; row < kThetaBins; ++row) {
      const double solid_angle_row = one_minus_cos_edge_[row + 1] - one_minus_cos_edge_[row];
      for (int column = 0; column < kPhiBins; ++column) {
        double sum = 0.0;
        for (int a = 0; a < 2; ++a) {
          for (int b = 0; b < 2; ++b) {
            const double u = (row + 0.25 + 0.5 * a) / kThetaBins;
            const Vec3 h =
                HalfVector(OneMinusCos(ThetaOfU(u)), (column + 0.25 + 0.5 * b) * kPhiStep);
            const double wo_dot_h = wo.dot(h);
            const Vec3 wi = 2.0 * wo_dot_h * h - wo;
            if (wi.z() <= 0.0 || wo_dot_h <= 0.0) continue;
            const double value = Luminance(brdf(wi, wo)) * wi.z() * 4.0 * wo_dot_h;
            if (value > 0.0 && std::isfinite(value)) sum += value;
          }
        }
        weight[row * kPhiBins + column] = 0.25 * sum * solid_angle_row * kPhiStep;
      }
    }
    // Rows, then columns within each row, as cumulative sums normalised to 1.
    double* rows = &row_cdf_[bin * (kThetaBins + 1)];
    for (int row = 0; row < kThetaBins; ++row) {
      double row_sum = 0.0;
      double* columns = &column_cdf_[(bin * kThetaBins + row) * (kPhiBins + 1)];
      for (int column = 0; column < kPhiBins; ++column) {
        row_sum += weight[row * kPhiBins + column];
        columns[column + 1] = row_sum;
      }
      for (int column = 1; column <= kPhiBins; ++column) {
        columns[column] = row_sum > 0.0 ? columns[column] / row_sum : double(column) / kPhiBins;
      }
      rows[row + 1] = rows[row] + row_sum;
    }
    const double total = rows[kThetaBins];
    bin_total_[bin] = total;
    if (!(total > 0.0)) return;
    for (int row = 1; row <= kThetaBins; ++row) rows[row] /= total;
    rows[kThetaBins] = 1.0;
    for (int row = 0; row < kThetaBins; ++row) {
      const double solid_angle =
          (one_minus_cos_edge_[row + 1] - one_minus_cos_edge_[row]) * kPhiStep;
      for (int column = 0; column < kPhiBins; ++column) {
        density_[bin * kCellsPerBin + row * kPhiBins + column] =
            weight[row * kPhiBins + column] / total / solid_angle;
      }
    }
  });
}

TableSampler::View TableSampler::ViewOf(const Vec3& wo) {
  View view;
  view.wo = wo.normalized();
  view.bin = IncidenceBin(Theta(view.wo));
  view.phi_o = std::atan2(view.wo.y(), view.wo.x());
  return view;
}

Vec3 TableSampler::Sample(const Vec3& wo, double u0, double u1) const {
  return SampleIn(ViewOf(wo), u0, u1);
}

double TableSampler::Pdf(const Vec3& wo, const Vec3& wi) const { return PdfIn(ViewOf(wo), wi); }

Vec3 TableSampler::SampleIn(const View& view, double u0, double u1) const {
  if (!HasWeight(view.bin)) return Vec3(0.0, 0.0, -1.0);
  const double* rows = &row_cdf_[view.bin * (kThetaBins + 1)];
  const int row = FindInterval(rows, kThetaBins, u0);
  const double* columns = &column_cdf_[(view.bin * kThetaBins + row) * (kPhiBins + 1)];
  const int column = FindInterval(columns, kPhiBins, u1);
  // What is left of u0 and u1 inside the chosen row and column, uniform in [0, 1).
  const double in_row =
      std::clamp((u0 - rows[row]) / std::max(rows[row + 1] - rows[row], 1e-300), 0.0, 1.0);
  const double in_column = std::clamp(
      (u1 - columns[column]) / std::max(columns[column + 1] - columns[column], 1e-300), 0.0, 1.0);
  const double one_minus_cos =
      one_minus_cos_edge_[row] + in_row * (one_minus_cos_edge_[row + 1] - one_minus_cos_edge_[row]);
  const Vec3 h = HalfVector(one_minus_cos, view.phi_o + (column + in_column) * kPhiStep);
  return 2.0 * view.wo.dot(h) * h - view.wo;
}

double TableSampler::PdfIn(const View& view, const Vec3& wi) const {
  if (!(wi.z() > 0.0) || !HasWeight(view.bin)) return 0.0;
  const Vec3 sum = wi.normalized() + view.wo;
  const double norm = sum.norm();
  if (!(norm > 0.0)) return 0.0;
  const Vec3 h = sum / norm;
  const double wo_dot_h = view.wo.dot(h);
  if (!(wo_dot_h > 0.0)) return 0.0;
  const double theta_h = std::atan2(std::hypot(h.x(), h.y()), h.z());
  const int row =
      std::min(static_cast<int>(std::sqrt(theta_h / kHalfPi) * kThetaBins), kThetaBins - 1);
  double phi = std::atan2(h.y(), h.x()) - view.phi_o;
  phi -= 2.0 * kPi * std::floor(phi / (2.0 * kPi));
  const int column = std::clamp(static_cast<int>(phi / kPhiStep), 0, kPhiBins - 1);
  return density_[view.bin * kCellsPerBin + row * kPhiBins + column] / (4.0 * wo_dot_h);
}

void TableSampler::SampleBatch(const Vec3f& wo, const float* u0, const float* u1, int count,
                               float* x, float* y, float* z) const {
  const View view = ViewOf(wo.cast<double>());
  for (int k = 0; k < count; ++k) {
    const Vec3 wi = SampleIn(view, u0[k], u1[k]);
    x[k] = static_cast<float>(wi.x());
    y[k] = static_cast<float>(wi.y());
    z[k] = static_cast<float>(wi.z());
  }
}

void TableSampler::PdfBatch(const Vec3f& wo, const float* x, const float* y, const float* z,
                            int count, float* pdf) const {
  const View view = ViewOf(wo.cast<double>());
  for (int k = 0; k < count; ++k) {
    pdf[k] = static_cast<float>(PdfIn(view, Vec3(x[k], y[k], z[k])));
  }
}

}  // namespace brdf
