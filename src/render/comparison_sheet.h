// Side-by-side comparison of two previews rendered under identical light (DESIGN §8: "measured
// vs fitted spheres with a false-colour error map"; sheets share one exposure and compare
// colour): A, B, the colour error in false colour, and a labelled colour bar.
//
// The colour error of a pixel is the largest over red, green and blue of the relative error
// |A_c - B_c| / max(B_c, floor): a hue shift (a blue fitted as cyan) shows in the channel that
// moved even where the luminance barely does. floor = 5 % of B's reference level, the 90th
// percentile of B's luminance over its sphere: a sharp highlight, covering a few pixels, sets
// neither the floor nor, through it, the scale of every other pixel's error. The statistics
// (median, 90th and 99th percentiles, max, mean) run over the lit sphere: pixels on both
// spheres where A or B is brighter than 1 % of the reference level (not the black back of a
// sphere under a directional light, which would count as a perfect match).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

#include "core/vec.h"
#include "hdr/image.h"
#include "hdr/image_files.h"
#include "hdr/pipeline.h"

namespace brdf {

struct ComparisonSheet {
  Image8 sheet;  // empty from CompareRadiance
  // The colour error (see above) over the lit sphere.
  double median_relative_error = 0.0;
  double p90_relative_error = 0.0;
  double p99_relative_error = 0.0;
  double max_relative_error = 0.0;
  double mean_relative_error = 0.0;
  int64_t lit_pixels = 0;
  double reference_luminance = 0.0;  // B's 90th-percentile luminance, W/(m^2 sr)
  double colour_bar_top = 0.0;       // the error shown as the top of the colour bar
  std::string Summary() const;
};

// The colour error of one pixel: max over c of |a_c - b_c| / max(b_c, floor) (0 where both are
// 0; 1 where b and the floor are 0 and a is not).
double ColourRelativeError(const Rgb& a, const Rgb& b, double floor);

// The statistics alone, of two radiance images of the same size (alpha 0 off the sphere);
// `error_map` (may be null; CV_32F of the images' size) receives each lit pixel's error.
ComparisonSheet CompareRadiance(const Image& radiance_a, const Image& radiance_b,
                                cv::Mat* error_map = nullptr);

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
