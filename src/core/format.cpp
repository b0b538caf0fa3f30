#include "core/format.h"

#include <cstdarg>
#include <cstdio>

namespace brdf {

std::string Format(const char* format, ...) {
  // Most results fit a small stack buffer; a longer one is formatted a second time at its size.
  char buffer[256];
  va_list arguments;
  va_start(arguments, format);
  va_list retry;
  va_copy(retry, arguments);
  const int length = std::vsnprintf(buffer, sizeof(buffer), format, arguments);
  va_end(arguments);
  if (length < 0) {
    va_end(retry);
    return std::string();
  }
  if (static_cast<size_t>(length) < sizeof(buffer)) {
    va_end(retry);
    return std::string(buffer, static_cast<size_t>(length));
  }
  std::string text(static_cast<size_t>(length), '\0');
  std::vsnprintf(text.data(), text.size() + 1, format, retry);
  va_end(retry);
  return text;
}

}  // namespace brdf
