#include "gonio/json_fields.h"

#include "core/errors.h"

namespace brdf::gonio {

JsonFields::JsonFields(const nlohmann::json& object, std::string prefix, const std::string& origin)
    : object_(object), prefix_(std::move(prefix)), origin_(origin) {
  if (!object_.is_object()) Fail(prefix_.empty() ? "top level" : prefix_, "expected an object");
}

const nlohmann::json* JsonFields::Find(const char* key) {
  known_[key] = true;
  return object_.contains(key) ? &object_[key] : nullptr;
}

void JsonFields::Number(const char* key, double* value) {
  const nlohmann::json* field = Find(key);
  if (field == nullptr) return;
  if (!field->is_number()) Fail(Name(key), "expected a number");
  *value = field->get<double>();
}

void JsonFields::Integer(const char* key, int* value) {
  const nlohmann::json* field = Find(key);
  if (field == nullptr) return;
  if (!field->is_number_integer()) Fail(Name(key), "expected an integer");
  *value = field->get<int>();
}

void JsonFields::Text(const char* key, std::string* value) {
  const nlohmann::json* field = Find(key);
  if (field == nullptr) return;
  if (!field->is_string()) Fail(Name(key), "expected a string");
  *value = field->get<std::string>();
}

void JsonFields::Object(const char* key, const std::function<void(JsonFields&)>& read) {
  const nlohmann::json* field = Find(key);
  if (field == nullptr) return;
  JsonFields nested(*field, Name(key), origin_);
  read(nested);
  nested.RejectUnknown();
}

void JsonFields::RejectUnknown() const {
  for (const auto& item : object_.items()) {
    if (known_.count(item.key())) continue;
    std::string list;
    for (const auto& [name, unused] : known_) list += (list.empty() ? "" : ", ") + name;
    Fail(Name(item.key().c_str()), "unknown field (known here: " + list + ")");
  }
}

void JsonFields::Fail(const std::string& field, const std::string& what) const {
  throw InputError(origin_, field + ": " + what);
}

std::string JsonFields::Name(const char* key) const {
  return prefix_.empty() ? key : prefix_ + "." + key;
}

}  // namespace brdf::gonio
