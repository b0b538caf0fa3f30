// The page of `brdf view` (DESIGN §3): one self-contained HTML file that shows measurements and
// models side by side, interactively, opened from disk with no network request. The data are
// evaluated here; the page draws them (src/render/view/view.html, with three.js for the 3D lobe
// vendored into it at build time, its licence kept beside it in the page).
#pragma once

#include <string>
#include <vector>

namespace brdf {

// How finely each source is tabulated into the page.
struct ViewGrid {
  // Plane of incidence: incidence angles 0, step, ... up to max; outgoing angles every
  // outgoing_step_deg over (-90, 90), positive on the specular side.
  double incidence_step_deg = 5;
  double incidence_max_deg = 80;
  double outgoing_step_deg = 1;
  // The half/difference table the lobe, the (theta_h, theta_d) slice and the lit sphere are
  // drawn from: cell centres, theta_h spaced as the square of a uniform variable (MERL's rule:
  // finer near the peak), theta_d and phi_d (folded into [0, 180) deg by reciprocity) uniform.
  int theta_h_cells = 48;
  int theta_d_cells = 24;
  int phi_d_cells = 24;
  // Albedo curve: incidence angles over [0, 89] deg.
  int albedo_steps = 30;
};

// The page for `sources` (model strings, fit reports or measurement files, in order: the
// first is drawn first). Throws UsageError / InputError naming the source that cannot be read.
std::string ViewPageHtml(const std::vector<std::string>& sources, const ViewGrid& grid = {});

// ViewPageHtml written atomically to `path`.
void WriteViewPage(const std::vector<std::string>& sources, const std::string& path,
                   const ViewGrid& grid = {});

}  // namespace brdf
