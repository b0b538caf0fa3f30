#include "render/environment.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "core/angles.h"
#include "core/errors.h"
#include "core/text.h"
#include "hdr/image_files.h"

namespace brdf {
Environment::Environment(Image image)
    : width_(image.width),
      height_(image.height),
      row_scale_(static_cast<float>(image.height / kPi)),
      column_scale_(static_cast<float>(image.width / (2.0 * kPi))) {
  const int width = width_, height = height_;
  const int64_t count = int64_t{width} * height;
  if (count >= (int64_t{1} << 32)) {
    throw UsageError("environment of " + std::to_string(width) + "x" + std::to_string(height) +
                     " pixels: at most 2^32 pixels are supported");
  }
  std::vector<double> weight(static_cast<size_t>(count));
  double total = 0.0;
  for (int r = 0; r < height; ++r) {
    const double sin_theta = std::sin(kPi * (r + 0.5) / height);
    for (int c = 0; c < width; ++c) {
      const double luminance = std::max(0.0f, PixelLuminance(image.pixel(c, r)));
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
  texels_.resize(count);
  for (int64_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) texels_[i].rgb[c] = image.rgba[i * Image::kChannels + c];
    texels_[i].density_uv = static_cast<float>(weight[i] / total * count);
    texels_[i].alias = static_cast<uint32_t>(i);
  }

  // Vose's construction: scaled probabilities count * p_i split into those below 1 ("small")
  // and the rest; each small entry is topped up from a large one, which becomes its alias.
  std::vector<double> scaled(static_cast<size_t>(count));
  std::vector<uint32_t> small, large;
  for (int64_t i = 0; i < count; ++i) {
    scaled[i] = weight[i] / total * count;
    (scaled[i] < 1.0 ? small : large).push_back(static_cast<uint32_t>(i));
  }
  while (!small.empty() && !large.empty()) {
    const uint32_t less = small.back(), more = large.back();
    small.pop_back();
    texels_[less].keep = static_cast<float>(scaled[less]);
    texels_[less].alias = more;
    scaled[more] -= 1.0 - scaled[less];
    if (scaled[more] < 1.0) {
      large.pop_back();
      small.push_back(more);
    }
  }
  // What remains is 1 up to rounding.
  for (uint32_t i : large) texels_[i].keep = 1.0f, texels_[i].alias = i;
  for (uint32_t i : small) texels_[i].keep = 1.0f, texels_[i].alias = i;
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
      throw UsageError("environment '" + spec + "': expected uniform:L or uniform:R,G,B");
    }
    for (int c = 0; c < 3; ++c) {
      const std::string_view field = fields[fields.size() == 1 ? 0 : c];
      const auto [end, error] =
          std::from_chars(field.data(), field.data() + field.size(), radiance[c]);
      if (field.empty() || error != std::errc() || end != field.data() + field.size() ||
          !std::isfinite(radiance[c]) || radiance[c] < 0.0) {
        throw UsageError("environment '" + spec + "': expected a radiance >= 0, found '" +
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
  const double cos_theta = std::clamp(omega.y(), -1.0, 1.0);
  const double theta = std::acos(cos_theta);
  double phi = std::atan2(omega.x(), -omega.z());
  if (phi < 0.0) phi += 2.0 * kPi;
  *row = std::clamp(static_cast<int>(theta * (height_ / kPi)), 0, height_ - 1);
  *column = std::clamp(static_cast<int>(phi * (width_ / (2.0 * kPi))), 0, width_ - 1);
  *sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
}

Rgb Environment::Radiance(const Vec3& omega) const {
  double pdf = 0.0;
  return RadianceAndPdf(omega, &pdf);
}

double Environment::Pdf(const Vec3& omega) const {
  double pdf = 0.0;
  RadianceAndPdf(omega, &pdf);
  return pdf;
}

Rgb Environment::RadianceAndPdf(const Vec3& omega, double* pdf) const {
  int row = 0, column = 0;
  double sin_theta = 0.0;
  Locate(omega, &row, &column, &sin_theta);
  const Texel& texel = texels_[int64_t{row} * width_ + column];
  *pdf = sin_theta > 0.0 ? texel.density_uv / (2.0 * kPi * kPi * sin_theta) : 0.0;
  return Rgb(texel.rgb[0], texel.rgb[1], texel.rgb[2]);
}

Environment::Sample Environment::SampleDirection(double u1, double u2) const {
  const int width = width_, height = height_;
  const int64_t count = int64_t{width} * height;
  // u1 picks a slot; its leftover fraction, uniform in [0, 1), decides between the slot and
  // its alias and, rescaled once more, places the point across the pixel.
  const double slot_position = u1 * count;
  const int64_t slot = std::min<int64_t>(static_cast<int64_t>(slot_position), count - 1);
  double fraction = slot_position - slot;
  int64_t pixel = slot;
  const Texel& entry = texels_[slot];
  if (fraction < entry.keep) {
    fraction /= entry.keep;
  } else {
    fraction = (fraction - entry.keep) / (1.0 - entry.keep);
    pixel = entry.alias;
  }
  const int row = static_cast<int>(pixel / width), column = static_cast<int>(pixel % width);
  const double u = (column + std::clamp(fraction, 0.0, 1.0)) / width;
  const double v = (row + u2) / height;

  const double theta = kPi * v, phi = 2.0 * kPi * u;
  const double sin_theta = std::sin(theta);
  Sample sample;
  sample.direction = Vec3(sin_theta * std::sin(phi), std::cos(theta), -sin_theta * std::cos(phi));
  const Texel& texel = texels_[pixel];
  sample.radiance = Rgb(texel.rgb[0], texel.rgb[1], texel.rgb[2]);
  sample.pdf = sin_theta > 0.0 ? texel.density_uv / (2.0 * kPi * kPi * sin_theta) : 0.0;
  return sample;
}

uint32_t Environment::DrawFloat(uint32_t slot, uint64_t bits, float v_in_pixel, float* u,
                                float* v) const {
  // Selects, not a branch: which way a draw goes is random (core/float_math.h).
  const float below = static_cast<float>(bits & 0xffffff) * 0x1.0p-24f;
  const Texel& entry = texels_[slot];
  const bool aliased = !(below < entry.keep);
  const float taken = static_cast<float>(aliased);
  const uint32_t pixel = aliased ? entry.alias : slot;
  const float fraction =
      (below - taken * entry.keep) / ((1.0f - taken) * entry.keep + taken * (1.0f - entry.keep));
  const uint32_t row = pixel / static_cast<uint32_t>(width_);
  const uint32_t column = pixel - row * static_cast<uint32_t>(width_);
  *u = (static_cast<float>(column) + std::min(fraction, 1.0f)) / width_;
  *v = (static_cast<float>(row) + v_in_pixel) / height_;
  return pixel;
}

}  // namespace brdf
