// ASTM E1392 text ("Standard Practice for Angle Resolved Optical Scatter Measurements on
// Specular or Diffuse Surfaces") as written by the Cornell Program of Computer Graphics for its
// gonioreflectometer (DESIGN §4; ../shared/data-real/README.md):
//   LAB_NAME Cornell University, Program of Computer Graphics     header: KEY value
//   ...
//   NUM_POINTS 1439
//   VARS theta_i,phi_i,theta_s,phi_s,400nm,410nm,...,700nm
//   0.872665,0.000000,0.573513,0.000000,0.000874,...             rows: radians, then sr^-1
// Header lines begin with a letter; VARS, which names the columns of the rows, ends the header.
#include <algorithm>
#include <cctype>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/text.h"
#include "io/formats.h"
#include "io/spectral_rows.h"

namespace brdf {
namespace {

constexpr int64_t kMaxAstmBytes = int64_t{1} << 30;
constexpr const char* kAngleVars[] = {"theta_i", "phi_i", "theta_s", "phi_s"};
// The shortest possible row, "0,0,0,0,0,0\n" (four angles and two wavelengths), bounds how many
// rows a file can hold, so that a hostile NUM_POINTS cannot make the reader allocate.
constexpr int64_t kMinRowBytes = 12;

// ASTM header keys and the metadata keys they become (DESIGN §4).
struct HeaderKey {
  const char* astm;
  const char* metadata;
};
constexpr HeaderKey kHeaderKeys[] = {
    {"SAMPLE_NAME", "sample"},     {"SAMPLE_TYPE", "sample_type"}, {"LAB_NAME", "lab"},
    {"SYSTEM_NAME", "instrument"}, {"LAB_OPERATOR", "operator"},   {"LAB_COMMENTS", "comments"},
};

bool IsHeaderLine(std::string_view line) {
  return !line.empty() && std::isalpha(static_cast<unsigned char>(line.front()));
}

// VARS theta_i,phi_i,theta_s,phi_s,400nm,...: the column names and the wavelengths they give.
struct Vars {
  std::vector<std::string> names;
  std::vector<double> wavelengths_nm;
};

Vars ParseVars(const LineReader& reader, std::string_view value) {
  Vars vars;
  for (std::string_view name : SplitFields(value, ",", false)) vars.names.emplace_back(name);
  const size_t angles = std::size(kAngleVars);
  bool angles_first = vars.names.size() > angles;
  for (size_t k = 0; k < angles && angles_first; ++k) angles_first = vars.names[k] == kAngleVars[k];
  if (!angles_first) {
    reader.Fail(
        "VARS must begin with theta_i,phi_i,theta_s,phi_s (radians) and list the "
        "wavelengths after them, found '" +
        std::string(value.substr(0, 60)) + "'");
  }
  for (size_t k = angles; k < vars.names.size(); ++k) {
    std::string_view name = vars.names[k];
    if (name.size() < 3 || name.substr(name.size() - 2) != "nm") {
      reader.Fail("VARS column " + std::to_string(k + 1) + " '" + std::string(name) +
                  "' is not a wavelength such as '400nm'");
    }
    name.remove_suffix(2);
    const double wavelength_nm = ParseNumber(reader, name, "a VARS wavelength (nm)");
    CheckNextWavelength(reader, vars.wavelengths_nm, wavelength_nm);
    vars.wavelengths_nm.push_back(wavelength_nm);
  }
  if (static_cast<int64_t>(vars.wavelengths_nm.size()) < kMinWavelengths) {
    reader.Fail("VARS lists " + std::to_string(vars.wavelengths_nm.size()) +
                " wavelengths, a spectrum needs at least " + std::to_string(kMinWavelengths));
  }
  return vars;
}

}  // namespace

bool SniffAstm(std::string_view head, int64_t) {
  if (StartsWith(head, "LAB_NAME")) return true;
  LineReader lines("", head);
  std::string_view line;
  while (lines.Next(&line)) {
    if (StartsWith(line, "NUM_POINTS") || StartsWith(line, "VARS ")) return true;
  }
  return false;
}

Measurement ReadAstm(const std::string& path, const ReadOptions& options) {
  const std::string text = ReadFileBytes(path, kMaxAstmBytes);
  if (text.empty()) throw ParseError(path, 1, "empty file, expected an ASTM E1392 header");
  LineReader reader(path, text);
  Measurement measurement;
  measurement.format = "astm";
  measurement.source = path;

  int64_t num_points = -1;
  // Where each header key the reader uses was first seen: a second line for one, even an
  // agreeing one, leaves the reader guessing which the writer meant.
  std::map<std::string, int64_t, std::less<>> key_lines;
  std::vector<std::string> column_names;
  std::optional<SpectralRecords> records;  // once VARS has named the columns
  std::vector<double> record;
  int64_t rows = 0;
  std::string_view line;
  while (reader.Next(&line)) {
    if (Trim(line).empty()) continue;
    if (!records) {
      if (!IsHeaderLine(line)) {
        reader.Fail(num_points < 0 ? "data before the NUM_POINTS and VARS header lines"
                                   : "data before the VARS header line");
      }
      const size_t space = line.find_first_of(" \t");
      const std::string_view key = line.substr(0, space);
      const std::string_view value =
          space == std::string_view::npos ? std::string_view() : Trim(line.substr(space));
      const bool used =
          key == "NUM_POINTS" ||
          std::any_of(std::begin(kHeaderKeys), std::end(kHeaderKeys),
                      [&](const HeaderKey& header_key) { return key == header_key.astm; });
      if (used && !key_lines.emplace(std::string(key), reader.line_number()).second) {
        reader.Fail("second " + std::string(key) + " line (first on line " +
                    std::to_string(key_lines.find(key)->second) + ")");
      }
      if (key == "NUM_POINTS") {
        num_points = ParseCount(reader, value, "NUM_POINTS", std::numeric_limits<int64_t>::max());
        if (num_points == 0) reader.Fail("NUM_POINTS is 0: the file holds no data");
        if (num_points > kMaxAstmBytes / kMinRowBytes) {
          reader.Fail("NUM_POINTS " + std::to_string(num_points) + " is more rows than any file " +
                      "brdfkit reads (at most " + std::to_string(kMaxAstmBytes) +
                      " bytes) can hold");
        }
      } else if (key == "VARS") {
        Vars vars = ParseVars(reader, value);
        column_names = std::move(vars.names);
        records.emplace(std::move(vars.wavelengths_nm), options.illuminant);
      }
      for (const HeaderKey& header_key : kHeaderKeys) {
        if (key == header_key.astm) measurement.metadata[header_key.metadata] = std::string(value);
      }
      continue;
    }
    if (num_points < 0) reader.Fail("data before the NUM_POINTS header line");
    if (rows == 0) {
      // A truncated file promises more rows than it holds: reserve no more than fit in it.
      const int64_t room = static_cast<int64_t>(text.size()) / kMinRowBytes;
      measurement.samples.reserve(static_cast<size_t>(std::min(num_points, room)));
    }
    if (rows == num_points) {
      reader.Fail("more data rows than NUM_POINTS " + std::to_string(num_points) + " promises");
    }
    const std::vector<std::string_view> fields = SplitFields(line, ",", false);
    if (fields.size() != column_names.size()) {
      reader.Fail("expected " + std::to_string(column_names.size()) +
                  " comma-separated values (one per VARS column), found " +
                  std::to_string(fields.size()));
    }
    record.resize(fields.size());
    for (size_t k = 0; k < fields.size(); ++k) {
      record[k] = ParseNumber(reader, fields[k], column_names[k].c_str());
    }
    records->Add(path, reader.line_number(), record.data(), &measurement);
    ++rows;
  }
  if (num_points < 0) reader.Fail("no NUM_POINTS header line: not an ASTM E1392 file?");
  if (!records) reader.Fail("no VARS header line: the columns are unknown");
  if (rows != num_points) {
    reader.Fail("expected " + std::to_string(num_points) + " data rows, found " +
                std::to_string(rows) + " (truncated?)");
  }
  records->Describe(&measurement);
  return measurement;
}

}  // namespace brdf
