// Talking to a running ctburton server (the `--server URL` mode of the CLI).
#pragma once

#include <optional>
#include <string>
#include <variant>

#include "planner/model/error.h"
#include "planner/model/json_io.h"

namespace ctb::cli {

// POSTs body to URL + path; returns the JSON answer of a 2xx, or the server's error (its
// {"error": {...}} turned back into an Error with the HTTP status's code), or a connection
// error (kUnavailable).
std::variant<Json, Error> PostJson(const std::string& server, const std::string& path,
                                   const Json& body, long timeout_ms);

// A request body's domain from a --domain flag: a path (it has a '/' or ".json") is read and sent
// as "action_model", anything else as the name "domain". An Error when the file cannot be read.
std::optional<Error> AddDomain(Json& body, const std::string& domain);

}  // namespace ctb::cli
