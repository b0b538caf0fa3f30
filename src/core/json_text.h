// Parsing the JSON a user hands the tool (fit reports, instrument and surface descriptions):
// malformed text becomes an InputError naming the file and the byte, never a stray
// nlohmann exception (the fuzzer found one: a number like 8888888888888E8888 throws
// out_of_range, not parse_error).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace brdf {

// `origin` names the file in errors; `expected` says what the file should hold.
nlohmann::json ParseJsonText(const std::string& text, const std::string& origin,
                             const std::string& expected);

}  // namespace brdf
