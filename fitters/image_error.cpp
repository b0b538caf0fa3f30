#include "fitters/image_error.h"

#include <cmath>

#include "core/angles.h"
#include "core/errors.h"
#include "core/format.h"
#include "core/sampling.h"
#include "fitters/fit_samples.h"

namespace brdf::fitters {

std::vector<PixelGeometry> LitSphereGeometry(const ImageErrorSetup& setup) {
  std::vector<PixelGeometry> pixels;
  const Vec3 wo_world(0.0, 0.0, 1.0);
  for (double theta_deg : setup.light_theta_deg) {
    const double theta = DegToRad(theta_deg);
    const Vec3 light(std::sin(theta), 0.0, std::cos(theta));
    for (int y = 0; y < setup.size; ++y) {
      for (int x = 0; x < setup.size; ++x) {
        // The pixel's normal as render/sphere.h defines it.
        const double u = (2.0 * x + 1.0) / setup.size - 1.0;
        const double v = 1.0 - (2.0 * y + 1.0) / setup.size;
        const double r2 = u * u + v * v;
        if (r2 >= 1.0) continue;
        const Frame frame = Frame::FromZ(Vec3(u, v, std::sqrt(1.0 - r2)));
        const Vec3 wi = frame.ToLocal(light);
        if (wi.z() <= 0.0) continue;
        pixels.push_back({wi, frame.ToLocal(wo_world)});
      }
    }
  }
  return pixels;
}

SphereRadiance RenderLitSphere(const BrdfFunction& brdf, const ImageErrorSetup& setup) {
  SphereRadiance result;
  for (const PixelGeometry& pixel : LitSphereGeometry(setup)) {
    result.radiance.push_back(brdf(pixel.wi, pixel.wo) * pixel.wi.z());
  }
  return result;
}

ImageErrorSetup ImageLossSetup() {
  ImageErrorSetup setup;
  setup.size = 64;
  setup.light_theta_deg = {5, 15, 25, 35, 45, 55, 65, 75, 85};
  return setup;
}

Measurement ImageLossSamples(const Measurement& measurement) {
  if (!measurement.tabulated) {
    throw ComputeError(measurement.source + ": the image loss's spheres need an evaluator");
  }
  Measurement rendered;
  rendered.format = measurement.format;
  rendered.source = measurement.source;
  rendered.metadata = measurement.metadata;
  rendered.metadata["weighting"] = "equal";
  // The pixels are values of the table, not readings of an instrument.
  rendered.metadata.erase(kInstrumentKey);
  rendered.tabulated = measurement.tabulated;
  for (const PixelGeometry& pixel : LitSphereGeometry(ImageLossSetup())) {
    const Rgb value = measurement.tabulated->Eval(pixel.wi, pixel.wo);
    if (value.allFinite()) rendered.samples.push_back({pixel.wi, pixel.wo, value});
  }
  return rendered;
}

std::string ImageLossWeighting() {
  const ImageErrorSetup setup = ImageLossSetup();
  return Format(
      "the table at the pixels of %d x %d px spheres under lights at %g, %g, ..., %g deg "
      "(image loss), equal weights",
      setup.size, setup.size, setup.light_theta_deg.front(), setup.light_theta_deg[1],
      setup.light_theta_deg.back());
}

double RelativeL1(const SphereRadiance& reference, const SphereRadiance& test) {
  if (reference.radiance.size() != test.radiance.size()) {
    throw ComputeError("image error: the two renders differ in size");
  }
  Rgb difference = Rgb::Zero(), total = Rgb::Zero();
  for (size_t k = 0; k < reference.radiance.size(); ++k) {
    const Rgb& a = reference.radiance[k];
    const Rgb& b = test.radiance[k];
    if (!a.allFinite() || !b.allFinite()) continue;
    difference += (a - b).abs();
    total += a.abs();
  }
  double sum = 0;
  for (int c = 0; c < 3; ++c) sum += total[c] > 0 ? difference[c] / total[c] : 0.0;
  return sum / 3.0;
}

}  // namespace brdf::fitters
