// The measurement summary shown by `brdf info` and `brdf demo`, as text and as JSON.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "core/measurement.h"

namespace brdf::cli {

struct SummaryRow {
  std::string path;
  std::string format_description;
  Measurement measurement;  // samples may be cleared once summarized
  MeasurementSummary summary;
};

SummaryRow SummarizeFile(const std::string& path);

// JSON with at least format, samples, theta_i_deg, theta_o_deg, min, max, missing.
nlohmann::json SummaryJson(const SummaryRow& row);
// The `brdf info` block: one "field  value" line each, then the metadata.
void PrintSummary(std::ostream& out, const SummaryRow& row);
// One line per file, aligned columns (`brdf demo`).
void PrintSummaryTable(std::ostream& out, const std::vector<SummaryRow>& rows);

}  // namespace brdf::cli
