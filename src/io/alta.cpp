// ALTA data text (the format of the ALTA library, belcour/alta, "data" files; its params.h
// names the parameterizations): `#` header lines, then one whitespace-separated row per sample.
//   #DIM 3 1                                   input and output dimensions
//   #VS 0                                      confidence columns per output (0: none)
//   #PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI        how the inputs locate the directions
//   #PARAM_OUT INV_STERADIAN_COSINE_FACTOR     what the outputs are
//   #SAMPLE "3M Yellow"                        any other `#` line: a comment (kept as metadata)
//   0.2618  -1.5469  -0.2728  0.000452         theta_l, theta_v cos(dphi), theta_v sin(dphi), value
// Read here: input ISOTROPIC_TL_TV_PROJ_DPHI (ALTA's "3D parametrization where the phi
// component is projected", angles in radians), light at azimuth 0 and view at azimuth dphi:
//   wi = (sin theta_l, 0, cos theta_l),  theta_v = |(x, y)|,  dphi = atan2(y, x),
//   wo = (sin theta_v cos dphi, sin theta_v sin dphi, cos theta_v)
// (in the CEA files the retro-reflection peak sits at dphi = 0, theta_v = theta_l: wo = wi).
// Outputs INV_STERADIAN (f, sr^-1) and INV_STERADIAN_COSINE_FACTOR (f cos(theta_v): divided by
// cos(theta_v) here); one output (grey, copied to r, g, b) or three (r, g, b). Without a
// #PARAM_OUT line the values are taken as they are (f), as ALTA does, and the metadata says so
// (retro-gray-tape.dat has none). Anything else is refused with the line that names it.
#include <cmath>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/errors.h"
#include "core/text.h"
#include "io/formats.h"

namespace brdf {
namespace {

constexpr int64_t kMaxAltaBytes = int64_t{1} << 30;
constexpr std::string_view kProjectedInput = "ISOTROPIC_TL_TV_PROJ_DPHI";
// Rows whose view direction is this close to the horizon have no f: the file's f cos(theta_v)
// is divided by a cosine that is zero up to round-off.
constexpr double kHorizonCos = 1e-6;
// Angles may exceed their range by round-off in the files' 32-digit decimals.
constexpr double kAngleSlack = 1e-9;

std::string KeywordValue(std::string_view line, std::string_view keyword) {
  return std::string(Trim(line.substr(keyword.size())));
}

}  // namespace

bool SniffAlta(std::string_view head, int64_t) {
  LineReader lines("", head);
  std::string_view line;
  bool dim = false, param_in = false;
  while (lines.Next(&line)) {
    line = Trim(line);
    if (line.empty()) continue;
    if (line.front() != '#') break;  // the header is over
    dim = dim || StartsWith(line, "#DIM ");
    param_in = param_in || StartsWith(line, "#PARAM_IN ");
  }
  return dim && param_in;
}

Measurement ReadAlta(const std::string& path, const ReadOptions&) {
  const std::string text = ReadFileBytes(path, kMaxAltaBytes);
  LineReader reader(path, text);
  Measurement measurement;
  int64_t dims_in = -1, dims_out = -1, confidence = 0;
  std::string param_in, param_out;
  int64_t dim_line = 0, param_in_line = 0, param_out_line = 0;
  bool divide_by_cosine = false;
  std::string_view line;
  std::vector<std::string> comments;
  int64_t horizon_rows = 0;
  auto check_header = [&]() {
    if (dim_line == 0) reader.Fail("data row before the #DIM line (expected '#DIM 3 1')");
    if (param_in_line == 0) {
      reader.Fail("data row before the #PARAM_IN line (expected '#PARAM_IN " +
                  std::string(kProjectedInput) + "')");
    }
  };
  bool header_done = false;
  while (reader.Next(&line)) {
    line = Trim(line);
    if (line.empty()) continue;
    if (line.front() == '#') {
      if (header_done) continue;  // a comment among the rows
      if (StartsWith(line, "#DIM")) {
        if (dim_line != 0)
          reader.Fail("second #DIM line (first on line " + std::to_string(dim_line) + ")");
        dim_line = reader.line_number();
        const std::string counts = KeywordValue(line, "#DIM");  // the fields view into it
        const std::vector<std::string_view> fields = SplitFields(counts, " \t", true);
        if (fields.size() != 2)
          reader.Fail("#DIM needs two counts (inputs outputs), e.g. '#DIM 3 1'");
        dims_in = ParseCount(reader, fields[0], "the #DIM input count", 16);
        dims_out = ParseCount(reader, fields[1], "the #DIM output count", 16);
        if (dims_in != 3) {
          reader.Fail("#DIM input count " + std::to_string(dims_in) + " is not supported (" +
                      std::string(kProjectedInput) + " has 3 inputs)");
        }
        if (dims_out != 1 && dims_out != 3) {
          reader.Fail("#DIM output count " + std::to_string(dims_out) +
                      " is not supported (expected 1, grey, or 3, r g b)");
        }
      } else if (StartsWith(line, "#VS")) {
        const std::string value = KeywordValue(line, "#VS");
        confidence = ParseCount(reader, value, "the #VS confidence-column count", 16);
        if (confidence != 0) {
          reader.Fail("#VS " + value + ": confidence columns are not supported (expected #VS 0)");
        }
      } else if (StartsWith(line, "#PARAM_IN")) {
        if (param_in_line != 0) reader.Fail("second #PARAM_IN line");
        param_in_line = reader.line_number();
        param_in = KeywordValue(line, "#PARAM_IN");
        if (param_in != kProjectedInput) {
          reader.Fail("#PARAM_IN " + param_in + " is not supported (brdfkit reads " +
                      std::string(kProjectedInput) + ")");
        }
      } else if (StartsWith(line, "#PARAM_OUT")) {
        if (param_out_line != 0) reader.Fail("second #PARAM_OUT line");
        param_out_line = reader.line_number();
        param_out = KeywordValue(line, "#PARAM_OUT");
        if (param_out == "INV_STERADIAN_COSINE_FACTOR") {
          divide_by_cosine = true;
        } else if (param_out != "INV_STERADIAN") {
          reader.Fail("#PARAM_OUT " + param_out +
                      " is not supported (expected INV_STERADIAN or INV_STERADIAN_COSINE_FACTOR)");
        }
      } else {
        const std::string comment(Trim(line.substr(1)));
        if (StartsWith(comment, "SAMPLE ")) {
          std::string sample(Trim(std::string_view(comment).substr(7)));
          if (sample.size() >= 2 && sample.front() == '"' && sample.back() == '"') {
            sample = sample.substr(1, sample.size() - 2);
          }
          measurement.metadata["sample"] = sample;
        } else if (!comment.empty()) {
          comments.push_back(comment);
        }
      }
      continue;
    }
    if (!header_done) {
      check_header();
      header_done = true;
    }
    const std::vector<std::string_view> fields = SplitFields(line, " \t", true);
    const size_t expected = static_cast<size_t>(dims_in + dims_out);
    if (fields.size() != expected) {
      reader.Fail("expected " + std::to_string(expected) + " values (" + std::to_string(dims_in) +
                  " inputs, " + std::to_string(dims_out) + " outputs), found " +
                  std::to_string(fields.size()));
    }
    const double theta_l = ParseNumber(reader, fields[0], "theta_l (radians)");
    const double x = ParseNumber(reader, fields[1], "theta_v cos(dphi) (radians)");
    const double y = ParseNumber(reader, fields[2], "theta_v sin(dphi) (radians)");
    if (theta_l < -kAngleSlack || theta_l >= 0.5 * kPi) {
      reader.Fail("theta_l " + FormatNumber(theta_l) + " rad is outside [0, pi/2)");
    }
    const double theta_v = std::hypot(x, y);
    if (theta_v > 0.5 * kPi + kAngleSlack) {
      reader.Fail("theta_v = |(" + FormatNumber(x) + ", " + FormatNumber(y) +
                  ")| = " + FormatNumber(theta_v) + " rad is beyond the horizon (pi/2)");
    }
    const double dphi = std::atan2(y, x);
    Sample sample;
    sample.wi = SphericalDirection(std::max(0.0, theta_l), 0.0);
    sample.wo = SphericalDirection(std::min(theta_v, 0.5 * kPi), dphi);
    for (int c = 0; c < 3; ++c) {
      sample.value[c] = ParseNumber(reader, fields[3 + (dims_out == 3 ? c : 0)], "a BRDF value");
    }
    const double cos_theta_v = std::cos(theta_v);
    if (divide_by_cosine) {
      if (cos_theta_v < kHorizonCos) {
        sample.missing = true;  // f cos = value at the horizon: f itself is undefined
        ++horizon_rows;
      } else {
        sample.value /= cos_theta_v;
      }
    }
    measurement.samples.push_back(sample);
  }
  if (!header_done) {
    reader.Fail(dim_line == 0 ? "no #DIM header: not an ALTA data file"
                              : "no data rows after the header");
  }
  measurement.metadata["parameterization"] =
      param_in +
      " (theta_l, theta_v cos dphi, theta_v sin dphi; radians): wi at azimuth 0, wo "
      "at azimuth dphi";
  if (divide_by_cosine) {
    measurement.metadata["units"] =
        "BRDF in sr^-1: the file's INV_STERADIAN_COSINE_FACTOR (f cos theta_v) divided by cos "
        "theta_v";
  } else if (param_out_line != 0) {
    measurement.metadata["units"] = "BRDF in sr^-1 (INV_STERADIAN)";
  } else {
    // ALTA itself reads a file without #PARAM_OUT as an unknown output, values as they are.
    measurement.metadata["units"] =
        "ASSUMED BRDF in sr^-1: the file has no #PARAM_OUT line, so its values are taken as f, "
        "as ALTA takes an unknown output (not divided by cos theta_v)";
  }
  measurement.metadata["channels"] =
      dims_out == 1 ? "one value per row, copied to r, g and b" : "three values per row: r, g, b";
  if (horizon_rows > 0) {
    measurement.metadata["missing"] = std::to_string(horizon_rows) +
                                      " rows at theta_v = 90 deg (f cos theta_v given, cos = 0: "
                                      "f undefined) flagged missing";
  }
  for (size_t k = 0; k < comments.size(); ++k) {
    measurement.metadata["comment" + (comments.size() > 1 ? std::to_string(k + 1) : "")] =
        comments[k];
  }
  return measurement;
}

}  // namespace brdf
