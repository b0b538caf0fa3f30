// printf-style formatting into a std::string: the one formatter for report lines, table
// columns, captions and messages that want a fixed printf layout ("%-12.6g", "%.4g", "%a").
//
// Which to use:
// - Format(...) when the output has a printf layout: column widths, a fixed number of
//   significant digits or decimals, hex floats. The compiler checks the arguments against the
//   format (the attribute below), so a mismatched conversion is a warning, not a crash.
// - FormatNumber(value) (core/text.h) when a number must read back to exactly the same double
//   (model strings, JSON-like text, CSV values another program parses): shortest round trip.
#pragma once

#include <string>

namespace brdf {

// std::snprintf semantics; the result has no length limit.
std::string Format(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace brdf
