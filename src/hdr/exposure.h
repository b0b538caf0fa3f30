// The exposure stage and the scene statistics the later stages need (DESIGN §8).
#pragma once

#include <cstdint>
#include <functional>

#include "hdr/image.h"

namespace brdf {

// Luminance statistics over the pixels with alpha > 0 (a rendered sphere's background does
// not count; an image without alpha has alpha 1 everywhere).
struct SceneLuminance {
  // Reinhard et al. 2002, eq. (1): exp(mean(log(delta + L_w))); delta keeps black pixels from
  // sending the mean to -infinity.
  double log_average = 0.0;
  double max = 0.0;
  int64_t pixels = 0;
  // Pixels of luminance <= 0 (black, or negative and clamped), and the log-average over the
  // others: each black pixel adds log(delta) to the mean, so many of them pull the automatic
  // exposure up (docs/stability.md).
  int64_t black_pixels = 0;
  double log_average_lit = 0.0;
};
// With `peaks` (PeakFloats(width, height) floats): the largest red, green and blue of each
// segment of each row (PeakAt), NaN skipped (-infinity for a segment of NaN only). The bright
// pass (bloom.h) uses them to skip the segments it can prove dark.
SceneLuminance MeasureSceneLuminance(const Image& image, double delta = 1e-4,
                                     float* peaks = nullptr);
// Row segments of the peaks: pixels [kPeakSegment s, kPeakSegment (s + 1)) of a row.
constexpr int kPeakSegment = 64;
inline int PeakSegments(int width) { return (width + kPeakSegment - 1) / kPeakSegment; }
inline int64_t PeakFloats(int width, int height) {
  return 3 * int64_t{PeakSegments(width)} * height;
}
// The red, green and blue peaks of segment `segment` of row y.
inline const float* PeakAt(const float* peaks, int width, int y, int segment) {
  return peaks + 3 * (int64_t{y} * PeakSegments(width) + segment);
}

// The same statistics of a width x height image that exists only a row at a time (the fused
// pipeline measures the exposed and bloomed image without storing it): `row(y, scratch)`
// returns row y, `width` RGBA pixels, written into `scratch` (room for two such rows) or held
// elsewhere.
// Rows are summed in chunks of a fixed number of rows, so the result does not depend on the
// thread count; MeasureSceneLuminance(image) is this with the image's own rows.
SceneLuminance MeasureSceneLuminanceByRow(
    int width, int height, double delta,
    const std::function<const float*(int y, float* scratch)>& row, float* peaks = nullptr);

// The statistics of an exposed (and bloomed) image that exists only a row at a time: row y
// has RGB = scale * in + strength * add (`add` null: no bloom), alpha that of `in`, as
// ExposeRow() makes it. `row(y, scratch)` returns row y's `in` and `add` (`scratch` has room
// for one RGBA row, e.g. for a bloom row made on the fly) and where to keep the exposed row's
// red, green and blue (null: nowhere): three planes of `width` floats, keep[x],
// keep[width + x], keep[2 width + x]. Summed like MeasureSceneLuminanceByRow, with the same
// result.
struct ExposedRowSource {
  const float* in = nullptr;
  const float* add = nullptr;
  float* keep = nullptr;
};
SceneLuminance MeasureExposedLuminanceByRow(
    int width, int height, double delta, float scale, float strength,
    const std::function<ExposedRowSource(int y, float* scratch)>& row);

// One exposed (and bloomed) row of `width` RGBA pixels into `out`: RGB = in * scale
// (+ strength * add when `add` is not null), alpha copied; the arithmetic of ApplyExposure
// then AddBloom, for a pipeline that never stores the exposed image.
void ExposeRow(const float* in, const float* add, int width, float scale, float strength,
               float* out);

// Multiplies RGB by `exposure` (2^EV for an exposure value EV).
void ApplyExposure(Image* image, double exposure);

// The exposure that brings the log-average luminance to `key` (Reinhard's 0.18, "middle
// grey"): how the preview chooses an exposure by itself.
double AutoExposure(const SceneLuminance& scene, double key = 0.18);

}  // namespace brdf
