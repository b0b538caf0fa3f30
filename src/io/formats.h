// Measurement file formats (DESIGN §4): one reader/writer per file, chosen by content first
// and by extension second (a small taxonomy after tev: a sniffer says "mine" or "not mine";
// a reader that claims a file and finds it broken throws InputError naming file and line/byte).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/colour.h"
#include "core/measurement.h"

namespace brdf {

struct ReadOptions {
  // Illuminant under which spectral files (ASTM, pbrt-v2) become RGB; recorded in metadata.
  Illuminant illuminant = Illuminant::kD65;
  // RGL-EPFL tensors: read with the more grazing direction as the light (reciprocal by
  // construction) instead of as the format's reference evaluates them (io/rgl_bsdf.h).
  bool reciprocal = false;
};

// What a writer wants the user to know (e.g. samples binned onto a grid).
struct WriteReport {
  std::vector<std::string> warnings;
};

struct FileFormat {
  std::string name;         // "native-csv", "merl", "astm", "zemax", "rgl-bsdf", "alta-slice", ...
  std::string description;  // one line for --help and `brdf info`
  std::vector<std::string> extensions;  // lower case, with the dot
  // True when the first bytes of a file (up to 4 KiB) and its size say "this is mine".
  bool (*sniff)(std::string_view head, int64_t file_size) = nullptr;
  Measurement (*read)(const std::string& path, const ReadOptions& options) = nullptr;
  WriteReport (*write)(const Measurement& measurement, const std::string& path) = nullptr;
  // The file is a fixed table of cells of its own (MERL): its writer fills every cell from the
  // measurement's evaluator, so a model can be written without a schedule.
  bool fixed_grid = false;
  // Copies a valid file of this format unchanged (validated on the way), or nullptr.
  void (*copy)(const std::string& from, const std::string& to) = nullptr;
  // Reads the file's evaluator (Measurement::tabulated, its cell measure and the metadata)
  // without making its samples, for a consumer that asks for the evaluator alone (a fit under
  // the image loss renders it and never reads a sample; a MERL table's samples are 117 MB).
  // nullptr: the format has no evaluator, or its samples cost nothing worth saving.
  Measurement (*read_evaluator)(const std::string& path, const ReadOptions& options) = nullptr;
};

const std::vector<FileFormat>& FileFormats();

// The format whose sniffer claims the file by its content, or nullptr (the extension is not
// looked at: a listing of measurement files among others asks this). Throws InputError when the
// file cannot be opened or is not a regular file.
const FileFormat* FormatByContent(const std::string& path);
// The format of an existing file: by content, else by extension. Throws InputError when
// neither identifies it (listing the formats it knows).
const FileFormat& DetectFormat(const std::string& path);
// The format to write `path` in: `format_name` if given, else by extension. Throws UsageError
// when the format is unknown or cannot be written.
const FileFormat& OutputFormat(const std::string& path, const std::string& format_name = "");

Measurement ReadMeasurement(const std::string& path, const ReadOptions& options = {});
// The file's evaluator alone, its samples not made (Measurement::samples empty), when its format
// hands one out that way (FileFormat::read_evaluator); std::nullopt otherwise, and the caller
// reads the whole measurement.
std::optional<Measurement> ReadEvaluator(const std::string& path, const ReadOptions& options = {});
WriteReport WriteMeasurement(const Measurement& measurement, const std::string& path,
                             const std::string& format_name = "");

// Readers and writers, one per file (registered in formats.cpp).
Measurement ReadNativeCsv(const std::string& path, const ReadOptions& options);
WriteReport WriteNativeCsv(const Measurement& measurement, const std::string& path);
bool SniffNativeCsv(std::string_view head, int64_t file_size);

Measurement ReadMerl(const std::string& path, const ReadOptions& options);
Measurement ReadMerlEvaluator(const std::string& path, const ReadOptions& options);
WriteReport WriteMerl(const Measurement& measurement, const std::string& path);
bool SniffMerl(std::string_view head, int64_t file_size);
void CopyMerl(const std::string& from, const std::string& to);

Measurement ReadAstm(const std::string& path, const ReadOptions& options);
bool SniffAstm(std::string_view head, int64_t file_size);

Measurement ReadPbrtBrdf(const std::string& path, const ReadOptions& options);
bool SniffPbrtBrdf(std::string_view head, int64_t file_size);

Measurement ReadZemax(const std::string& path, const ReadOptions& options);
bool SniffZemax(std::string_view head, int64_t file_size);

Measurement ReadAlta(const std::string& path, const ReadOptions& options);
bool SniffAlta(std::string_view head, int64_t file_size);

Measurement ReadGonioCsv(const std::string& path, const ReadOptions& options);
bool SniffGonioCsv(std::string_view head, int64_t file_size);

Measurement ReadAltaSlice(const std::string& path, const ReadOptions& options);
bool SniffAltaSlice(std::string_view head, int64_t file_size);

}  // namespace brdf
