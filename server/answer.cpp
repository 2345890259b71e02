#include "server/answer.h"

#include "planner/model/json_io.h"
#include "app/budget.h"

namespace ctb::server {

Json ErrorObject(const Error& e, const std::string& request_id) {
  Json err = {{"code", CodeName(e.code)}, {"message", e.message}};
  if (e.limit) err["limit"] = app::LimitJson(*e.limit);
  if (!request_id.empty()) err["request_id"] = request_id;
  if (!e.details.empty()) {
    err["path"] = e.details[0].pointer.empty() ? "/" : e.details[0].pointer;
    Json details = Json::array();
    for (const auto& d : e.details) {
      Json x = {{"path", d.pointer.empty() ? "/" : d.pointer}, {"message", d.message}};
      if (d.offset) x["offset"] = *d.offset;
      details.push_back(x);
    }
    err["details"] = details;
  }
  return err;
}

void SendJson(httplib::Response& res, int status, const Json& j) {
  res.status = status;
  res.set_content(WireText(j), "application/json");
}

void SendError(httplib::Response& res, const Error& e) {
  if (e.code == ErrorCode::kBusy) res.set_header("Retry-After", "2");
  if (e.code == ErrorCode::kUnavailable) res.set_header("Retry-After", "1");
  if (e.code == ErrorCode::kUnauthenticated) res.set_header("WWW-Authenticate", "Bearer");
  const Json err = ErrorObject(e, res.get_header_value("X-Request-Id"));
  SendJson(res, HttpStatus(e.code), {{"error", err}});
}

void Send(httplib::Response& res, const RouteAnswer& answer) {
  if (const auto* e = std::get_if<Error>(&answer)) return SendError(res, *e);
  const auto& reply = std::get<JsonReply>(answer);
  for (const auto& [name, value] : reply.headers) res.set_header(name, value);
  SendJson(res, reply.status, reply.body);
}

}  // namespace ctb::server
