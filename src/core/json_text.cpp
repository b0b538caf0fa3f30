#include "core/json_text.h"

#include "core/errors.h"

namespace brdf {

nlohmann::json ParseJsonText(const std::string& text, const std::string& origin,
                             const std::string& expected) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& error) {
    throw ByteError(origin, static_cast<int64_t>(error.byte) - 1,
                    "not valid JSON, expected " + expected);
  } catch (const nlohmann::json::exception& error) {
    // out_of_range (a number too large for a double) and the like carry no position.
    throw InputError(origin,
                     std::string("unreadable JSON (") + error.what() + "), expected " + expected);
  }
}

}  // namespace brdf
