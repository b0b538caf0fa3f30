// The main job (`brdf demo`, DESIGN §3): simulate measurements of three samples with the
// virtual gonioreflectometer, fit every model to them and to the bundled real measurements,
// check the energy of every fit, render previews, and keep everything in one directory with
// a self-contained HTML report.
#pragma once

#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "cli/summary_report.h"
#include "fitters/fit.h"
#include "fitters/select.h"

namespace brdf::cli {

struct DemoOptions {
  std::string out_dir = "brdf-demo";
  std::string data_dir;  // bundled measurements
  bool quick = false;    // smaller simulations and fits (CI)
  bool quiet = false;
};

// The schedule each simulated sample is measured with. The rough gold surface is traced over the
// hemisphere (11,010 geometries at 10 deg steps of theta_i) so that its sheets show the surface,
// not an interpolation of a few in-plane readings.
inline std::string DemoSchedule(std::string_view sample_name, bool quick) {
  if (sample_name == "matte") {
    return quick ? "hemisphere:theta_i_step=15:theta_o_step=10:phi_o_step=15" : "hemisphere";
  }
  if (sample_name == "plastic-sphere") return quick ? "inplane:step=30" : "inplane:step=10";
  return quick ? "hemisphere:theta_i_step=30:theta_o_step=10:phi_o_step=15"
               : "hemisphere:theta_i_step=10";
}

struct DemoImage {
  std::string caption;
  std::string path;  // relative to the output directory
};

// The chosen fit in a renderer's terms (brdf export), with its error against the fit.
struct DemoExport {
  std::string target;    // "mitsuba3", "pbrt-v4", "gltf"
  std::string path;      // relative to the output directory
  std::string material;  // the renderer's material
  bool exact = false;
  double log_rmse = 0, max_relative = 0;
  std::vector<std::string> warnings;  // the export loses the material (export.h)
};

struct DemoDataset {
  std::string name;              // file-name friendly
  std::string title;             // for people
  std::string kind;              // "simulated" or "real"
  std::string source;            // sample spec, or the data file
  std::string truth;             // the simulated truth's model string; empty for real data
  std::string measurement_path;  // relative to the output directory (or the data file)
  size_t samples = 0;
  std::vector<fitters::FitResult> fits;  // every model, in AutoCandidates() order
  std::vector<std::string> fit_paths;    // their reports, relative to the output directory
  fitters::Selection selection;
  size_t chosen = 0;        // index into fits
  double truth_error = -1;  // max relative parameter error of the truth's model
  std::vector<DemoImage> images;
  std::vector<DemoExport> exports;  // the chosen fit, one per export target
  std::string view_path;            // brdf view of the data and the chosen fit
  double seconds = 0;
};

struct DemoResult {
  std::vector<SummaryRow> bundled;  // every bundled real measurement, summarized
  std::vector<DemoDataset> datasets;
  std::vector<std::string> notes;
  double seconds = 0;
};

DemoResult RunDemo(const DemoOptions& options);
void PrintDemoSummary(std::ostream& out, const DemoResult& result);
// Writes summary.json in the output directory: the bundled files' summaries and, per dataset,
// the chosen model, its metrics and energy check, and every fit report's path.
void WriteDemoSummaryJson(const DemoResult& result, const DemoOptions& options);
// Writes report.html in the output directory (images beside it, referenced relatively).
void WriteDemoReport(const DemoResult& result, const DemoOptions& options);

}  // namespace brdf::cli
