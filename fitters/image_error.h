// Image-space error of a fitted material against a reference (DESIGN §6 and §12): both rendered
// as the preview sphere (render/sphere.h: orthographic camera along -z, a unit sphere filling an
// N x N image, wo = +z) under directional lights of unit irradiance, and compared by the relative
// L1 of their RGB radiance over the lit sphere, per channel:
//
//   e_c = sum over pixels and lights |L_fit,c - L_ref,c| / sum over pixels and lights L_ref,c,
//   L_c = f_c(wi, wo) cos theta_i,
//
// the error the mean of e_c over the channels. Pixels where the reference has no value (a
// missing MERL cell) count for neither image. A render with directional lights alone is exact
// (no Monte Carlo), so this is what `brdf render` shows of the two materials under those lights,
// computed here without the render library so that `--model auto` can use it (select.h).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/measurement.h"
#include "core/vec.h"

namespace brdf::fitters {

using BrdfFunction = std::function<Rgb(const Vec3& wi, const Vec3& wo)>;

struct ImageErrorSetup {
  int size = 128;  // image width = height, px
  // The lights' angles from the view direction, degrees, in the plane x-z (to the right).
  std::vector<double> light_theta_deg = {20.0, 60.0};
};

// The radiance of every lit pixel under every light, in a fixed order (light, row, column).
struct SphereRadiance {
  std::vector<Rgb> radiance;  // NaN where the material has no value
};

// The (wi, wo) of every lit pixel under every light, in that order, in the pixel's local frame.
struct PixelGeometry {
  Vec3 wi, wo;
};
std::vector<PixelGeometry> LitSphereGeometry(const ImageErrorSetup& setup);

SphereRadiance RenderLitSphere(const BrdfFunction& brdf, const ImageErrorSetup& setup = {});

// The geometries the `image` loss fits a measurement with an evaluator on (fit_samples.h):
// spheres of 64 x 64 px under lights at 5, 15, ..., 85 degrees from the view, none of them a
// scoring light of the image error (ImageErrorSetup's defaults), so that a fit is not scored on
// its own samples. Lights behind the sphere are left out: their lit crescents see f at grazing
// angles, where a table's values are least certain, and with them the fits of the benchmark
// lose the front-lit highlight (docs/real-data.md).
ImageErrorSetup ImageLossSetup();

// The measurement's evaluator at ImageLossSetup()'s pixels: equal weights (each pixel stands
// for itself), the evaluator and the metadata kept; pixels without a value left out. Throws
// ComputeError when the measurement has no evaluator.
Measurement ImageLossSamples(const Measurement& measurement);
// How ImageLossSamples weighs, for the fit report.
std::string ImageLossWeighting();

// The mean over channels of the relative L1 error of `test` against `reference` (same setup).
double RelativeL1(const SphereRadiance& reference, const SphereRadiance& test);

}  // namespace brdf::fitters
