// In-plane spectral gonio table (DESIGN §4), the layout of the 2D measurement that the brdf
// viewer of ansys/optical-automation turns into a Speos BRDF (tests/workflows/example_models/
// test_brdf_viewer_2D_data.csv there):
//    Incident_angle,Measure_angle, 390nm , 400nm , ... , 730nm       header (spaces allowed)
//   10,-78,0.7165,0.7181,...                                          one row per geometry
// Angles in degrees in the plane of incidence; then one value per wavelength. The file states
// neither units nor sign convention, so this reader assumes, and says so in the metadata:
// - the light lies at azimuth 0 (wi = (sin theta_i, 0, cos theta_i)); the detector at
//   |Measure_angle| from the normal, on the far side of it (azimuth 180 deg: the specular side)
//   when the angle is positive and on the light's side (azimuth 0) when it is negative. The
//   shared file's specular peaks sit at Measure_angle = +Incident_angle, which is what this
//   convention predicts.
// - values are the BRDF in sr^-1, as the viewer that reads the file takes them;
// - a row whose every band reads exactly 0 is no reading (missing): the shared file has such
//   runs around Measure_angle = -Incident_angle, where the detector stands in the beam.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/errors.h"
#include "core/text.h"
#include "io/formats.h"
#include "io/spectral_rows.h"

namespace brdf {
namespace {

constexpr int64_t kMaxGonioCsvBytes = int64_t{1} << 30;
constexpr std::string_view kIncidentColumn = "Incident_angle";
constexpr std::string_view kMeasureColumn = "Measure_angle";
constexpr size_t kAngleColumns = 2;

// The header line without a UTF-8 byte-order mark, split into trimmed names.
std::vector<std::string_view> HeaderNames(std::string_view line) {
  if (StartsWith(line, "\xEF\xBB\xBF")) line.remove_prefix(3);
  std::vector<std::string_view> names = SplitFields(line, ",", false);
  for (std::string_view& name : names) name = Trim(name);
  return names;
}

// The wavelengths of the header's columns after the two angles ("390nm", " 400nm ", ...).
std::vector<double> ParseWavelengths(const LineReader& reader,
                                     const std::vector<std::string_view>& names) {
  if (names.size() < kAngleColumns || names[0] != kIncidentColumn || names[1] != kMeasureColumn) {
    reader.Fail(
        "expected the header to begin 'Incident_angle,Measure_angle' and list "
        "wavelengths such as '390nm' after them");
  }
  std::vector<double> wavelengths_nm;
  for (size_t k = kAngleColumns; k < names.size(); ++k) {
    std::string_view name = names[k];
    if (name.size() < 3 || name.substr(name.size() - 2) != "nm") {
      reader.Fail("column " + std::to_string(k + 1) + " '" + PrintableText(name.substr(0, 40)) +
                  "' is not a wavelength such as '390nm'");
    }
    name.remove_suffix(2);
    const double wavelength_nm = ParseNumber(reader, Trim(name), "a column wavelength (nm)");
    CheckNextWavelength(reader, wavelengths_nm, wavelength_nm);
    wavelengths_nm.push_back(wavelength_nm);
  }
  if (static_cast<int64_t>(wavelengths_nm.size()) < kMinWavelengths) {
    reader.Fail("the header lists " + std::to_string(wavelengths_nm.size()) +
                " wavelengths, a spectrum needs at least " + std::to_string(kMinWavelengths));
  }
  return wavelengths_nm;
}

}  // namespace

bool SniffGonioCsv(std::string_view head, int64_t) {
  LineReader lines("", head);
  std::string_view line;
  while (lines.Next(&line)) {
    if (Trim(line).empty()) continue;
    const std::vector<std::string_view> names = HeaderNames(line);
    return names.size() > kAngleColumns && names[0] == kIncidentColumn &&
           names[1] == kMeasureColumn;
  }
  return false;
}

Measurement ReadGonioCsv(const std::string& path, const ReadOptions& options) {
  const std::string text = ReadFileBytes(path, kMaxGonioCsvBytes);
  LineReader reader(path, text);
  Measurement measurement;
  std::vector<double> wavelengths_nm;
  std::string_view line;
  while (wavelengths_nm.empty() && reader.Next(&line)) {
    if (!Trim(line).empty()) wavelengths_nm = ParseWavelengths(reader, HeaderNames(line));
  }
  if (wavelengths_nm.empty()) {
    throw ParseError(path, 1, "empty file, expected the header 'Incident_angle,Measure_angle,...'");
  }
  const size_t columns = kAngleColumns + wavelengths_nm.size();
  SpectralRecords records(wavelengths_nm, options.illuminant);
  // At most one sample per line left in the file.
  measurement.samples.reserve(static_cast<size_t>(std::count(text.begin(), text.end(), '\n')));
  std::vector<double> record(records.record_size());
  std::vector<double> incidences_deg;
  int64_t blank_rows = 0;
  while (reader.Next(&line)) {
    if (Trim(line).empty()) continue;
    const std::vector<std::string_view> fields = SplitFields(line, ",", false);
    if (fields.size() != columns) {
      reader.Fail("expected " + std::to_string(columns) +
                  " comma-separated values (two angles and one per wavelength), found " +
                  std::to_string(fields.size()));
    }
    const double incident_deg = ParseNumber(reader, Trim(fields[0]), "Incident_angle (degrees)");
    const double measure_deg = ParseNumber(reader, Trim(fields[1]), "Measure_angle (degrees)");
    if (incident_deg < 0 || incident_deg >= 90) {
      reader.Fail("Incident_angle " + FormatNumber(incident_deg) +
                  " deg is outside [0, 90): not a direction above the surface");
    }
    if (std::abs(measure_deg) > 90) {
      reader.Fail("Measure_angle " + FormatNumber(measure_deg) +
                  " deg is outside [-90, 90]: not a direction above the surface");
    }
    bool all_zero = true;
    for (size_t k = 0; k < wavelengths_nm.size(); ++k) {
      const double value = ParseNumber(reader, Trim(fields[kAngleColumns + k]), "a BRDF value");
      record[SpectralRecords::kFirstSpectral + k] = value;
      all_zero = all_zero && value == 0;
    }
    record[SpectralRecords::kThetaI] = DegToRad(incident_deg);
    record[SpectralRecords::kPhiI] = 0;
    record[SpectralRecords::kThetaS] = DegToRad(std::abs(measure_deg));
    record[SpectralRecords::kPhiS] = measure_deg > 0 ? kPi : 0;
    records.Add(path, reader.line_number(), record.data(), &measurement);
    if (all_zero) {
      measurement.samples.back().missing = true;
      ++blank_rows;
    }
    if (std::find(incidences_deg.begin(), incidences_deg.end(), incident_deg) ==
        incidences_deg.end()) {
      incidences_deg.push_back(incident_deg);
    }
  }
  if (measurement.samples.empty()) reader.Fail("no data rows after the header");
  records.Describe(&measurement);
  auto& metadata = measurement.metadata;
  metadata["geometry"] =
      "in-plane, angles in degrees: wi at azimuth 0, theta_i = Incident_angle; wo at theta_o = "
      "|Measure_angle|, azimuth 180 deg (the specular side) when Measure_angle > 0 and azimuth 0 "
      "(the light's side) when < 0 (ASSUMED: the file states no convention)";
  metadata["units"] =
      "ASSUMED BRDF in sr^-1 per wavelength: the file names no unit (the brdf viewer of "
      "ansys/optical-automation reads the columns as BRDF)";
  metadata["isotropy"] = "ASSUMED isotropic: one plane of incidence measured";
  std::string incidences;
  for (double incidence_deg : incidences_deg) {
    incidences += (incidences.empty() ? "" : ", ") + FormatNumber(incidence_deg, 6);
  }
  metadata["incidences_deg"] = incidences;
  metadata["missing"] =
      std::to_string(blank_rows) +
      " rows read 0 in every band and are flagged missing (no reading: the detector "
      "shadows the beam near the retro-reflection direction)";
  return measurement;
}

}  // namespace brdf
