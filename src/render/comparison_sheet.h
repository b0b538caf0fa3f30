// Side-by-side comparison of two previews rendered under identical light (DESIGN §8: "measured
// vs fitted spheres with a false-colour error map"): A, B, the relative luminance error
// |Y_A - Y_B| / max(Y_B, 1% of B's brightest) in false colour, and a labelled colour bar.
#pragma once

#include <string>

#include "hdr/image.h"
#include "hdr/image_files.h"
#include "hdr/pipeline.h"

namespace brdf {

struct ComparisonSheet {
  Image8 sheet;
  double max_relative_error = 0.0;  // over pixels on both spheres
  double p99_relative_error = 0.0;  // its 99th percentile
  double mean_relative_error = 0.0;
  double colour_bar_top = 0.0;  // the error shown as the top of the colour bar
  std::string Summary() const;
};

// `display_a`, `display_b`: the two previews after the HDR pipeline (same size);
// `radiance_a`, `radiance_b`: their radiance (alpha 0 off the sphere). The error map uses the
// viridis colour map (perceptually uniform, readable in grey) from 0 to a round number at or
// above the 99th percentile of the error (larger errors saturate).
ComparisonSheet MakeComparisonSheet(const Image8& display_a, const Image8& display_b,
                                    const Image& radiance_a, const Image& radiance_b,
                                    const std::string& label_a, const std::string& label_b);

// Two radiance images (same size) through one run of the tone pipeline side by side, so both
// are mapped identically, then the sheet. `toned` (may be null) receives the pipeline's result.
ComparisonSheet ToneMapAndCompare(const Image& radiance_a, const Image& radiance_b,
                                  const ToneOptions& tone, const std::string& label_a,
                                  const std::string& label_b, ToneResult* toned = nullptr);

}  // namespace brdf
