// Bloom (DESIGN §8): light scattered in the eye or the lens spreads around bright sources.
// Bright pass -> blur (blur.h) -> added back with a strength.
#pragma once

#include "hdr/image.h"

namespace brdf {

// Keeps what lies above `threshold` in luminance: RGB * max(0, L - T) / L, so the pass is
// continuous at the threshold (no hard edge around bright regions) and keeps the chroma.
Image BrightPass(const Image& image, double threshold);

// image.rgb += strength * bloom.rgb (alpha untouched); both of one size.
void AddBloom(Image* image, const Image& bloom, double strength);

}  // namespace brdf
