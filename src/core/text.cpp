#include "core/text.h"

#include <sys/stat.h>

#include <charconv>
#include <cmath>
#include <fstream>

#include "core/errors.h"

namespace brdf {

int64_t RegularFileSize(const std::string& path) {
  struct stat info;
  if (::stat(path.c_str(), &info) != 0) throw InputError(path, "cannot open (no such file)");
  if (S_ISDIR(info.st_mode)) throw InputError(path, "is a directory, expected a file");
  if (!S_ISREG(info.st_mode)) throw InputError(path, "is not a regular file");
  return info.st_size;
}

std::string ReadFileBytes(const std::string& path, int64_t max_bytes) {
  const int64_t size = RegularFileSize(path);
  if (size > max_bytes) {
    throw InputError(path, "file of " + std::to_string(size) + " bytes is larger than the " +
                               std::to_string(max_bytes) + "-byte limit for this format");
  }
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw InputError(path, "cannot open for reading");
  std::string bytes(static_cast<size_t>(size), '\0');
  stream.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (stream.gcount() != static_cast<std::streamsize>(bytes.size())) {
    throw ByteError(path, stream.gcount(), "read failed (file changed while reading?)");
  }
  return bytes;
}

bool LineReader::Next(std::string_view* line) {
  if (position_ >= text_.size()) return false;
  size_t end = text_.find('\n', position_);
  if (end == std::string_view::npos) end = text_.size();
  std::string_view current = text_.substr(position_, end - position_);
  if (!current.empty() && current.back() == '\r') current.remove_suffix(1);
  position_ = end + 1;
  ++line_number_;
  *line = current;
  return true;
}

void LineReader::Fail(const std::string& what) const {
  throw ParseError(path_, line_number_, what);
}

std::vector<std::string_view> SplitFields(std::string_view line, std::string_view separators,
                                          bool collapse) {
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (start <= line.size()) {
    size_t end = line.find_first_of(separators, start);
    if (end == std::string_view::npos) end = line.size();
    std::string_view field = Trim(line.substr(start, end - start));
    if (!(collapse && field.empty())) fields.push_back(field);
    start = end + 1;
  }
  return fields;
}

std::string FormatNumber(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::string FormatNumber(double value, int significant) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value,
                                    std::chars_format::general, significant);
  return std::string(buffer, result.ptr);
}

std::string_view Trim(std::string_view text) {
  const char* kSpace = " \t\r\n\f\v";
  const size_t first = text.find_first_not_of(kSpace);
  if (first == std::string_view::npos) return {};
  const size_t last = text.find_last_not_of(kSpace);
  return text.substr(first, last - first + 1);
}

bool StartsWith(std::string_view text, std::string_view prefix) {
  return text.substr(0, prefix.size()) == prefix;
}

std::string PrintableText(std::string_view text) {
  std::string printable;
  printable.reserve(text.size());
  for (unsigned char c : text) printable += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  return printable;
}

std::string ShortLabel(std::string_view text, size_t max_chars) {
  if (text.size() <= max_chars) return std::string(text);
  // A path names its file at the end: keep the file name, drop the directories before it.
  std::string label;
  size_t begin = 0;
  while (begin <= text.size()) {
    size_t end = text.find(' ', begin);
    if (end == std::string_view::npos) end = text.size();
    std::string_view word = text.substr(begin, end - begin);
    const size_t slash = word.find_last_of('/');
    if (slash != std::string_view::npos && slash + 1 < word.size()) word.remove_prefix(slash + 1);
    label += word;
    if (end < text.size()) label += ' ';
    begin = end + 1;
  }
  if (label.size() <= max_chars || max_chars < 4) return label;
  return label.substr(0, max_chars - 3) + "...";
}

namespace {
std::string Quote(std::string_view field) {
  constexpr size_t kMaxShown = 40;
  std::string shown = PrintableText(field.substr(0, kMaxShown));
  if (field.size() > kMaxShown) shown += "...";
  return "'" + shown + "'";
}
}  // namespace

double ParseNumber(const LineReader& reader, std::string_view field, const char* what,
                   bool allow_non_finite) {
  if (field.empty()) reader.Fail(std::string("expected a number for ") + what + ", found nothing");
  const char* begin = field.data();
  if (*begin == '+') ++begin;  // from_chars does not take a leading '+'
  double value = 0;
  const auto [end, error] = std::from_chars(begin, field.data() + field.size(), value);
  if (error == std::errc::result_out_of_range) {
    reader.Fail(std::string("number out of range for ") + what + ": " + Quote(field));
  }
  if (error != std::errc() || end != field.data() + field.size()) {
    reader.Fail(std::string("expected a number for ") + what + ", found " + Quote(field));
  }
  if (!allow_non_finite && !std::isfinite(value)) {
    reader.Fail(std::string("expected a finite number for ") + what + ", found " + Quote(field));
  }
  return value;
}

int64_t ParseCount(const LineReader& reader, std::string_view field, const char* what,
                   int64_t max_value) {
  int64_t value = 0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc() || end != field.data() + field.size() || field.empty()) {
    reader.Fail(std::string("expected a whole number for ") + what + ", found " + Quote(field));
  }
  if (value < 0 || value > max_value) {
    reader.Fail(std::string(what) + " must be between 0 and " + std::to_string(max_value) +
                ", found " + std::to_string(value));
  }
  return value;
}

}  // namespace brdf
