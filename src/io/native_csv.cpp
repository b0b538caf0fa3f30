// Native CSV (DESIGN §4):
//   # brdfkit measurement v1
//   # key: value                      (metadata, any number of lines)
//   theta_i,phi_i,theta_o,phi_o,r,g,b[,sigma_r,sigma_g,sigma_b][,weight]
//   rows, angles in degrees, BRDF in sr^-1
#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/angles.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/text.h"
#include "io/formats.h"

namespace brdf {
namespace {

constexpr std::string_view kMagic = "# brdfkit measurement v1";
constexpr const char* kBaseColumns[] = {"theta_i", "phi_i", "theta_o", "phi_o", "r", "g", "b"};
constexpr const char* kSigmaColumns[] = {"sigma_r", "sigma_g", "sigma_b"};

struct Columns {
  bool sigma = false;
  bool weight = false;
  size_t count() const { return 7 + (sigma ? 3 : 0) + (weight ? 1 : 0); }
};

Columns ParseHeader(const LineReader& reader, std::string_view line) {
  const std::vector<std::string_view> names = SplitFields(line, ",", false);
  std::string expected = "theta_i,phi_i,theta_o,phi_o,r,g,b[,sigma_r,sigma_g,sigma_b][,weight]";
  if (names.size() < 7) reader.Fail("expected the column header " + expected);
  for (size_t k = 0; k < 7; ++k) {
    if (names[k] != kBaseColumns[k]) {
      reader.Fail("expected column " + std::to_string(k + 1) + " to be '" + kBaseColumns[k] +
                  "', found '" + std::string(names[k]) + "' (header " + expected + ")");
    }
  }
  Columns columns;
  size_t next = 7;
  if (names.size() >= 10 && names[7] == kSigmaColumns[0]) {
    for (size_t k = 0; k < 3; ++k) {
      if (names[7 + k] != kSigmaColumns[k]) {
        reader.Fail(std::string("expected column '") + kSigmaColumns[k] + "', found '" +
                    std::string(names[7 + k]) + "'");
      }
    }
    columns.sigma = true;
    next = 10;
  }
  if (next < names.size() && names[next] == "weight") {
    columns.weight = true;
    ++next;
  }
  if (next != names.size()) {
    reader.Fail("unexpected column '" + std::string(names[next]) + "' (header " + expected + ")");
  }
  return columns;
}

double ParseAngle(const LineReader& reader, std::string_view field, const char* what, double lower,
                  double upper) {
  const double degrees = ParseNumber(reader, field, what);
  if (degrees < lower || degrees > upper) {
    std::ostringstream message;
    message << what << " = " << field << " degrees is outside [" << lower << ", " << upper << "]";
    reader.Fail(message.str());
  }
  return DegToRad(degrees);
}

}  // namespace

bool SniffNativeCsv(std::string_view head, int64_t) { return StartsWith(head, kMagic); }

Measurement ReadNativeCsv(const std::string& path, const ReadOptions&) {
  const std::string text = ReadFileBytes(path);
  LineReader reader(path, text);
  std::string_view line;
  if (!reader.Next(&line)) throw ByteError(path, 0, "empty file, expected a measurement");
  if (Trim(line) != kMagic) {
    reader.Fail("expected the first line '" + std::string(kMagic) + "'");
  }

  Measurement measurement;
  measurement.metadata["units"] = "BRDF in sr^-1, angles in degrees";
  // Metadata lines, then the column header.
  Columns columns;
  bool have_header = false;
  while (reader.Next(&line)) {
    const std::string_view trimmed = Trim(line);
    if (trimmed.empty()) continue;
    if (trimmed[0] != '#') {
      columns = ParseHeader(reader, trimmed);
      have_header = true;
      break;
    }
    const std::string_view body = Trim(trimmed.substr(1));
    const size_t colon = body.find(':');
    if (colon == std::string_view::npos || colon == 0) {
      reader.Fail("expected a metadata line '# key: value'");
    }
    const std::string key(Trim(body.substr(0, colon)));
    if (!measurement.metadata.emplace(key, std::string(Trim(body.substr(colon + 1)))).second &&
        key != "units") {
      reader.Fail("metadata key '" + key + "' given twice");
    }
  }
  if (!have_header) reader.Fail("file ends before the column header theta_i,phi_i,...");

  // Bound the reservation by what the file can hold (a row is at least 14 bytes).
  measurement.samples.reserve(text.size() / 14);
  while (reader.Next(&line)) {
    if (Trim(line).empty()) continue;
    const std::vector<std::string_view> fields = SplitFields(line, ",", false);
    if (fields.size() != columns.count()) {
      reader.Fail("expected " + std::to_string(columns.count()) + " columns, found " +
                  std::to_string(fields.size()));
    }
    Sample sample;
    const double theta_i = ParseAngle(reader, fields[0], "theta_i", 0.0, 90.0);
    const double phi_i = ParseAngle(reader, fields[1], "phi_i", -360.0, 360.0);
    const double theta_o = ParseAngle(reader, fields[2], "theta_o", 0.0, 90.0);
    const double phi_o = ParseAngle(reader, fields[3], "phi_o", -360.0, 360.0);
    sample.wi = SphericalDirection(theta_i, phi_i);
    sample.wo = SphericalDirection(theta_o, phi_o);
    for (int c = 0; c < 3; ++c) sample.value[c] = ParseNumber(reader, fields[4 + c], "BRDF value");
    measurement.samples.push_back(sample);
    if (columns.sigma) {
      Rgb sigma;
      for (int c = 0; c < 3; ++c) {
        sigma[c] = ParseNumber(reader, fields[7 + c], kSigmaColumns[c]);
        if (sigma[c] < 0) reader.Fail(std::string(kSigmaColumns[c]) + " must not be negative");
      }
      measurement.sigma.push_back(sigma);
    }
    if (columns.weight) {
      const double weight = ParseNumber(reader, fields.back(), "weight");
      if (weight < 0) reader.Fail("weight must not be negative");
      measurement.weight.push_back(weight);
    }
  }
  if (measurement.samples.empty()) reader.Fail("no data rows after the column header");
  return measurement;
}

WriteReport WriteNativeCsv(const Measurement& measurement, const std::string& path) {
  WriteReport report;
  size_t dropped = 0;
  for (const Sample& sample : measurement.samples) dropped += sample.missing ? 1 : 0;
  if (dropped > 0) {
    report.warnings.push_back(std::to_string(dropped) +
                              " missing samples are not written (the CSV holds measured values)");
  }
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << kMagic << "\n";
    for (const auto& [key, value] : measurement.metadata) {
      if (key == "units") continue;  // restated below
      std::string one_line = value;
      for (char& c : one_line) c = (c == '\n' || c == '\r') ? ' ' : c;
      out << "# " << key << ": " << one_line << "\n";
    }
    if (!measurement.format.empty() && !measurement.metadata.count("converted_from")) {
      out << "# converted_from: " << measurement.format << "\n";
    }
    out << "# units: BRDF in sr^-1, angles in degrees\n";
    out << "theta_i,phi_i,theta_o,phi_o,r,g,b";
    if (measurement.has_sigma()) out << ",sigma_r,sigma_g,sigma_b";
    if (measurement.has_weight()) out << ",weight";
    out << "\n";
    for (size_t k = 0; k < measurement.samples.size(); ++k) {
      const Sample& sample = measurement.samples[k];
      if (sample.missing) continue;
      const DegreesText wi = DirectionDegreesText(sample.wi);
      const DegreesText wo = DirectionDegreesText(sample.wo);
      out << wi.theta << ',' << wi.phi << ',' << wo.theta << ',' << wo.phi;
      for (int c = 0; c < 3; ++c) out << ',' << FormatNumber(sample.value[c]);
      if (measurement.has_sigma()) {
        for (int c = 0; c < 3; ++c) out << ',' << FormatNumber(measurement.sigma[k][c]);
      }
      if (measurement.has_weight()) out << ',' << FormatNumber(measurement.weight[k]);
      out << '\n';
    }
  });
  return report;
}

}  // namespace brdf
