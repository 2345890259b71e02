// What a route answers, and how it goes on the wire. A route's answer is a value: a JSON document
// with its status and headers, or an Error (written as {"error": {...}} with the code's HTTP
// status). The plain HTTP path writes it once with Send(); a stream (server/stream.h) sends the
// same document as its last event's data, never reading its own text back.
#pragma once

#include <httplib.h>

#include <string>
#include <variant>

#include "planner/model/error.h"
#include "planner/model/json_io.h"

namespace ctb::server {

// A document answered with `status`, plus headers of its own (e.g. Server-Timing). A stream
// sends only the document: its head has gone out before the route ran.
struct JsonReply {
  int status = 200;
  Json body;
  httplib::Headers headers = {};
};

using RouteAnswer = std::variant<JsonReply, Error>;

// The error's object: {"code", "message", "limit"?, "request_id"?, "path"?, "details"?};
// request_id only when not empty, path and details only when the error has details.
Json ErrorObject(const Error& e, const std::string& request_id);

// `j` as the body with `status`. Text from an LLM or an upstream error may hold invalid UTF-8:
// replaced, never thrown.
void SendJson(httplib::Response& res, int status, const Json& j);

// {"error": ErrorObject(e, the response's X-Request-Id)} with the code's HTTP status; busy and
// unavailable get Retry-After (2 s, 1 s), unauthenticated gets WWW-Authenticate.
void SendError(httplib::Response& res, const Error& e);

// A route's answer: the reply's headers and document, or SendError().
void Send(httplib::Response& res, const RouteAnswer& answer);

}  // namespace ctb::server
