#include "planner/model/json_io.h"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

namespace ctb {
namespace {

// Finds the first place where brackets nest deeper than max_depth, outside strings. Runs before
// the parser so that hostile nesting costs O(n) and no recursion anywhere.
std::optional<std::size_t> FindTooDeep(std::string_view text, int max_depth) {
  int depth = 0;
  bool in_string = false;
  bool escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') in_string = true;
    else if (c == '[' || c == '{') {
      if (++depth > max_depth) return i;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return std::nullopt;
}

bool IsBlank(std::string_view text) {
  for (char c : text)
    if (c != ' ' && c != '\t' && c != '\n' && c != '\r') return false;
  return true;
}

}  // namespace

const char* JsonTypeName(const Json& j) {
  switch (j.type()) {
    case Json::value_t::object: return "object";
    case Json::value_t::array: return "array";
    case Json::value_t::string: return "string";
    case Json::value_t::boolean: return "boolean";
    case Json::value_t::null: return "null";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float: return "number";
    default: return "value";
  }
}

std::optional<Json> ParseJsonStrict(std::string_view text, Diagnostics& diags,
                                    const ParseLimits& limits) {
  if (text.size() > limits.max_bytes) {
    diags.Error("", "input is " + std::to_string(text.size()) + " bytes, more than the limit of " +
                        std::to_string(limits.max_bytes));
    return std::nullopt;
  }
  if (IsBlank(text)) {
    diags.Error("", "empty input: expected a JSON document");
    return std::nullopt;
  }
  if (auto at = FindTooDeep(text, limits.max_depth)) {
    diags.Error("", "JSON nested deeper than " + std::to_string(limits.max_depth) + " levels",
                *at);
    return std::nullopt;
  }
  // Duplicate keys: nlohmann keeps the last one silently; a stack of key sets catches them.
  std::vector<std::set<std::string>> keys;
  std::string duplicate;
  auto callback = [&](int /*depth*/, Json::parse_event_t event, Json& parsed) -> bool {
    switch (event) {
      case Json::parse_event_t::object_start: keys.emplace_back(); break;
      case Json::parse_event_t::object_end:
        if (!keys.empty()) keys.pop_back();
        break;
      case Json::parse_event_t::key:
        if (!keys.empty() && !keys.back().insert(parsed.get<std::string>()).second &&
            duplicate.empty())
          duplicate = parsed.get<std::string>();
        break;
      default: break;
    }
    return true;
  };
  try {
    Json j = Json::parse(text.begin(), text.end(), callback, /*allow_exceptions=*/true,
                         /*ignore_comments=*/false);
    if (!duplicate.empty()) {
      diags.Error("", "duplicate key \"" + duplicate + "\" in a JSON object");
      return std::nullopt;
    }
    return j;
  } catch (const Json::parse_error& e) {
    // e.byte is 1-based; report a 0-based offset. Strip nlohmann's "[json.exception...]" prefix.
    std::string what = e.what();
    auto pos = what.find("] ");
    if (pos != std::string::npos) what = what.substr(pos + 2);
    diags.Error("", "not valid JSON: " + what, e.byte > 0 ? e.byte - 1 : 0);
  } catch (const std::exception& e) {
    diags.Error("", std::string("not valid JSON: ") + e.what());
  }
  return std::nullopt;
}

std::string WireText(const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); }

std::string PrettyText(const Json& j) { return j.dump(2, ' ', false, Json::error_handler_t::replace); }

std::optional<Json> ReadJsonFile(const std::string& path, Diagnostics& diags,
                                 const ParseLimits& limits) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    diags.Error("", "cannot open file '" + path + "'");
    return std::nullopt;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  return ParseJsonStrict(ss.str(), diags, limits);
}

std::optional<double> AsNonNegative(const Json& j, const std::string& pointer, Diagnostics& diags) {
  if (!j.is_number()) {
    diags.Error(pointer, std::string("expected a number, got ") + JsonTypeName(j));
    return std::nullopt;
  }
  double v = j.get<double>();
  if (!std::isfinite(v)) {
    diags.Error(pointer, "number is not finite");
    return std::nullopt;
  }
  if (v < 0) {
    diags.Error(pointer, "number must not be negative, got " + j.dump());
    return std::nullopt;
  }
  return v;
}

ObjectReader::ObjectReader(const Json& j, std::string pointer, Diagnostics& diags)
    : j_(&j), pointer_(std::move(pointer)), diags_(&diags), valid_(j.is_object()) {
  if (!valid_) diags.Error(pointer_, std::string("expected an object, got ") + JsonTypeName(j));
}

void ObjectReader::CheckKeys(std::initializer_list<std::string_view> allowed) const {
  if (!valid_) return;
  for (const auto& [key, value] : j_->items()) {
    bool ok = false;
    for (auto a : allowed) ok = ok || a == key;
    if (!ok) {
      std::string list;
      for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      diags_->Error(Child(key), "unknown field \"" + key + "\" (allowed: " + list + ")");
    }
  }
}

bool ObjectReader::Has(const std::string& key) const { return valid_ && j_->contains(key); }

const Json* ObjectReader::Get(const std::string& key) const {
  if (!valid_) return nullptr;
  auto it = j_->find(key);
  return it == j_->end() ? nullptr : &*it;
}

std::optional<std::string> ObjectReader::String(const std::string& key, bool required) const {
  const Json* v = Get(key);
  if (!v) {
    if (required && valid_) diags_->Error(Child(key), "missing required field \"" + key + "\"");
    return std::nullopt;
  }
  if (!v->is_string()) {
    diags_->Error(Child(key), std::string("expected a string, got ") + JsonTypeName(*v));
    return std::nullopt;
  }
  return v->get<std::string>();
}

std::optional<double> ObjectReader::NonNegative(const std::string& key, bool required) const {
  const Json* v = Get(key);
  if (!v) {
    if (required && valid_) diags_->Error(Child(key), "missing required field \"" + key + "\"");
    return std::nullopt;
  }
  return AsNonNegative(*v, Child(key), *diags_);
}

std::optional<bool> ObjectReader::Bool(const std::string& key, bool required) const {
  const Json* v = Get(key);
  if (!v) {
    if (required && valid_) diags_->Error(Child(key), "missing required field \"" + key + "\"");
    return std::nullopt;
  }
  if (!v->is_boolean()) {
    diags_->Error(Child(key), std::string("expected a boolean, got ") + JsonTypeName(*v));
    return std::nullopt;
  }
  return v->get<bool>();
}

}  // namespace ctb
