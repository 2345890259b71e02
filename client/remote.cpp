#include "client/remote.h"

#include <httplib.h>

namespace ctb::cli {

std::variant<Json, Error> PostJson(const std::string& server, const std::string& path,
                                   const Json& body, long timeout_ms) {
  httplib::Client cli(server);
  cli.set_connection_timeout(5, 0);
  cli.set_read_timeout(timeout_ms / 1000 + 30, 0);
  cli.set_write_timeout(30, 0);
  auto res = cli.Post(path.c_str(), body.dump(), "application/json");
  if (!res)
    return Error{ErrorCode::kUnavailable,
                 "cannot reach " + server + ": " + httplib::to_string(res.error()), {}};
  Json j = Json::parse(res->body, nullptr, false);
  if (res->status / 100 == 2 && !j.is_discarded()) return j;  // 200, or 201 (created)
  Error e{ErrorCode::kInternal, "server answered HTTP " + std::to_string(res->status), {}};
  if (j.is_object() && j.contains("error") && j["error"].is_object()) {
    const Json& err = j["error"];
    e.message = err.value("message", e.message) + " (HTTP " + std::to_string(res->status) + ")";
    if (err.contains("details") && err["details"].is_array())
      for (const auto& d : err["details"])
        e.details.push_back({d.value("path", ""),
                             d.contains("offset") ? std::optional<std::size_t>(d["offset"].get<std::size_t>()) : std::nullopt,
                             d.value("message", "")});
  }
  switch (res->status) {
    case 400: e.code = ErrorCode::kInvalidInput; break;
    case 404: e.code = ErrorCode::kNotFound; break;
    case 413: e.code = ErrorCode::kTooLarge; break;
    case 422: e.code = ErrorCode::kUnprocessable; break;
    case 502: e.code = ErrorCode::kUpstreamFailed; break;
    case 503: e.code = ErrorCode::kUnavailable; break;
    case 504: e.code = ErrorCode::kUpstreamTimeout; break;
    default: break;
  }
  return e;
}

std::optional<Error> AddDomain(Json& body, const std::string& domain) {
  if (domain.find('/') == std::string::npos && domain.find(".json") == std::string::npos) {
    body["domain"] = domain;
    return std::nullopt;
  }
  Diagnostics d;
  auto dom = ReadJsonFile(domain, d);
  if (!dom) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "cannot read " + domain, d);
  body["action_model"] = *dom;
  return std::nullopt;
}

}  // namespace ctb::cli
