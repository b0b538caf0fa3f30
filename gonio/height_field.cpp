#include "gonio/height_field.h"

#include <ImfArray.h>
#include <ImfRgbaFile.h>

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "core/text.h"
#include "gonio/rng.h"

namespace brdf::gonio {
namespace {

// A normalized Gaussian kernel of standard deviation `sigma` (cells), 3 sigma either side.
std::vector<double> GaussianKernel(double sigma) {
  const int radius = static_cast<int>(std::ceil(3 * sigma));
  std::vector<double> kernel(2 * radius + 1);
  double sum = 0;
  for (int k = -radius; k <= radius; ++k)
    sum += kernel[k + radius] = std::exp(-0.5 * k * k / (sigma * sigma));
  for (double& weight : kernel) weight /= sum;
  return kernel;
}

// Periodic separable Gaussian blur of an n × n grid, `sigma_x` along x and `sigma_y` along y.
std::vector<float> BlurPeriodic(const std::vector<float>& grid, int n, double sigma_x,
                                double sigma_y) {
  const std::vector<double> kernel_x = GaussianKernel(sigma_x), kernel_y = GaussianKernel(sigma_y);
  const int radius_x = static_cast<int>(kernel_x.size() / 2);
  const int radius_y = static_cast<int>(kernel_y.size() / 2);
  std::vector<float> rows(grid.size()), result(grid.size());
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      double value = 0;
      for (int k = -radius_x; k <= radius_x; ++k)
        value += kernel_x[k + radius_x] * grid[y * n + ((x + k) % n + n) % n];
      rows[y * n + x] = static_cast<float>(value);
    }
  }
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      double value = 0;
      for (int k = -radius_y; k <= radius_y; ++k)
        value += kernel_y[k + radius_y] * rows[((y + k) % n + n) % n * n + x];
      result[y * n + x] = static_cast<float>(value);
    }
  }
  return result;
}

// White noise blurred by a Gaussian of sigma cells has the autocorrelation exp(-d²/(4 sigma²))
// along that axis, so a unit step's height difference has variance 2 C0 (1 - exp(-1/(4
// sigma²))). The smoothing radius whose variance is `ratio`² of that of radius `sigma`.
double RadiusForSlopeRatio(double sigma, double ratio) {
  const double share = ratio * ratio * (1.0 - std::exp(-0.25 / (sigma * sigma)));
  return 0.5 / std::sqrt(-std::log1p(-share));
}

HeightField ReadExrHeights(const std::string& path) {
  HeightField field;
  try {
    Imf::RgbaInputFile file(path.c_str());
    const Imath::Box2i window = file.dataWindow();
    const int width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
    if (width != height || width < 4) {
      throw InputError(path, "height map must be square and at least 4 x 4, found " +
                                 std::to_string(width) + " x " + std::to_string(height));
    }
    Imf::Array2D<Imf::Rgba> pixels(height, width);
    file.setFrameBuffer(&pixels[0][0] - window.min.x - window.min.y * width, 1, width);
    file.readPixels(window.min.y, window.max.y);
    field.resolution = width;
    field.heights.resize(size_t(width) * width);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const float value = pixels[y][x].r;
        if (!std::isfinite(value))
          throw InputError(
              path, "non-finite height at pixel " + std::to_string(x) + "," + std::to_string(y));
        field.heights[size_t(y) * width + x] = value;
      }
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& error) {
    throw InputError(path, std::string("cannot read the EXR height map: ") + error.what());
  }
  return field;
}

}  // namespace

void HeightFieldSpec::Validate(const std::string& origin) const {
  const auto fail = [&](const std::string& what) {
    throw InputError(origin, "heightfield." + what);
  };
  if (kind != "flat" && kind != "gaussian" && kind != "v-grooves" && kind != "file") {
    fail("kind: expected flat, gaussian, v-grooves or file, got \"" + kind + "\"");
  }
  if (!(rms_slope > 0 && rms_slope <= 5))
    fail("rms_slope: must be in (0, 5], got " + FormatNumber(rms_slope));
  if (!(rms_slope_y == 0 || (rms_slope_y > 0 && rms_slope_y <= 5)))
    fail("rms_slope_y: must be in (0, 5], got " + FormatNumber(rms_slope_y));
  if (rms_slope_y != 0 && kind != "gaussian")
    fail("rms_slope_y: only a gaussian height field has a second slope, not \"" + kind + "\"");
  if (resolution < 4 || resolution > 8192)
    fail("resolution: must be in [4, 8192], got " + std::to_string(resolution));
  if (!(correlation >= 0.5 && correlation <= resolution / 4.0))
    fail("correlation: must be in [0.5, resolution/4] cells, got " + FormatNumber(correlation));
  if (kind == "gaussian" && !(std::max(CorrelationX(), CorrelationY()) <= resolution / 4.0)) {
    fail("rms_slope_y: the smoother axis is smoothed over " +
         FormatNumber(std::max(CorrelationX(), CorrelationY())) +
         " cells, more than resolution/4; raise the resolution or lower the correlation");
  }
  if (period < 2 || period % 2 != 0 || resolution % period != 0)
    fail("period: must be even and divide the resolution, got " + std::to_string(period));
  if (kind == "file" && path.empty()) fail("path: a height map (EXR) is needed for kind \"file\"");
}

double HeightFieldSpec::CorrelationX() const {
  return SlopeX() < SlopeY() ? RadiusForSlopeRatio(correlation, SlopeX() / SlopeY()) : correlation;
}

double HeightFieldSpec::CorrelationY() const {
  return SlopeY() < SlopeX() ? RadiusForSlopeRatio(correlation, SlopeY() / SlopeX()) : correlation;
}

float HeightField::MinHeight() const { return *std::min_element(heights.begin(), heights.end()); }
float HeightField::MaxHeight() const { return *std::max_element(heights.begin(), heights.end()); }

double HeightField::RmsSlope() const {
  double sum = 0;
  for (int y = 0; y < resolution; ++y) {
    for (int x = 0; x < resolution; ++x) {
      const double dx = At(x + 1, y) - At(x, y), dy = At(x, y + 1) - At(x, y);
      sum += dx * dx + dy * dy;
    }
  }
  return std::sqrt(sum / (double(resolution) * resolution));
}

HeightField MakeHeightField(const HeightFieldSpec& spec) {
  if (spec.kind == "file") return ReadExrHeights(spec.path);
  HeightField field;
  const int n = spec.resolution;
  field.resolution = n;
  field.heights.assign(size_t(n) * n, 0.0f);
  if (spec.kind == "flat") return field;
  if (spec.kind == "v-grooves") {
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        const int phase = x % spec.period;
        field.heights[size_t(y) * n + x] =
            static_cast<float>(spec.rms_slope * std::abs(phase - spec.period / 2));
      }
    }
    return field;
  }
  std::vector<float> noise(size_t(n) * n);
  for (size_t k = 0; k < noise.size(); ++k) {
    noise[k] = static_cast<float>(StreamRng(spec.seed, Stream::kHeightField, k).Normal());
  }
  field.heights = BlurPeriodic(noise, n, spec.CorrelationX(), spec.CorrelationY());
  // The realized field's sqrt(<|∇h|²>) is set exactly; its split between the axes follows the
  // smoothing radii (each axis within about 2 % at 128², the tests say).
  const double rms =
      spec.rms_slope_y > 0
          ? std::sqrt(0.5 * (spec.SlopeX() * spec.SlopeX() + spec.SlopeY() * spec.SlopeY()))
          : spec.rms_slope;
  const double scale = rms / field.RmsSlope();
  for (float& h : field.heights) h = static_cast<float>(h * scale);
  return field;
}

}  // namespace brdf::gonio
