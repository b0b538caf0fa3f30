// Reading the small JSON descriptions of gonio/ (instrument, surface): every field optional,
// typed, and unknown keys rejected so that a typo is not silently ignored. Errors are
// InputError naming the file and the dotted field ("detector.photons: expected a number").
#pragma once

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "core/json_text.h"

namespace brdf::gonio {

class JsonFields {
 public:
  // `prefix` names the object in errors ("" for the top level).
  JsonFields(const nlohmann::json& object, std::string prefix, const std::string& origin);

  void Number(const char* key, double* value);
  void Integer(const char* key, int* value);
  void Text(const char* key, std::string* value);
  // Reads a nested object with `read` (then rejects its unknown keys).
  void Object(const char* key, const std::function<void(JsonFields&)>& read);
  // Throws for keys no Number/Integer/Text/Object call asked for.
  void RejectUnknown() const;
  [[noreturn]] void Fail(const std::string& field, const std::string& what) const;
  std::string Name(const char* key) const;

 private:
  const nlohmann::json* Find(const char* key);

  const nlohmann::json& object_;
  std::string prefix_;
  const std::string& origin_;
  std::map<std::string, bool> known_;
};

}  // namespace brdf::gonio
