// The names enum values go by on the command line, in reports and in files, and parsing them
// back: one table of {value, name} per enum, defined next to the enum's functions, which become
// one-line wrappers.
//
//   constexpr EnumName<Loss> kLossNames[] = {{Loss::kL2, "l2"}, {Loss::kLog, "log"}};
//   Loss ParseLoss(const std::string& name) { return ParseEnum(kLossNames, name, "loss"); }
//   const char* LossName(Loss loss) { return NameOf(kLossNames, loss); }
//
// Every unknown name is reported the same way: "unknown loss 'l1' (known: l2, log)".
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace brdf {

template <typename Enum>
struct EnumName {
  Enum value;
  const char* name;
};

// Whether "d65" names the value spelled "D65".
enum class NameCase { kExact, kIgnore };

bool NamesMatch(std::string_view text, std::string_view name, NameCase name_case);
// "a, b, c": the accepted names, for messages and help texts.
std::string JoinNames(const char* const* names, size_t count);
// Throws UsageError("unknown WHAT 'TEXT' (known: a, b, c)").
[[noreturn]] void ThrowUnknownName(const char* what, std::string_view text,
                                   const char* const* names, size_t count);

// The name of `value`; "?" for a value missing from the table (a cast integer).
template <typename Enum, size_t N>
const char* NameOf(const EnumName<Enum> (&table)[N], Enum value) {
  for (const EnumName<Enum>& entry : table) {
    if (entry.value == value) return entry.name;
  }
  return "?";
}

template <typename Enum, size_t N>
std::string KnownNames(const EnumName<Enum> (&table)[N]) {
  const char* names[N];
  for (size_t k = 0; k < N; ++k) names[k] = table[k].name;
  return JoinNames(names, N);
}

// The value named `text`, or nothing: for callers that report an unknown name with their own
// error type (a file's field is an InputError naming the file, not a usage error).
template <typename Enum, size_t N>
std::optional<Enum> LookupEnum(const EnumName<Enum> (&table)[N], std::string_view text,
                               NameCase name_case = NameCase::kExact) {
  for (const EnumName<Enum>& entry : table) {
    if (NamesMatch(text, entry.name, name_case)) return entry.value;
  }
  return std::nullopt;
}

// The value named `text`; an unknown name is a UsageError naming `what`, the text and the
// accepted names.
template <typename Enum, size_t N>
Enum ParseEnum(const EnumName<Enum> (&table)[N], std::string_view text, const char* what,
               NameCase name_case = NameCase::kExact) {
  if (const std::optional<Enum> value = LookupEnum(table, text, name_case)) return *value;
  const char* names[N];
  for (size_t k = 0; k < N; ++k) names[k] = table[k].name;
  ThrowUnknownName(what, text, names, N);
}

}  // namespace brdf
