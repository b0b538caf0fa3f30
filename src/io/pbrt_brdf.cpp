// pbrt-v2 measured `.brdf` text (DESIGN §4; pbrt-v2 scenes/brdfs/, read there by
// ReadFloatFile and the "measured" material): `#` starts a comment that runs to the end of the
// line; the rest is whitespace-separated numbers:
//   # Cornell University, Program of Computer Graphics      header comments (optional)
//   # Cayman Metallic
//   # num wls
//   31                                                      number of wavelengths
//   400 410 ... 700                                         the wavelengths (nm)
//   0.872665 0.000000 0.573513 0.000000 0.000874 ...        records: 4 angles (radians), then
//                                                           one BRDF value (sr^-1) per wavelength
// pbrt itself ignores line breaks. Here every record must start on a new line (the Cornell
// files hold one record per line; it may continue onto following lines): otherwise a line
// missing one value would silently shift every later record.
#include <optional>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/text.h"
#include "io/formats.h"
#include "io/spectral_rows.h"

namespace brdf {
namespace {

constexpr int64_t kMaxPbrtBytes = int64_t{1} << 30;
// No instrument samples a spectrum this finely; a larger count is a broken file.
constexpr int64_t kMaxWavelengths = 1000;
constexpr std::string_view kWavelengthCountComment = "num wls";

const char* RecordFieldName(size_t index) {
  constexpr const char* kAngleNames[] = {"theta_i", "phi_i", "theta_s", "phi_s"};
  return index < std::size(kAngleNames) ? kAngleNames[index] : "a spectral BRDF value";
}

std::string FileName(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace

bool SniffPbrtBrdf(std::string_view head, int64_t) {
  LineReader lines("", head);
  std::string_view line;
  while (lines.Next(&line)) {
    if (StartsWith(line, "#") && Trim(line.substr(1)) == kWavelengthCountComment) return true;
  }
  return false;
}

Measurement ReadPbrtBrdf(const std::string& path, const ReadOptions& options) {
  const std::string text = ReadFileBytes(path, kMaxPbrtBytes);
  if (text.empty()) throw ParseError(path, 1, "empty file, expected '# num wls' and a count");
  LineReader reader(path, text);
  Measurement measurement;
  measurement.format = "pbrt-brdf";
  measurement.source = path;

  // The comment lines before "# num wls" describe the sample (see the Cornell files).
  std::vector<std::string> header_comments;
  bool in_header = true;
  int64_t wavelength_count = -1;
  int64_t count_comment_line = 0;  // where "# num wls" is; 0 until seen
  std::vector<double> wavelengths_nm;
  std::optional<SpectralRecords> records;  // once the wavelengths are known
  std::vector<double> record;
  int64_t record_line = 0;           // where the current record starts
  size_t record_values_on_line = 0;  // how many of its values are on that line
  std::string_view line;
  while (reader.Next(&line)) {
    const size_t hash = line.find('#');
    if (hash != std::string_view::npos) {
      const std::string_view comment = Trim(line.substr(hash + 1));
      if (comment == kWavelengthCountComment) {
        // A second count line would leave the reader guessing which count the writer meant.
        if (count_comment_line != 0) {
          reader.Fail("second '# num wls' line (first on line " +
                      std::to_string(count_comment_line) + ")");
        }
        count_comment_line = reader.line_number();
        in_header = false;
      }
      if (in_header && !comment.empty()) header_comments.emplace_back(comment);
      line = line.substr(0, hash);
    }
    const std::vector<std::string_view> fields = SplitFields(line, " \t\f\v", true);
    if (!fields.empty()) in_header = false;
    for (size_t f = 0; f < fields.size(); ++f) {
      if (wavelength_count < 0) {
        wavelength_count =
            ParseCount(reader, fields[f], "the number of wavelengths", kMaxWavelengths);
        if (wavelength_count < kMinWavelengths) {
          reader.Fail("the number of wavelengths is " + std::to_string(wavelength_count) +
                      ", a spectrum needs at least " + std::to_string(kMinWavelengths));
        }
      } else if (!records) {
        const double wavelength_nm = ParseNumber(reader, fields[f], "a wavelength (nm)");
        CheckNextWavelength(reader, wavelengths_nm, wavelength_nm);
        wavelengths_nm.push_back(wavelength_nm);
        if (static_cast<int64_t>(wavelengths_nm.size()) == wavelength_count) {
          records.emplace(wavelengths_nm, options.illuminant);
        }
      } else {
        if (record.empty()) {
          record_line = reader.line_number();
          record_values_on_line = fields.size() - f;
        }
        record.push_back(ParseNumber(reader, fields[f], RecordFieldName(record.size())));
        if (record.size() < records->record_size()) continue;
        if (f + 1 < fields.size()) {  // the record ends mid-line
          const std::string record_shape = std::to_string(records->record_size()) +
                                           " values (4 angles + " +
                                           std::to_string(wavelength_count) + " spectral)";
          if (record_line == reader.line_number()) {
            reader.Fail("line holds " + std::to_string(fields.size()) + " values, a record holds " +
                        record_shape);
          }
          throw ParseError(path, record_line,
                           "the record starting here has " + std::to_string(record_values_on_line) +
                               " values on this line and ends in the middle of line " +
                               std::to_string(reader.line_number()) + ": a record holds " +
                               record_shape + " and starts on a new line");
        }
        records->Add(path, record_line, record.data(), &measurement);
        record.clear();
      }
    }
  }
  if (wavelength_count < 0) reader.Fail("no data: expected the number of wavelengths");
  if (!records) {
    reader.Fail("file ends after " + std::to_string(wavelengths_nm.size()) + " of " +
                std::to_string(wavelength_count) + " wavelengths (truncated?)");
  }
  if (!record.empty()) {
    reader.Fail("file ends inside the record that starts on line " + std::to_string(record_line) +
                ": " + std::to_string(record.size()) + " of " +
                std::to_string(records->record_size()) + " values (truncated?)");
  }
  if (measurement.samples.empty()) reader.Fail("no records after the wavelengths");

  // "# Cornell University, ...", "# Cayman Metallic", "# High-gloss Paint": the second line
  // names the sample. It may go on to describe it ("Krylon spray enamel 7205, "True Blue";
  // overcoat Plasti-kote 33 Glass Frosting Spray"): the name is its first clause, and the whole
  // line stays in "comments". Files without such a header (acryl_blue.brdf) are named by the
  // file, without its extension.
  if (header_comments.size() >= 2) {
    const std::string& line = header_comments[1];
    measurement.metadata["sample"] =
        std::string(Trim(std::string_view(line).substr(0, line.find(';'))));
  } else {
    const std::string file = FileName(path);
    measurement.metadata["sample"] = file.substr(0, file.find_last_of('.'));
  }
  if (!header_comments.empty()) {
    std::string comments;
    for (const std::string& comment : header_comments) {
      comments += (comments.empty() ? "" : "; ") + comment;
    }
    measurement.metadata["comments"] = comments;
  }
  records->Describe(&measurement);
  return measurement;
}

}  // namespace brdf
