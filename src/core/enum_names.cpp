#include "core/enum_names.h"

#include <algorithm>
#include <cctype>

#include "core/errors.h"
#include "core/text.h"

namespace brdf {

bool NamesMatch(std::string_view text, std::string_view name, NameCase name_case) {
  if (name_case == NameCase::kExact) return text == name;
  return text.size() == name.size() &&
         std::equal(text.begin(), text.end(), name.begin(), [](unsigned char a, unsigned char b) {
           return std::tolower(a) == std::tolower(b);
         });
}

std::string JoinNames(const char* const* names, size_t count) {
  std::string text;
  for (size_t k = 0; k < count; ++k) {
    if (k > 0) text += ", ";
    text += names[k];
  }
  return text;
}

void ThrowUnknownName(const char* what, std::string_view text, const char* const* names,
                      size_t count) {
  throw UsageError(std::string("unknown ") + what + " '" + PrintableText(text) +
                   "' (known: " + JoinNames(names, count) + ")");
}

}  // namespace brdf
