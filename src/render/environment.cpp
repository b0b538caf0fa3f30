#include "render/environment.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "core/angles.h"
#include "core/errors.h"
#include "core/text.h"
#include "hdr/image_files.h"

namespace brdf {
namespace {

// Index i with cdf[i] <= u < cdf[i + 1], skipping empty intervals.
int FindInterval(const double* cdf, int count, double u) {
  const double* upper = std::upper_bound(cdf + 1, cdf + count + 1, u);
  return std::clamp(static_cast<int>(upper - cdf) - 1, 0, count - 1);
}

}  // namespace

Environment::Environment(Image image) : image_(std::move(image)) {
  const int width = image_.width, height = image_.height;
  std::vector<double> weight(int64_t{width} * height);
  double total = 0.0;
  for (int r = 0; r < height; ++r) {
    const double sin_theta = std::sin(kPi * (r + 0.5) / height);
    for (int c = 0; c < width; ++c) {
      const double luminance = std::max(0.0f, PixelLuminance(image_.pixel(c, r)));
      weight[int64_t{r} * width + c] = luminance * sin_theta;
      total += luminance * sin_theta;
    }
  }
  // A black map has nothing to prefer: sample the sphere by area instead.
  if (!(total > 0.0)) {
    total = 0.0;
    for (int r = 0; r < height; ++r) {
      const double sin_theta = std::sin(kPi * (r + 0.5) / height);
      for (int c = 0; c < width; ++c) weight[int64_t{r} * width + c] = sin_theta;
      total += sin_theta * width;
    }
  }
  pixel_probability_.resize(weight.size());
  for (size_t i = 0; i < weight.size(); ++i) pixel_probability_[i] = weight[i] / total;
  marginal_cdf_.assign(height + 1, 0.0);
  conditional_cdf_.assign(int64_t{height} * (width + 1), 0.0);
  for (int r = 0; r < height; ++r) {
    double* row_cdf = conditional_cdf_.data() + int64_t{r} * (width + 1);
    for (int c = 0; c < width; ++c) {
      row_cdf[c + 1] = row_cdf[c] + pixel_probability_[int64_t{r} * width + c];
    }
    const double row_probability = row_cdf[width];
    marginal_cdf_[r + 1] = marginal_cdf_[r] + row_probability;
    for (int c = 1; c <= width; ++c) {
      row_cdf[c] = row_probability > 0.0 ? row_cdf[c] / row_probability : double(c) / width;
    }
  }
  for (double& value : marginal_cdf_) value /= marginal_cdf_[height];
}

Environment Environment::Uniform(const Rgb& radiance) {
  Image image(1, 1);
  for (int c = 0; c < 3; ++c) image.rgba[c] = static_cast<float>(radiance[c]);
  return Environment(std::move(image));
}

Environment Environment::Load(const std::string& spec, int64_t* non_finite) {
  if (StartsWith(spec, "uniform:")) {
    const std::vector<std::string_view> fields =
        SplitFields(std::string_view(spec).substr(8), ",", /*collapse=*/false);
    Rgb radiance;
    if (fields.size() != 1 && fields.size() != 3) {
      throw UsageError("--env '" + spec + "': expected uniform:L or uniform:R,G,B");
    }
    for (int c = 0; c < 3; ++c) {
      const std::string_view field = fields[fields.size() == 1 ? 0 : c];
      const auto [end, error] =
          std::from_chars(field.data(), field.data() + field.size(), radiance[c]);
      if (field.empty() || error != std::errc() || end != field.data() + field.size() ||
          !std::isfinite(radiance[c]) || radiance[c] < 0.0) {
        throw UsageError("--env '" + spec + "': expected a radiance >= 0, found '" +
                         std::string(field) + "'");
      }
    }
    return Uniform(radiance);
  }
  Image image = ReadHdrImage(spec);
  const int64_t broken = ReplaceNonFinite(&image);
  if (non_finite != nullptr) *non_finite = broken;
  return Environment(std::move(image));
}

void Environment::Locate(const Vec3& omega, int* row, int* column, double* sin_theta) const {
  const double theta = std::acos(std::clamp(omega.y(), -1.0, 1.0));
  double phi = std::atan2(omega.x(), -omega.z());
  if (phi < 0.0) phi += 2.0 * kPi;
  *row = std::clamp(static_cast<int>(theta / kPi * image_.height), 0, image_.height - 1);
  *column = std::clamp(static_cast<int>(phi / (2.0 * kPi) * image_.width), 0, image_.width - 1);
  *sin_theta = std::sin(theta);
}

Rgb Environment::Radiance(const Vec3& omega) const {
  int row = 0, column = 0;
  double sin_theta = 0.0;
  Locate(omega, &row, &column, &sin_theta);
  const float* rgba = image_.pixel(column, row);
  return Rgb(rgba[0], rgba[1], rgba[2]);
}

double Environment::Pdf(const Vec3& omega) const {
  int row = 0, column = 0;
  double sin_theta = 0.0;
  Locate(omega, &row, &column, &sin_theta);
  if (sin_theta <= 0.0) return 0.0;
  const double density_uv =
      pixel_probability_[int64_t{row} * image_.width + column] * image_.width * image_.height;
  return density_uv / (2.0 * kPi * kPi * sin_theta);
}

Environment::Sample Environment::SampleDirection(double u1, double u2) const {
  const int width = image_.width, height = image_.height;
  const int row = FindInterval(marginal_cdf_.data(), height, u1);
  const double row_width = marginal_cdf_[row + 1] - marginal_cdf_[row];
  const double v = (row + (row_width > 0 ? (u1 - marginal_cdf_[row]) / row_width : 0.5)) / height;
  const double* row_cdf = conditional_cdf_.data() + int64_t{row} * (width + 1);
  const int column = FindInterval(row_cdf, width, u2);
  const double column_width = row_cdf[column + 1] - row_cdf[column];
  const double u =
      (column + (column_width > 0 ? (u2 - row_cdf[column]) / column_width : 0.5)) / width;

  const double theta = kPi * std::clamp(v, 0.0, 1.0), phi = 2.0 * kPi * u;
  const double sin_theta = std::sin(theta);
  Sample sample;
  sample.direction = Vec3(sin_theta * std::sin(phi), std::cos(theta), -sin_theta * std::cos(phi));
  const float* rgba = image_.pixel(column, row);
  sample.radiance = Rgb(rgba[0], rgba[1], rgba[2]);
  sample.pdf = sin_theta > 0.0 ? pixel_probability_[int64_t{row} * width + column] * width *
                                     height / (2.0 * kPi * kPi * sin_theta)
                               : 0.0;
  return sample;
}

}  // namespace brdf
