#include "io/formats.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <fstream>

#include "core/errors.h"
#include "io/rgl_bsdf.h"

namespace brdf {
namespace {

std::string LowerExtension(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string extension = path.substr(dot);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return extension;
}

std::string KnownFormats(bool writable) {
  std::string names;
  for (const FileFormat& format : FileFormats()) {
    if (writable && format.write == nullptr) continue;
    names += (names.empty() ? "" : ", ") + format.name;
    for (const std::string& extension : format.extensions) names += " " + extension;
  }
  return names;
}

}  // namespace

const std::vector<FileFormat>& FileFormats() {
  static const std::vector<FileFormat> formats = {
      {"native-csv",
       "brdfkit measurement CSV (degrees, sr^-1)",
       {".csv"},
       &SniffNativeCsv,
       &ReadNativeCsv,
       &WriteNativeCsv},
      {"merl",
       "MERL isotropic binary table 90x90x180",
       {".binary"},
       &SniffMerl,
       &ReadMerl,
       &WriteMerl,
       true,
       &CopyMerl,
       &ReadMerlEvaluator},
      {"astm", "ASTM E1392 text (Cornell), spectral", {".astm"}, &SniffAstm, &ReadAstm, nullptr},
      {"pbrt-brdf",
       "pbrt-v2 measured .brdf text, spectral",
       {".brdf"},
       &SniffPbrtBrdf,
       &ReadPbrtBrdf,
       nullptr},
      {"zemax",
       "Zemax tabular BSDF (BRDF, plane-symmetric)",
       {".bsdf"},
       &SniffZemax,
       &ReadZemax,
       nullptr},
      // After Zemax: both use .bsdf, and a file that neither the magic nor the Zemax keywords
      // identify is more likely a broken Zemax text than a tensor_file.
      {"rgl-bsdf",
       "RGL-EPFL tensor_file material (Dupuy & Jakob 2018), RGB or spectral",
       {".bsdf"},
       &SniffRglBsdf,
       &ReadRglBsdf,
       nullptr},
      {"alta",
       "ALTA data text (ISOTROPIC_TL_TV_PROJ_DPHI input, f or f cos output)",
       {".dat", ".alta"},
       &SniffAlta,
       &ReadAlta,
       nullptr},
      {"gonio-csv",
       "in-plane spectral gonio table (Incident_angle,Measure_angle,<nm>...; degrees)",
       {".csv"},
       &SniffGonioCsv,
       &ReadGonioCsv,
       nullptr},
      {"alta-slice",
       "BRDF slice image, ALTA data_brdf_slice OpenEXR (theta_h x theta_d, phi_d 90 deg)",
       {".exr"},
       &SniffAltaSlice,
       &ReadAltaSlice,
       nullptr},
  };
  return formats;
}

const FileFormat* FormatByContent(const std::string& path) {
  struct stat info;
  if (::stat(path.c_str(), &info) != 0) throw InputError(path, "cannot open (no such file)");
  if (S_ISDIR(info.st_mode)) throw InputError(path, "is a directory, expected a measurement file");
  if (!S_ISREG(info.st_mode)) throw InputError(path, "is not a regular file");
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw InputError(path, "cannot open for reading");
  std::string head(4096, '\0');
  stream.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(stream.gcount()));
  if (head.empty()) throw ByteError(path, 0, "empty file, expected a measurement");

  for (const FileFormat& format : FileFormats()) {
    if (format.sniff(head, info.st_size)) return &format;
  }
  return nullptr;
}

const FileFormat& DetectFormat(const std::string& path) {
  if (const FileFormat* format = FormatByContent(path)) return *format;
  const std::string extension = LowerExtension(path);
  for (const FileFormat& format : FileFormats()) {
    for (const std::string& known : format.extensions) {
      if (known == extension) return format;
    }
  }
  throw ByteError(
      path, 0,
      "not a measurement format brdfkit reads (expected one of: " + KnownFormats(false) + ")");
}

const FileFormat& OutputFormat(const std::string& path, const std::string& format_name) {
  const std::string extension = LowerExtension(path);
  for (const FileFormat& format : FileFormats()) {
    bool match = format.name == format_name;
    if (format_name.empty()) {
      match = std::find(format.extensions.begin(), format.extensions.end(), extension) !=
              format.extensions.end();
    }
    if (!match) continue;
    if (format.write == nullptr) {
      throw UsageError(path + ": brdfkit cannot write " + format.name +
                       " files (writable: " + KnownFormats(true) + ")");
    }
    return format;
  }
  throw UsageError(path + ": cannot tell the output format from '" +
                   (format_name.empty() ? extension : format_name) +
                   "' (writable: " + KnownFormats(true) + ")");
}

Measurement ReadMeasurement(const std::string& path, const ReadOptions& options) {
  const FileFormat& format = DetectFormat(path);
  Measurement measurement = format.read(path, options);
  measurement.format = format.name;
  measurement.source = path;
  return measurement;
}

std::optional<Measurement> ReadEvaluator(const std::string& path, const ReadOptions& options) {
  const FileFormat& format = DetectFormat(path);
  if (format.read_evaluator == nullptr) return std::nullopt;
  Measurement measurement = format.read_evaluator(path, options);
  measurement.format = format.name;
  measurement.source = path;
  return measurement;
}

WriteReport WriteMeasurement(const Measurement& measurement, const std::string& path,
                             const std::string& format_name) {
  return OutputFormat(path, format_name).write(measurement, path);
}

}  // namespace brdf
