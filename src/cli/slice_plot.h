// The plane-of-incidence slice chart (`brdf fit --plot`, the demo report's DATASET-slices.png):
// the figure of Ngan et al. 2005 and BRDF Explorer. One panel per incidence angle; in each,
// the measured samples that lie in the plane of incidence (± one sigma) and every given
// model's curve, against the signed detector angle (positive on the mirror side), on a log
// scale of luminance Y of f (DESIGN §1). Drawn in C++ (OpenCV) like the albedo chart, so that
// `brdf` needs no Python at run time.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/measurement.h"
#include "core/vec.h"

namespace brdf::cli {

// A curve to draw: a label for the legend and f(wi, wo) in sr^-1.
struct SliceCurve {
  std::string label;
  std::function<Rgb(const Vec3& wi, const Vec3& wo)> brdf;
};

struct SlicePoint {
  double theta_o_deg = 0;  // signed: > 0 on the mirror side of the normal, < 0 toward the light
  double luminance = 0;    // Y of f, sr^-1
  double sigma = 0;        // Y-weighted one sigma (0 when the file has none)
};

struct SlicePanel {
  double theta_i_deg = 0;     // the panel's incidence (the mean of its samples' theta_i)
  double half_width_deg = 0;  // 0 for one exact incidence; the bin's half width otherwise
  std::vector<SlicePoint> points;
};

// Samples whose azimuth lies within this angle of the plane of incidence (phi_o - phi_i near 0
// or 180 deg) count as in-plane; a detector at the normal always does.
inline constexpr double kInPlaneToleranceDeg = 1.5;
// Incidences arrive as a schedule's few exact angles, or (image-based data) one per sample;
// beyond this many distinct angles they are binned.
inline constexpr int kMaxExactIncidences = 64;
inline constexpr double kIncidenceBinDeg = 2.0;

// The in-plane samples of up to `max_panels` incidences, evenly spread over those with at
// least three in-plane samples, in increasing theta_i.
std::vector<SlicePanel> ExtractSlices(const Measurement& measurement, int max_panels = 6);

// Draws the panels with `curves` (each evaluated at the panel's incidence, azimuth 0, over
// theta_o from -89 to 89 deg) and writes a PNG atomically. Throws InputError when the
// measurement has no in-plane samples to draw, OutputError when the file cannot be written.
void WriteSlicePlot(const Measurement& measurement, const std::vector<SliceCurve>& curves,
                    const std::string& title, const std::string& path);

}  // namespace brdf::cli
