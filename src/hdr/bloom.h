// Bloom (DESIGN §8): light scattered in the eye or the lens spreads around bright sources.
// Bright pass -> blur (blur.h) -> added back with a strength.
#pragma once

#include "hdr/image.h"

namespace brdf {

// Keeps what lies above `threshold` in luminance: RGB * max(0, L - T) / L, so the pass is
// continuous at the threshold (no hard edge around bright regions) and keeps the chroma.
// `exposure` multiplies RGB first, as ApplyExposure does (the pipeline passes its exposure
// here instead of rewriting the image). The bright image's alpha is 0.
Image BrightPass(const Image& image, double threshold, double exposure = 1.0);
// The bright pass fused into the first half-resolution step of the dual filter: equal to
// DualFilterDown(BrightPass(image, threshold, exposure)) without the full-size bright image.
// `peaks`, if not null, are the image's segment peaks from MeasureSceneLuminance (exposure.h):
// row segments they prove dark at this threshold and exposure are not bright-passed (their
// zeros are known), and destination pixels that read dark segments alone are zeros; the bytes
// are the same.
Image BrightPassDown(const Image& image, double threshold, double exposure,
                     const float* peaks = nullptr);

// image.rgb += strength * bloom.rgb (alpha untouched); both of one size.
void AddBloom(Image* image, const Image& bloom, double strength);

}  // namespace brdf
