// report.html of `brdf demo`: one page a person can read in a browser, with the images beside
// it (relative links) and every number the summary table prints.
#include <sstream>

#include "cli/demo.h"
#include "core/atomic_file.h"
#include "core/format.h"
#include "fitters/report.h"

namespace brdf::cli {
namespace {

std::string Escape(const std::string& text) {
  std::string escaped;
  for (char c : text) {
    switch (c) {
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '&':
        escaped += "&amp;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      default:
        escaped += c;
    }
  }
  return escaped;
}

// The verdict in a word, marked unless conserving, with its reason on hover and below the table.
std::string EnergyCell(const EnergyVerdict& verdict) {
  const std::string name = Escape(verdict.name());
  const std::string word =
      verdict.conservation == Conservation::kConserving ? name : "<b>" + name + "</b>";
  return "<span title=\"" + Escape(verdict.reason) + "\">" + word + "</span>";
}

std::string Triple(const Rgb& rgb) { return Format("%.3f, %.3f, %.3f", rgb[0], rgb[1], rgb[2]); }

void WriteBundledTable(std::ostream& out, const DemoResult& result) {
  out << "<h2>Bundled real measurements</h2>\n<table>\n<tr><th>file</th><th>format</th>"
         "<th>sample</th><th>samples</th><th>&theta;<sub>i</sub> (deg)</th>"
         "<th>&theta;<sub>o</sub> (deg)</th><th>incidences</th><th>missing</th>"
         "<th>negative</th></tr>\n";
  for (const SummaryRow& row : result.bundled) {
    const MeasurementSummary& s = row.summary;
    out << "<tr><td>" << Escape(row.path) << "</td><td>" << Escape(s.format) << "</td><td>"
        << Escape(s.sample_name) << "</td><td>" << s.samples << "</td><td>"
        << Format("%.1f", s.theta_i_deg[0]) << "&ndash;" << Format("%.1f", s.theta_i_deg[1])
        << "</td><td>" << Format("%.1f", s.theta_o_deg[0]) << "&ndash;"
        << Format("%.1f", s.theta_o_deg[1]) << "</td><td>" << s.incidence_directions << "</td><td>"
        << s.missing << "</td><td>" << s.negative << "</td></tr>\n";
  }
  out << "</table>\n";
}

void WriteDataset(std::ostream& out, const DemoDataset& dataset) {
  out << "<h3 id=\"" << Escape(dataset.name) << "\">" << Escape(dataset.title) << "</h3>\n<p>"
      << Escape(dataset.kind) << " &middot; " << Escape(dataset.source) << " &middot; "
      << dataset.samples << " samples";
  if (dataset.kind == "simulated") {
    out << " &middot; measurement <a href=\"" << Escape(dataset.measurement_path) << "\">"
        << Escape(dataset.measurement_path) << "</a>";
  }
  if (!dataset.truth.empty()) {
    out << "<br>truth: <code>" << Escape(dataset.truth) << "</code>; its model fitted back "
        << "within " << Format("%.2g", 100 * dataset.truth_error) << " % (largest parameter)";
  }
  if (!dataset.view_path.empty()) {
    out << "<br><a href=\"" << Escape(dataset.view_path)
        << "\">interactive view</a> of the data and the chosen fit (<code>brdf view</code>)";
  }
  out << "<br>selection: " << Escape(dataset.selection.reason) << "</p>\n";
  out << "<table>\n<tr><th>model</th><th>BIC</th><th>rmse (sr<sup>-1</sup>)</th>"
         "<th>log rmse</th><th>parameters</th><th>max albedo (integrated)</th><th>energy</th>"
         "<th>converged</th><th>report</th></tr>\n";
  for (size_t k = 0; k < dataset.fits.size(); ++k) {
    const fitters::FitResult& fit = dataset.fits[k];
    const bool chosen = k == dataset.chosen;
    out << "<tr" << (chosen ? " class=\"chosen\"" : "") << "><td>" << Escape(fit.model.name())
        << (chosen ? " &#9733;" : "") << "</td><td>" << Format("%.6g", fit.bic) << "</td><td>"
        << Format("%.4g", fit.metrics.rmse) << "</td><td>" << Format("%.4g", fit.metrics.log_rmse)
        << "</td><td><code>" << Escape(fit.model.ToString(4)) << "</code></td><td>"
        << Triple(fit.energy.max_albedo) << "</td><td>" << EnergyCell(fit.energy.verdict)
        << "</td><td>" << (fit.converged ? "yes" : "<b>no</b>") << "</td><td><a href=\""
        << Escape(dataset.fit_paths[k]) << "\">json</a></td></tr>\n";
  }
  out << "</table>\n";
  if (!dataset.exports.empty()) {
    out << "<p>the " << Escape(dataset.fits[dataset.chosen].model.name())
        << " fit for renderers (<code>brdf export</code>; error of the renderer's model against "
           "the fit on its samples):";
    for (const DemoExport& exported : dataset.exports) {
      out << "<br><a href=\"" << Escape(exported.path) << "\">" << Escape(exported.target)
          << "</a>: " << Escape(exported.material) << ", "
          << (exported.exact ? "exact" : "approximate") << ", log rmse "
          << Format("%.4g", exported.log_rmse) << ", max relative error "
          << Format("%.4g", exported.max_relative);
      for (const std::string& warning : exported.warnings) {
        out << " <span class=\"warning\">&#9888; " << Escape(warning) << "</span>";
      }
    }
    out << "</p>\n";
  }
  const EnergyVerdict& verdict = dataset.fits[dataset.chosen].energy.verdict;
  out << "<p" << (verdict.conservation == Conservation::kConserving ? "" : " class=\"warning\"")
      << ">energy of the " << Escape(dataset.fits[dataset.chosen].model.name())
      << " fit: " << Escape(verdict.Text()) << "</p>\n";
  for (const std::string& warning : dataset.fits[dataset.chosen].warnings) {
    out << "<p class=\"warning\">" << Escape(warning) << "</p>\n";
  }
  out << "<div class=\"images\">\n";
  for (const DemoImage& image : dataset.images) {
    // Each picture links to itself at full size (the slice charts hold several panels).
    out << "<figure><a href=\"" << Escape(image.path) << "\"><img src=\"" << Escape(image.path)
        << "\" alt=\"" << Escape(image.caption) << "\"></a><figcaption>" << Escape(image.caption)
        << " (click for full size)</figcaption></figure>\n";
  }
  out << "</div>\n";
}

}  // namespace

void WriteDemoReport(const DemoResult& result, const DemoOptions& options) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
          "<title>brdfkit demo report</title>\n<style>\n"
          "body{font-family:sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;"
          "color:#222}\ntable{border-collapse:collapse;margin:0.5em 0;font-size:0.9em}\n"
          "td,th{border:1px solid #ccc;padding:0.25em 0.5em;text-align:left}\n"
          "tr.chosen{background:#eef6ee}\ncode{font-size:0.85em}\n"
          ".warning{color:#a40}\n.images{display:flex;flex-wrap:wrap;gap:1em}\n"
          "figure{margin:0}\nfigure img{max-width:100%}\nfigcaption{font-size:0.85em}\n"
          "</style></head><body>\n<h1>brdfkit demo report</h1>\n";
  html << "<p>Simulated measurements from the virtual gonioreflectometer and the bundled real "
          "measurements, each fitted with every model (Ceres; energy conservation built into "
          "the fit), the simplest model the data support chosen by BIC, and every fit's "
          "directional albedo integrated over 90 incidence angles. Run time "
       << Format("%.1f", result.seconds) << " s" << (options.quick ? " (--quick)" : "")
       << ".</p>\n";
  for (const std::string& note : result.notes) html << "<p>" << Escape(note) << "</p>\n";
  html << "<h2>Fits</h2>\n";
  for (const DemoDataset& dataset : result.datasets) WriteDataset(html, dataset);
  WriteBundledTable(html, result);
  html << "</body></html>\n";
  WriteFileAtomically(options.out_dir + "/report.html",
                      [&](std::ostream& out) { out << html.str(); });
}

}  // namespace brdf::cli
