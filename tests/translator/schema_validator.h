// A validator for the subset of JSON Schema that translator/schema.cpp emits (type, enum,
// required, properties, additionalProperties as a boolean or a schema, propertyNames.pattern,
// items, minItems, minimum, maximum, minLength, pattern, const, anyOf; types including null), for
// the tests. A keyword outside that
// subset is reported as an error, so that the schema cannot grow past what is checked here.
#pragma once

#include <regex>
#include <string>
#include <vector>

#include "planner/model/json_io.h"

namespace ctb::testing {

inline void Validate(const Json& s, const Json& v, const std::string& at,
                     std::vector<std::string>& errors) {
  static const std::vector<std::string> kKnown = {
      "$schema",       "title",     "description", "type",
      "enum",          "required",  "properties",  "additionalProperties",
      "propertyNames", "items",     "minItems",    "minimum",
      "maximum",       "minLength", "pattern",
      "const",         "anyOf"};
  for (auto it = s.begin(); it != s.end(); ++it)
    if (std::find(kKnown.begin(), kKnown.end(), it.key()) == kKnown.end())
      errors.push_back(at + ": schema keyword '" + it.key() +
                       "' not supported by the test validator");
  auto fail = [&](const std::string& why) {
    errors.push_back((at.empty() ? "/" : at) + ": " + why);
  };
  if (s.contains("anyOf")) {
    bool any = false;
    std::vector<std::string> first;
    for (const auto& alt : s["anyOf"]) {
      std::vector<std::string> e;
      Validate(alt, v, at, e);
      if (e.empty()) any = true;
      else if (first.empty()) first = e;
    }
    if (!any) errors.push_back((at.empty() ? "/" : at) + ": no alternative of anyOf holds (first: " +
                               (first.empty() ? "" : first[0]) + ")");
  }
  if (s.contains("const") && s["const"] != v) fail("expected " + s["const"].dump());
  if (s.contains("type")) {
    std::string t = s["type"];
    bool ok = (t == "object" && v.is_object()) || (t == "array" && v.is_array()) ||
              (t == "null" && v.is_null()) ||
              (t == "string" && v.is_string()) || (t == "number" && v.is_number()) ||
              (t == "integer" && v.is_number_integer()) || (t == "boolean" && v.is_boolean());
    if (!ok) return fail("expected " + t + ", got " + JsonTypeName(v));
  }
  if (s.contains("enum") && std::find(s["enum"].begin(), s["enum"].end(), v) == s["enum"].end())
    fail(v.dump() + " is not one of " + s["enum"].dump());
  if (v.is_number()) {
    if (s.contains("minimum") && v.get<double>() < s["minimum"].get<double>())
      fail("below minimum");
    if (s.contains("maximum") && v.get<double>() > s["maximum"].get<double>())
      fail("above maximum");
  }
  if (v.is_string()) {
    if (s.contains("minLength") && v.get<std::string>().size() < s["minLength"].get<std::size_t>())
      fail("too short");
    if (s.contains("pattern") &&
        !std::regex_search(v.get<std::string>(), std::regex(s["pattern"].get<std::string>())))
      fail("does not match " + s["pattern"].get<std::string>());
  }
  if (v.is_array()) {
    if (s.contains("minItems") && v.size() < s["minItems"].get<std::size_t>())
      fail("too few items");
    if (s.contains("items"))
      for (std::size_t i = 0; i < v.size(); ++i)
        Validate(s["items"], v[i], at + "/" + std::to_string(i), errors);
  }
  if (v.is_object()) {
    if (s.contains("required"))
      for (const auto& k : s["required"])
        if (!v.contains(k.get<std::string>()))
          fail("missing required \"" + k.get<std::string>() + "\"");
    for (auto it = v.begin(); it != v.end(); ++it) {
      std::string child = at + "/" + it.key();
      if (s.contains("propertyNames"))
        Validate(s["propertyNames"], Json(it.key()), child + " (name)", errors);
      if (s.contains("properties") && s["properties"].contains(it.key())) {
        Validate(s["properties"][it.key()], it.value(), child, errors);
      } else if (s.contains("additionalProperties")) {
        const Json& ap = s["additionalProperties"];
        if (ap.is_boolean()) {
          if (!ap.get<bool>()) fail("property \"" + it.key() + "\" not allowed");
        } else {
          Validate(ap, it.value(), child, errors);
        }
      }
    }
  }
}

inline std::vector<std::string> Validate(const Json& schema, const Json& value) {
  std::vector<std::string> errors;
  Validate(schema, value, "", errors);
  return errors;
}

}  // namespace ctb::testing
