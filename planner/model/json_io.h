// Strict JSON input: parsing untrusted text, and reading objects field by field with every
// problem reported at its JSON pointer.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "planner/model/error.h"

namespace ctb {

using Json = nlohmann::json;

struct ParseLimits {
  std::size_t max_bytes = 4 * 1024 * 1024;
  int max_depth = 64;
};

// Files a local user hands the command line (their own disk, not an untrusted body): 256 MiB,
// room for an imported PDDL model (IPC parking: 71 MB). The HTTP front end keeps its own limits.
inline ParseLimits LocalFileLimits() { return {std::size_t{256} << 20, 64}; }

// Parses text as one JSON document. Rejects (with a diagnostic at pointer "" and the byte
// offset): empty input, syntax errors, NaN/Infinity, numbers that overflow a double, nesting
// deeper than limits.max_depth, duplicate keys in an object, invalid UTF-8, and input longer
// than limits.max_bytes. Returns nullopt on any error. Never throws.
std::optional<Json> ParseJsonStrict(std::string_view text, Diagnostics& diags,
                                    const ParseLimits& limits = {});

// Reads a file and parses it strictly; errors name the file.
std::optional<Json> ReadJsonFile(const std::string& path, Diagnostics& diags,
                                 const ParseLimits& limits = {});

// The text of every answer the service gives (HTTP bodies, SSE event data, the CLI's --compact):
// one line, no spaces, invalid UTF-8 replaced (text from an LLM may hold some), never throws.
std::string WireText(const Json& j);
// The same document indented by two spaces, as the CLI prints it by default.
std::string PrettyText(const Json& j);

// A view of one JSON object that knows its pointer. Each getter records an error (wrong type,
// missing required field, non-finite or negative number) and returns nullopt; CheckKeys reports
// every field not in the allowed list.
class ObjectReader {
 public:
  // Records an error and leaves the reader invalid when j is not an object.
  ObjectReader(const Json& j, std::string pointer, Diagnostics& diags);
  bool valid() const { return valid_; }
  const std::string& pointer() const { return pointer_; }
  std::string Child(const std::string& key) const { return pointer_ + "/" + PointerToken(key); }

  void CheckKeys(std::initializer_list<std::string_view> allowed) const;
  bool Has(const std::string& key) const;
  const Json* Get(const std::string& key) const;  // nullptr when absent

  std::optional<std::string> String(const std::string& key, bool required) const;
  // A finite number >= 0.
  std::optional<double> NonNegative(const std::string& key, bool required) const;
  std::optional<bool> Bool(const std::string& key, bool required) const;

 private:
  const Json* j_;
  std::string pointer_;
  Diagnostics* diags_;
  bool valid_;
};

// "object", "array", "string", "number", "boolean", "null" for error messages.
const char* JsonTypeName(const Json& j);

// Checks that a number value is finite and >= 0; records an error at pointer otherwise.
std::optional<double> AsNonNegative(const Json& j, const std::string& pointer, Diagnostics& diags);

}  // namespace ctb
