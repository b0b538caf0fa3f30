#include <cmath>

#include "core/errors.h"
#include "hdr/blur.h"
#include "hdr/blur_separable.h"

namespace brdf {
namespace {

// Variance per axis of one pass: taps at +-o (o = offset + 1/2) and the bilinear split of
// each tap, f(1 - f) with f = frac(o).
double PassVariance(double offset) {
  const double o = offset + 0.5;
  const double f = o - std::floor(o);
  return o * o + f * (1.0 - f);
}

}  // namespace

double KawaseSigma(const std::vector<double>& offsets) {
  double variance = 0.0;
  for (double offset : offsets) variance += PassVariance(offset);
  return std::sqrt(variance);
}

std::vector<double> KawaseOffsetsForSigma(double sigma) {
  if (!(sigma > 0)) throw UsageError("Kawase blur: sigma must be > 0");
  std::vector<double> offsets;
  double remaining = sigma * sigma;
  for (int i = 0; PassVariance(i) <= remaining; ++i) {
    offsets.push_back(i);
    remaining -= PassVariance(i);
  }
  // PassVariance rises monotonically from 0 at offset -1/2, so the rest is solved by bisection
  // over offsets in [-1/2, next]; below 1e-6 px^2 the pass would not change the image.
  if (remaining > 1e-6) {
    double low = -0.5, high = static_cast<double>(offsets.size());
    for (int step = 0; step < 60; ++step) {
      const double middle = 0.5 * (low + high);
      (PassVariance(middle) < remaining ? low : high) = middle;
    }
    offsets.push_back(0.5 * (low + high));
  }
  return offsets;
}

Image KawaseBlur(const Image& image, const std::vector<double>& offsets) {
  Image result = image;
  for (double offset : offsets) {
    if (offset < -0.5) throw UsageError("Kawase blur: offsets must be >= -1/2");
    // The four bilinear taps at (+-o, +-o), weight 1/4 each, are the outer product of the 1D
    // kernel {1/2 at -o, 1/2 at +o} with itself, so a pass runs as two 1D passes.
    Kernel1D kernel;
    kernel.AddBilinearTap(-(offset + 0.5), 0.5);
    kernel.AddBilinearTap(offset + 0.5, 0.5);
    result = ConvolveSeparable(result, kernel);
  }
  return result;
}

}  // namespace brdf
