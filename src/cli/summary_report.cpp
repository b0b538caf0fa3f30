#include "cli/summary_report.h"

#include <iomanip>

#include "core/colour.h"
#include "core/format.h"
#include "io/formats.h"

namespace brdf::cli {
namespace {

nlohmann::json RgbJson(const Rgb& rgb) { return {rgb[0], rgb[1], rgb[2]}; }

}  // namespace

SummaryRow SummarizeFile(const std::string& path) {
  SummaryRow row;
  row.path = path;
  row.format_description = DetectFormat(path).description;
  row.measurement = ReadMeasurement(path);
  row.summary = Summarize(row.measurement);
  return row;
}

nlohmann::json SummaryJson(const SummaryRow& row) {
  const MeasurementSummary& s = row.summary;
  nlohmann::json json;
  json["file"] = row.path;
  json["format"] = s.format;
  json["format_description"] = row.format_description;
  json["sample"] = s.sample_name;
  json["samples"] = s.samples;
  json["theta_i_deg"] = {s.theta_i_deg[0], s.theta_i_deg[1]};
  json["theta_o_deg"] = {s.theta_o_deg[0], s.theta_o_deg[1]};
  json["incidence_directions"] = s.incidence_directions;
  json["min"] = RgbJson(s.min);
  json["max"] = RgbJson(s.max);
  json["missing"] = s.missing;
  json["negative"] = s.negative;
  json["nan"] = s.nan;
  json["has_sigma"] = row.measurement.has_sigma();
  json["has_weight"] = row.measurement.has_weight();
  json["metadata"] = row.measurement.metadata;
  return json;
}

void PrintSummary(std::ostream& out, const SummaryRow& row) {
  const MeasurementSummary& s = row.summary;
  auto line = [&](const char* field, const std::string& value) {
    out << std::left << std::setw(12) << field << value << "\n";
  };
  line("file", row.path);
  line("format", s.format + " (" + row.format_description + ")");
  line("sample", s.sample_name);
  line("samples", std::to_string(s.samples) + (row.measurement.has_sigma() ? ", with sigma" : ""));
  line("theta_i", Format("%.2f .. %.2f deg", s.theta_i_deg[0], s.theta_i_deg[1]) + ", " +
                      std::to_string(s.incidence_directions) + " incidence directions");
  line("theta_o", Format("%.2f .. %.2f deg", s.theta_o_deg[0], s.theta_o_deg[1]));
  const char* channels[] = {"r", "g", "b"};
  for (int c = 0; c < 3; ++c) {
    line(channels[c], Format("%.6g .. %.6g sr^-1", s.min[c], s.max[c]));
  }
  line("missing", std::to_string(s.missing));
  line("negative", std::to_string(s.negative));
  line("nan", std::to_string(s.nan));
  if (!row.measurement.metadata.empty()) out << "metadata\n";
  for (const auto& [key, value] : row.measurement.metadata) {
    out << "  " << key << ": " << value << "\n";
  }
}

void PrintSummaryTable(std::ostream& out, const std::vector<SummaryRow>& rows) {
  out << Format("%-44s %-10s %-26s %8s %13s %13s %5s %10s %8s\n", "file", "format", "sample",
                "samples", "theta_i deg", "theta_o deg", "inc", "max Y", "missing");
  for (const SummaryRow& row : rows) {
    const MeasurementSummary& s = row.summary;
    std::string file = row.path;
    if (file.size() > 44) file = "..." + file.substr(file.size() - 41);
    std::string sample = s.sample_name.substr(0, 26);
    const double max_y = Luminance(s.max);  // of the per-channel maxima
    out << Format("%-44s %-10s %-26s %8zu %6.1f-%-6.1f %6.1f-%-6.1f %5zu %10.4g %8zu\n",
                  file.c_str(), s.format.c_str(), sample.c_str(), s.samples, s.theta_i_deg[0],
                  s.theta_i_deg[1], s.theta_o_deg[0], s.theta_o_deg[1], s.incidence_directions,
                  max_y, s.missing);
  }
}

}  // namespace brdf::cli
