#pragma once
// A small JSON Schema (draft 2020-12) validator for tests, over tests/support/json_parse.h: the
// keywords Sylva's schemas use — type (one or a list; "integer" is a number with no fraction),
// const, enum, required, properties, additionalProperties (false), items, minItems, maxItems,
// minimum, pattern (strings only), oneOf, and $ref to "#/$defs/NAME". Annotations ($schema, $id,
// title, description, $defs) are skipped; any other keyword is an error, so a schema cannot use
// something this validator would silently ignore.

#include "tests/support/json_parse.h"

#include <cmath>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

namespace sylva::test {

class SchemaValidator {
 public:
  explicit SchemaValidator(Json schema) : root_(std::move(schema)) {}

  // Every violation, one line each with its JSON path ("$.comparisons[0].verdict: ..."); empty if valid.
  std::vector<std::string> validate(const Json& value) const {
    std::vector<std::string> errors;
    check(root_, value, "$", errors);
    return errors;
  }

 private:
  static bool equal(const Json& a, const Json& b) {
    if (a.kind != b.kind) return false;
    switch (a.kind) {
      case Json::Kind::Null:
        return true;
      case Json::Kind::Bool:
        return a.boolean == b.boolean;
      case Json::Kind::Number:
        return a.number == b.number;
      case Json::Kind::String:
        return a.string == b.string;
      default:
        return false;  // the schemas compare scalars only
    }
  }

  static bool has_type(const Json& v, const std::string& type) {
    if (type == "null") return v.kind == Json::Kind::Null;
    if (type == "boolean") return v.kind == Json::Kind::Bool;
    if (type == "number") return v.kind == Json::Kind::Number;
    if (type == "integer") return v.kind == Json::Kind::Number && std::floor(v.number) == v.number;
    if (type == "string") return v.kind == Json::Kind::String;
    if (type == "array") return v.kind == Json::Kind::Array;
    if (type == "object") return v.kind == Json::Kind::Object;
    throw std::runtime_error("schema: unknown type " + type);
  }

  const Json& resolve(const std::string& ref) const {
    const std::string prefix = "#/$defs/";
    if (ref.rfind(prefix, 0) != 0) throw std::runtime_error("schema: unsupported $ref " + ref);
    return root_["$defs"][ref.substr(prefix.size())];
  }

  void check(const Json& s, const Json& v, const std::string& path, std::vector<std::string>& errors) const {
    for (const auto& [key, arg] : s.object) {
      if (key == "$schema" || key == "$id" || key == "title" || key == "description" || key == "$defs") continue;
      if (key == "$ref") {
        check(resolve(arg.string), v, path, errors);
      } else if (key == "type") {
        bool ok = false;
        if (arg.kind == Json::Kind::String) ok = has_type(v, arg.string);
        for (const Json& t : arg.array) ok = ok || has_type(v, t.string);
        if (!ok) errors.push_back(path + ": wrong type");
      } else if (key == "const") {
        if (!equal(arg, v)) errors.push_back(path + ": not the constant");
      } else if (key == "enum") {
        bool ok = false;
        for (const Json& e : arg.array) ok = ok || equal(e, v);
        if (!ok) errors.push_back(path + ": not one of the enum");
      } else if (key == "required") {
        if (v.kind == Json::Kind::Object)
          for (const Json& r : arg.array)
            if (!v.has(r.string)) errors.push_back(path + ": missing " + r.string);
      } else if (key == "properties") {
        if (v.kind == Json::Kind::Object)
          for (const auto& [name, sub] : arg.object)
            if (v.has(name)) check(sub, v[name], path + "." + name, errors);
      } else if (key == "additionalProperties") {
        if (arg.kind != Json::Kind::Bool || arg.boolean) throw std::runtime_error("schema: additionalProperties");
        if (v.kind == Json::Kind::Object)
          for (const auto& [name, sub] : v.object)
            if (!s.has("properties") || !s["properties"].has(name))
              errors.push_back(path + ": unexpected property " + name);
      } else if (key == "items") {
        if (v.kind == Json::Kind::Array)
          for (size_t i = 0; i < v.array.size(); ++i)
            check(arg, v.array[i], path + "[" + std::to_string(i) + "]", errors);
      } else if (key == "minItems" || key == "maxItems") {
        if (v.kind == Json::Kind::Array &&
            (key == "minItems" ? v.array.size() < arg.number : v.array.size() > arg.number))
          errors.push_back(path + ": " + key);
      } else if (key == "minimum") {
        if (v.kind == Json::Kind::Number && v.number < arg.number) errors.push_back(path + ": below minimum");
      } else if (key == "pattern") {
        if (v.kind == Json::Kind::String && !std::regex_search(v.string, std::regex(arg.string)))
          errors.push_back(path + ": \"" + v.string + "\" does not match " + arg.string);
      } else if (key == "oneOf") {
        int matching = 0;
        for (const Json& option : arg.array) {
          std::vector<std::string> sub;
          check(option, v, path, sub);
          matching += sub.empty() ? 1 : 0;
        }
        if (matching != 1) errors.push_back(path + ": matches " + std::to_string(matching) + " of oneOf");
      } else {
        throw std::runtime_error("schema: unsupported keyword " + key);
      }
    }
  }

  Json root_;
};

}  // namespace sylva::test
