#include "core/json_text.h"

#include <map>
#include <set>
#include <vector>

#include "core/errors.h"

namespace brdf {
namespace {

// Byte offset of the `occurrence`-th (1-based) appearance of `key` as an object key ("key"
// followed by a colon) in `text`, or -1. Keys spelled with escapes are not found.
int64_t KeyByte(const std::string& text, const std::string& key, int occurrence) {
  const std::string quoted = "\"" + key + "\"";
  for (size_t at = text.find(quoted); at != std::string::npos; at = text.find(quoted, at + 1)) {
    size_t after = at + quoted.size();
    while (after < text.size() && (text[after] == ' ' || text[after] == '\t' ||
                                   text[after] == '\n' || text[after] == '\r')) {
      ++after;
    }
    if (after < text.size() && text[after] == ':' && --occurrence == 0) {
      return static_cast<int64_t>(at);
    }
  }
  return -1;
}

}  // namespace

nlohmann::json ParseJsonText(const std::string& text, const std::string& origin,
                             const std::string& expected) {
  // nlohmann keeps the last of two equal keys in an object without a word; a file that says
  // "bounces" twice leaves the reader guessing which the writer meant, so it is an error.
  std::vector<std::set<std::string>> open_objects;
  std::map<std::string, int> keys_seen;  // how often each key name appeared, for its byte
  std::string duplicate;
  const nlohmann::json::parser_callback_t check_keys =
      [&](int /*depth*/, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        if (event == nlohmann::json::parse_event_t::object_start) {
          open_objects.emplace_back();
        } else if (event == nlohmann::json::parse_event_t::object_end) {
          if (!open_objects.empty()) open_objects.pop_back();
        } else if (event == nlohmann::json::parse_event_t::key && duplicate.empty()) {
          const std::string key = parsed.get<std::string>();
          ++keys_seen[key];
          if (!open_objects.empty() && !open_objects.back().insert(key).second) duplicate = key;
        }
        return true;
      };
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text, check_keys);
  } catch (const nlohmann::json::parse_error& error) {
    throw ByteError(origin, static_cast<int64_t>(error.byte) - 1,
                    "not valid JSON, expected " + expected);
  } catch (const nlohmann::json::exception& error) {
    // out_of_range (a number too large for a double) and the like carry no position.
    throw InputError(origin,
                     std::string("unreadable JSON (") + error.what() + "), expected " + expected);
  }
  if (!duplicate.empty()) {
    const std::string what = "key \"" + duplicate + "\" appears twice in one object";
    const int64_t byte = KeyByte(text, duplicate, keys_seen[duplicate]);
    if (byte >= 0) throw ByteError(origin, byte, what);
    throw InputError(origin, what);
  }
  return json;
}

}  // namespace brdf
