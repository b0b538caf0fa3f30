// Line-oriented reading of text measurement files with exact error positions. Every text
// reader goes through this, so every parse error names the file and the 1-based line.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace brdf {

// Size of a regular file. Throws InputError if it cannot be opened or is not a regular file
// (a directory, a device).
int64_t RegularFileSize(const std::string& path);

// Reads a whole file into memory. Throws InputError if it cannot be opened, is not a regular
// file (a directory, a device) or is larger than `max_bytes`.
std::string ReadFileBytes(const std::string& path, int64_t max_bytes = int64_t{1} << 32);

// Walks the lines of an in-memory text; accepts \n and \r\n line ends.
class LineReader {
 public:
  LineReader(std::string path, std::string_view text) : path_(std::move(path)), text_(text) {}

  // Next line (without its end) or false at the end of the text.
  bool Next(std::string_view* line);
  int64_t line_number() const { return line_number_; }
  const std::string& path() const { return path_; }

  // Throws ParseError at the current line.
  [[noreturn]] void Fail(const std::string& what) const;

 private:
  std::string path_;
  std::string_view text_;
  size_t position_ = 0;
  int64_t line_number_ = 0;
};

// Splits on any of `separators`, skipping empty fields when `collapse` (whitespace-separated
// files) and keeping them otherwise (comma-separated files, where an empty field is an error
// the caller reports).
std::vector<std::string_view> SplitFields(std::string_view line, std::string_view separators,
                                          bool collapse);

// Shortest decimal text that reads back to exactly `value` (std::to_chars round trip).
std::string FormatNumber(double value);
// `value` rounded to `significant` digits, for people rather than for round trips.
std::string FormatNumber(double value, int significant);

// `text` in at most `max_chars` characters, for a label a person reads: a path in it is cut to
// its file name first (the directories go, the name stays), then the end is cut with "...".
std::string ShortLabel(std::string_view text, size_t max_chars);

std::string_view Trim(std::string_view text);
// `text` with every byte that is not printable ASCII shown as '?', for quoting file contents in
// messages (a binary file must never put raw bytes on the terminal).
std::string PrintableText(std::string_view text);
bool StartsWith(std::string_view text, std::string_view prefix);

// Parses a whole field as a finite double; throws ParseError at the reader's line naming
// `what` and the offending text. NaN and infinities are rejected unless `allow_non_finite`.
double ParseNumber(const LineReader& reader, std::string_view field, const char* what,
                   bool allow_non_finite = false);
// Parses a whole field as a non-negative integer no larger than `max_value`.
int64_t ParseCount(const LineReader& reader, std::string_view field, const char* what,
                   int64_t max_value);

}  // namespace brdf
