#include "server/http_front.h"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <chrono>

#include "app/ids.h"
#include "server/answer.h"
#include "server/conn_watch.h"
#include "server/limits.h"
#include "server/log_context.h"
#include "server/openapi_json.h"
#include "server/stream.h"
#include "server/worker_pool.h"
#include "translator/text.h"

namespace ctb::server {

namespace {
// cpp-httplib's task queue on our WorkerPool (server/worker_pool.h): threads on demand, the last
// idle one reused first, idle ones retired, so glibc's per-thread caches stay few.
class PoolQueue : public httplib::TaskQueue {
 public:
  explicit PoolQueue(int max_threads) : pool_({max_threads, std::chrono::seconds(30)}) {}
  void enqueue(std::function<void()> fn) override { pool_.Enqueue(std::move(fn)); }
  void shutdown() override { pool_.Shutdown(); }

 private:
  WorkerPool pool_;
};

using Clock = std::chrono::steady_clock;
using app::Core;

bool SaneRequestId(const std::string& id) {
  if (id.empty() || id.size() > 64) return false;
  for (char c : id)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.'))
      return false;
  return true;
}

Error Bad(const std::string& msg, const std::string& path) {
  return {ErrorCode::kInvalidInput, msg, {{path, std::nullopt, msg}}};
}

// The request's keys must be among `allowed`.
std::optional<Error> CheckKeys(const Json& body, std::initializer_list<std::string_view> allowed) {
  Diagnostics d;
  ObjectReader(body, "", d).CheckKeys(allowed);
  if (!d.ok()) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid request", d);
  return std::nullopt;
}

// An optional string field.
std::variant<std::optional<std::string>, Error> OptString(const Json& body, const char* key,
                                                          const std::string& message) {
  if (!body.contains(key)) return std::optional<std::string>();
  if (!body[key].is_string()) return Bad(message, std::string("/") + key);
  return std::optional<std::string>(body[key].get<std::string>());
}

std::variant<app::DomainRef, Error> DomainOf(const Json& body) {
  app::DomainRef ref;
  auto name = OptString(body, "domain", "\"domain\" must be a string");
  if (auto* e = std::get_if<Error>(&name)) return *e;
  ref.name = std::get<std::optional<std::string>>(name);
  if (body.contains("action_model")) ref.action_model = body["action_model"];
  return ref;
}

std::variant<app::RequestOptions, Error> OptionsOf(const Json& body) {
  if (!body.contains("options")) return app::RequestOptions{};
  return app::ParseRequestOptions(body["options"]);
}

}  // namespace

class HttpFrontEnd::Impl {
 public:
  Impl(const ServerConfig& cfg, Core& core, const app::ApiKeys* keys)
      : cfg_(cfg), core_(core), keys_(keys) {
    Routes();
  }

  int Bind() {
    int port = cfg_.port == 0 ? svr_.bind_to_any_port(cfg_.host)
                              : (svr_.bind_to_port(cfg_.host, cfg_.port) ? cfg_.port : -1);
    if (port >= 0 && !svr_.RaiseBacklog())
      spdlog::warn("{}", app::LogText("cannot raise the listen backlog; bursts of connections may wait"));
    return port;
  }
  void Listen() { svr_.listen_after_bind(); }
  void Stop() { svr_.stop(); }
  int InFlight() const { return in_flight_; }
  void SetDraining() { draining_ = true; }

 private:
  // Wraps a handler: access control, in-flight count, metrics, one JSON log line, a last-resort
  // exception guard.
  httplib::Server::Handler Wrap(const std::string& route,
                                std::function<void(const httplib::Request&, httplib::Response&)> fn,
                                bool needs_key = true) {
    return [this, route, fn, needs_key](const httplib::Request& req, httplib::Response& res) {
      auto t0 = Clock::now();
      ++in_flight_;
      SetThreadRequestId(res.get_header_value("X-Request-Id"));
      try {
        if (needs_key && keys_ && !keys_->CheckHeader(req.get_header_value("Authorization")))
          SendError(res, {ErrorCode::kUnauthenticated,
                          "this server needs an API key: send \"Authorization: Bearer KEY\"", {}});
        else
          fn(req, res);
      } catch (const std::exception& e) {
        spdlog::error("{}", app::LogText("unhandled exception in " + route + ": " + e.what()));
        SendError(res, {ErrorCode::kInternal, "internal error", {}});
      }
      --in_flight_;
      if (res.status == -1) res.status = 200;
      double secs = std::chrono::duration<double>(Clock::now() - t0).count();
      core_.metrics().Request(route, res.status, secs);
      spdlog::info("{}", Json({{"event", "request"}, {"method", req.method}, {"path", req.path},
                               {"route", route}, {"status", res.status},
                               {"ms", std::lround(secs * 1000)}})
                             .dump(-1, ' ', false, Json::error_handler_t::replace));
      SetThreadRequestId("");
    };
  }

  // The body as a JSON object, or an error already sent.
  std::optional<Json> Body(const httplib::Request& req, httplib::Response& res) {
    // Before the JSON parser: its messages quote the input, and bytes that are not UTF-8 could
    // not be sent back. A NUL is never part of a JSON text.
    if (auto at = InvalidUtf8Offset(req.body)) {
      const std::string where = "byte offset " + std::to_string(*at);
      SendError(res, {ErrorCode::kInvalidInput, "request body is not valid UTF-8 (" + where + ")",
                      {{"/", *at, "invalid UTF-8 at " + where}}});
      return std::nullopt;
    }
    if (auto nul = req.body.find('\0'); nul != std::string::npos) {
      const std::string where = "byte offset " + std::to_string(nul);
      SendError(res, {ErrorCode::kInvalidInput, "request body contains a NUL byte (" + where + ")",
                      {{"/", nul, "NUL byte at " + where}}});
      return std::nullopt;
    }
    Diagnostics d;
    ParseLimits limits;
    limits.max_bytes = static_cast<std::size_t>(BodyLimit(req.path));
    auto j = ParseJsonStrict(req.body, d, limits);
    if (!j) {
      SendError(res, Error::FromDiagnostics(ErrorCode::kInvalidInput, "request body is not valid JSON", d));
      return std::nullopt;
    }
    if (!j->is_object()) {
      SendError(res, Bad("request body must be a JSON object", "/"));
      return std::nullopt;
    }
    return j;
  }

  // The call's context: the observer (streaming) and a cancel check that sees the client leave.
  app::CallContext Context(const httplib::Request& req, app::Observer* observer) {
    app::CallContext ctx;
    ctx.observer = observer;
    ctx.request_id = ThreadRequestId();
    const int local_port = req.local_port, remote_port = req.remote_port;
    const std::string rid = ctx.request_id;
    ctx.cancelled = [local_port, remote_port, rid, logged = false]() mutable {
      if (ClientConnected(local_port, remote_port)) return false;
      if (!logged) {
        SetThreadRequestId(rid);
        spdlog::info("{}", Json({{"event", "client_gone"}, {"remote_port", remote_port}}).dump());
        logged = true;
      }
      return true;
    };
    return ctx;
  }

  RouteAnswer HandleSolve(const httplib::Request& req, const Json& body, app::Observer* obs) {
    if (auto e = CheckKeys(body, {"domain", "action_model", "state_plan", "options"})) return *e;
    app::SolveCall call;
    auto dom = DomainOf(body);
    if (auto* e = std::get_if<Error>(&dom)) return *e;
    call.domain = std::get<app::DomainRef>(dom);
    if (body.contains("state_plan")) call.state_plan = body["state_plan"];
    auto opts = OptionsOf(body);
    if (auto* e = std::get_if<Error>(&opts)) return *e;
    call.options = std::get<app::RequestOptions>(opts);
    auto r = core_.Solve(call, Context(req, obs));
    if (auto* e = std::get_if<Error>(&r)) return *e;
    const auto& a = std::get<app::Answer>(r);
    JsonReply reply{200, a.document};
    if (auto t = a.metrics.find("core_ms"); t != a.metrics.end())
      reply.headers.emplace("Server-Timing", "core;dur=" + t->second);
    return reply;
  }

  // POST /replan (contract section 11): in a session, or with domain/action_model, state_plan
  // and trajectory; options may carry "keep".
  RouteAnswer HandleReplan(const httplib::Request& req, const Json& body, app::Observer* obs) {
    if (auto e = CheckKeys(body, {"session", "domain", "action_model", "state_plan", "trajectory",
                                   "now", "executed", "observed", "blocked", "options", "stream",
                                   "command"}))
      return *e;
    app::ReplanCall call;
    auto command = OptString(body, "command", "\"command\" must be a string: what happened, in words");
    if (auto* e = std::get_if<Error>(&command)) return *e;
    call.command = std::get<std::optional<std::string>>(command);
    auto session = OptString(body, "session", "\"session\" must be a string");
    if (auto* e = std::get_if<Error>(&session)) return *e;
    call.session = std::get<std::optional<std::string>>(session);
    if (!call.session) {
      auto dom = DomainOf(body);
      if (auto* e = std::get_if<Error>(&dom)) return *e;
      call.domain = std::get<app::DomainRef>(dom);
    } else if (body.contains("domain") || body.contains("action_model")) {
      return Bad("a session replans its own domain", "/domain");
    }
    if (body.contains("state_plan")) call.state_plan = body["state_plan"];
    call.request = Json::object();
    for (const char* k : {"now", "executed", "observed", "blocked", "trajectory"})
      if (body.contains(k)) call.request[k] = body[k];
    auto opts = app::ParseReplanOptions(body.value("options", Json::object()));
    if (auto* e = std::get_if<Error>(&opts)) return *e;
    call.options = std::get<app::ReplanRequestOptions>(opts).options;
    call.keep = std::get<app::ReplanRequestOptions>(opts).keep;
    auto r = core_.Replan(call, Context(req, obs));
    if (auto* e = std::get_if<Error>(&r)) return *e;
    return JsonReply{200, std::get<app::Answer>(r).document};
  }

  void HandleValidate(const httplib::Request& req, httplib::Response& res) {
    auto body = Body(req, res);
    if (!body) return;
    if (auto e = CheckKeys(*body, {"domain", "action_model", "state_plan"})) return SendError(res, *e);
    app::SolveCall call;
    auto dom = DomainOf(*body);
    if (auto* e = std::get_if<Error>(&dom)) return SendError(res, *e);
    call.domain = std::get<app::DomainRef>(dom);
    if (body->contains("state_plan")) call.state_plan = (*body)["state_plan"];
    auto r = core_.Validate(call);
    if (auto* e = std::get_if<Error>(&r)) return SendError(res, *e);
    SendJson(res, 200, {{"valid", true}, {"warnings", std::get<app::ValidateAnswer>(r).WarningsJson()}});
  }

  void HandleTranslate(const httplib::Request& req, httplib::Response& res) {
    auto body = Body(req, res);
    if (!body) return;
    if (auto e = CheckKeys(*body, {"domain", "command", "prompting"})) return SendError(res, *e);
    app::TranslateCall call;
    auto dom = DomainOf(*body);
    if (auto* e = std::get_if<Error>(&dom)) return SendError(res, *e);
    call.domain = std::get<app::DomainRef>(dom);
    call.command = body->value("command", Json());
    auto p = OptString(*body, "prompting", "\"prompting\" must be cot or direct");
    if (auto* e = std::get_if<Error>(&p)) return SendError(res, *e);
    call.prompting = std::get<std::optional<std::string>>(p);
    auto r = core_.Translate(call, Context(req, nullptr));
    if (auto* e = std::get_if<Error>(&r)) return SendError(res, *e);
    const auto& t = std::get<app::TranslateAnswer>(r);
    Json out = {{"state_plan", t.state_plan}, {"reasoning", t.reasoning}};
    if (!t.warnings.empty()) out["warnings"] = t.warnings;
    SendJson(res, 200, out);
  }

  // POST /eval (contract section 15): {"suite", "prompting"?, "time_limit_ms"?} ->
  // {"items": [...], "totals": {...}}; streamed, each item as an `item` event.
  RouteAnswer HandleEval(const httplib::Request& req, const Json& body, app::Observer* obs) {
    if (auto e = CheckKeys(body, {"suite", "prompting", "time_limit_ms"})) return *e;
    app::EvalCall call;
    if (!body.contains("suite")) return Bad("missing required field \"suite\"", "/suite");
    call.suite = body["suite"];
    call.pointer = "/suite";
    auto p = OptString(body, "prompting", "\"prompting\" must be cot or direct");
    if (auto* e = std::get_if<Error>(&p)) return *e;
    call.prompting = std::get<std::optional<std::string>>(p);
    if (body.contains("time_limit_ms")) {
      const Json& t = body["time_limit_ms"];
      if (!t.is_number_integer()) return Bad("\"time_limit_ms\" must be an integer", "/time_limit_ms");
      call.time_limit_ms = t.get<long>();
    }
    Json items = Json::array();
    auto r = core_.Eval(call, Context(req, obs), [&items](const Json& line) { items.push_back(line); });
    if (auto* e = std::get_if<Error>(&r)) return *e;
    return JsonReply{200, {{"items", items}, {"totals", std::get<Json>(r)}}};
  }

  RouteAnswer HandlePlan(const httplib::Request& req, const Json& body, app::Observer* obs) {
    if (auto e = CheckKeys(body, {"domain", "command", "prompting", "session", "options"}))
      return *e;
    app::PlanCall call;
    for (auto [key, out, msg] :
         {std::tuple{"domain", &call.domain, "\"domain\" must be a string"},
          std::tuple{"prompting", &call.prompting, "\"prompting\" must be cot or direct"},
          std::tuple{"session", &call.session, "\"session\" must be a string"}}) {
      auto v = OptString(body, key, msg);
      if (auto* e = std::get_if<Error>(&v)) return *e;
      *out = std::get<std::optional<std::string>>(v);
    }
    call.command = body.value("command", Json());
    auto opts = OptionsOf(body);
    if (auto* e = std::get_if<Error>(&opts)) return *e;
    call.options = std::get<app::RequestOptions>(opts);
    auto r = core_.Plan(call, Context(req, obs));
    if (auto* e = std::get_if<Error>(&r)) return *e;
    const auto& p = std::get<app::PlanAnswer>(r);
    Json out = {{"state_plan", p.translation.state_plan}, {"reasoning", p.translation.reasoning},
                {"trajectory", p.answer.document}, {"session", p.session}};
    if (!p.translation.warnings.empty()) out["warnings"] = p.translation.warnings;
    return JsonReply{200, out};
  }

  // The body limit of a route: /networks/check takes networks of 10,000 points (4 MiB).
  long BodyLimit(const std::string& path) const {
    return path == "/networks/check" ? cfg_.max_network_body_bytes : cfg_.max_body_bytes;
  }
  long LargestBodyLimit() const { return std::max(cfg_.max_body_bytes, cfg_.max_network_body_bytes); }

  void SetUpServer() {
    svr_.set_tcp_nodelay(true);  // headers and body go out in two writes: no 40 ms Nagle stall
    svr_.set_read_timeout(cfg_.read_timeout_s, 0);
    svr_.set_write_timeout(cfg_.write_timeout_s, 0);
    svr_.set_payload_max_length(static_cast<std::size_t>(LargestBodyLimit()));
    // Connections are admitted, timed and checked by GuardedServer (server/limits.h). The pool has
    // more threads than admitted connections, so a refusal or /healthz never waits for a thread.
    ConnectionLimits limits;
    limits.per_address = cfg_.max_connections_per_address;
    limits.total = cfg_.max_connections;
    limits.head_timeout_ms = cfg_.read_timeout_s * 1000L;
    limits.body_timeout_ms = cfg_.body_timeout_s * 1000L;
    limits.keep_alive_ms = cfg_.keep_alive_s * 1000L;
    limits.max_body_bytes = LargestBodyLimit();  // per route in the pre-routing handler
    svr_.SetLimits(limits);
    svr_.set_keep_alive_timeout(cfg_.keep_alive_s);
    const int threads = cfg_.max_connections + 16;
    svr_.new_task_queue = [threads] { return new PoolQueue(threads); };
    svr_.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      std::string id = req.get_header_value("X-Request-Id");
      res.set_header("X-Request-Id", SaneRequestId(id) ? id : app::RandomHex(8));
      // Chunked bodies would dodge the length limit (cpp-httplib 0.11): refuse them.
      if (req.has_header("Transfer-Encoding")) {
        SendError(res, {ErrorCode::kTooLarge, "chunked request bodies are not accepted; send Content-Length", {}});
        res.status = 411;
        core_.metrics().Request("(refused)", 411, 0);
        return httplib::Server::HandlerResponse::Handled;
      }
      if (req.has_header("Content-Length") &&
          std::atoll(req.get_header_value("Content-Length").c_str()) > BodyLimit(req.path)) {
        SendError(res, {ErrorCode::kTooLarge, "request body larger than " + std::to_string(BodyLimit(req.path)) + " bytes", {}});
        core_.metrics().Request("(refused)", 413, 0);
        return httplib::Server::HandlerResponse::Handled;
      }
      return httplib::Server::HandlerResponse::Unhandled;
    });
    svr_.set_error_handler([](const httplib::Request&, httplib::Response& res) {
      if (!res.body.empty()) return;
      if (res.status == 414) {  // normally refused earlier, by GuardedServer
        res.set_content(Json({{"error", {{"code", "uri_too_long"}, {"message", "request line too long"}}}}).dump(),
                        "application/json");
        return;
      }
      Error e{ErrorCode::kNotFound, "no such route", {}};
      if (res.status == 413) e = {ErrorCode::kTooLarge, "request body too large", {}};
      else if (res.status == 400) e = {ErrorCode::kInvalidInput, "malformed request", {}};
      else if (res.status != 404) e = {ErrorCode::kInternal, "request failed", {}};
      int status = res.status;
      SendError(res, e);
      res.status = status;
    });
  }

  // Contract section 12: shipped and stored domains, their diagrams, drafts from words.
  // Executions (contract section 14).
  void ExecutionRoutes() {
    svr_.Post("/executions", Wrap("/executions", [this](auto& q, auto& s) {
      auto body = Body(q, s);
      if (!body) return;
      auto call = ExecutionCallOf(*body);
      if (auto* e = std::get_if<Error>(&call)) return SendError(s, *e);
      app::CallContext ctx;
      ctx.request_id = s.get_header_value("X-Request-Id");
      auto r = core_.StartExecution(std::get<app::ExecutionCall>(call), ctx);
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      s.set_header("Location", "/executions/" + std::get<std::string>(r));
      SendJson(s, 201, {{"execution", std::get<std::string>(r)}});
    }));
    svr_.Get(R"(/executions/([^/]{1,256}))", Wrap("/executions/{id}", [this](auto& q, auto& s) {
      auto r = core_.GetExecution(q.matches[1]);
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      SendJson(s, 200, std::get<Json>(r));
    }));
    svr_.Delete(R"(/executions/([^/]{1,256}))", Wrap("/executions/{id}", [this](auto& q, auto& s) {
      if (auto e = core_.StopExecution(q.matches[1])) return SendError(s, *e);
      auto r = core_.GetExecution(q.matches[1]);
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      SendJson(s, 200, {{"execution", q.matches[1]}, {"state", std::get<Json>(r)["state"]}});
    }));
    svr_.Put(R"(/executions/([^/]{1,256})/state_plan)", Wrap("/executions/{id}/state_plan", [this](auto& q, auto& s) {
      auto body = Body(q, s);
      if (!body) return;
      if (auto e = core_.ChangeExecutionStatePlan(q.matches[1], *body)) return SendError(s, *e);
      SendJson(s, 200, {{"execution", q.matches[1]}, {"replanning", true}});
    }));
    svr_.Post(R"(/executions/([^/]{1,256})/reports)", Wrap("/executions/{id}/reports", [this](auto& q, auto& s) {
      auto body = Body(q, s);
      if (!body) return;
      auto r = core_.ReportExecution(q.matches[1], *body);
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      SendJson(s, 200, std::get<Json>(r));
    }));
    svr_.Get(R"(/executions/([^/]{1,256})/events)", Wrap("/executions/{id}/events", [this](auto& q, auto& s) {
      const std::string id = q.matches[1];
      bool ended = false;
      auto first = core_.ExecutionEvents(id, 0, 0, &ended);
      if (auto* e = std::get_if<Error>(&first)) return SendError(s, *e);
      long after = 0;
      if (auto last = q.get_header_value("Last-Event-ID"); !last.empty() && last.size() < 18 &&
          last.find_first_not_of("0123456789") == std::string::npos)
        after = std::stol(last);
      s.set_header("Cache-Control", "no-cache");
      s.set_chunked_content_provider("text/event-stream", [this, id, after](size_t, httplib::DataSink& sink) mutable {
        bool done = false;
        auto r = core_.ExecutionEvents(id, after, 10000, &done);
        std::string out;
        if (auto* e = std::get_if<Error>(&r)) {
          out = "event: error\ndata: " + Json{{"message", e->message}}.dump() + "\n\n";
          done = true;
        } else {
          for (const auto& ev : std::get<std::vector<app::ExecutionEvent>>(r)) {
            out += "id: " + std::to_string(ev.seq) + "\nevent: " + ev.name + "\ndata: " +
                   WireText(ev.data) + "\n\n";
            after = ev.seq;
          }
          if (out.empty() && !done) out = ": waiting\n\n";  // keeps proxies and dead peers honest
        }
        if (!sink.write(out.data(), out.size())) return false;
        if (done) sink.done();
        return true;
      });
    }));
  }

  // The body of POST /executions as a call; unknown or mistyped fields at their pointers.
  static std::variant<app::ExecutionCall, Error> ExecutionCallOf(const Json& body) {
    if (!body.is_object()) return Bad("the body must be a JSON object", "/");
    if (auto e = CheckKeys(body, {"session", "domain", "action_model", "state_plan", "trajectory",
                                  "adapter", "speed", "sim", "replan", "options"}))
      return *e;
    app::ExecutionCall call;
    auto session = OptString(body, "session", "\"session\" must be a string");
    if (auto* e = std::get_if<Error>(&session)) return *e;
    call.session = std::get<std::optional<std::string>>(session);
    auto ref = DomainOf(body);
    if (auto* e = std::get_if<Error>(&ref)) return *e;
    call.domain = std::get<app::DomainRef>(ref);
    if (!call.session && !call.domain.name && !call.domain.action_model)
      return Bad("give \"session\", or \"domain\" or \"action_model\" with \"state_plan\"", "/domain");
    if (body.contains("state_plan")) call.state_plan = body["state_plan"];
    if (!call.session && call.state_plan.is_null()) return Bad("missing \"state_plan\"", "/state_plan");
    if (body.contains("trajectory")) {
      if (!body["trajectory"].is_object()) return Bad("\"trajectory\" must be a trajectory object", "/trajectory");
      call.trajectory = body["trajectory"];
    }
    auto adapter = OptString(body, "adapter", "\"adapter\" must be sim, mqtt, grpc or external");
    if (auto* e = std::get_if<Error>(&adapter)) return *e;
    call.adapter = std::get<std::optional<std::string>>(adapter).value_or("");
    if (body.contains("replan")) {
      if (!body["replan"].is_boolean()) return Bad("\"replan\" must be true or false", "/replan");
      call.replan = body["replan"].get<bool>();
    }
    if (body.contains("speed")) {
      if (!body["speed"].is_number()) return Bad("\"speed\" must be a number", "/speed");
      call.speed = body["speed"].get<double>();
    }
    if (body.contains("sim")) call.sim = body["sim"];
    auto opts = OptionsOf(body);
    if (auto* e = std::get_if<Error>(&opts)) return *e;
    call.options = std::get<app::RequestOptions>(opts);
    return call;
  }

  void DomainRoutes() {
    svr_.Get("/domains", Wrap("/domains", [this](auto&, auto& s) {
      auto r = core_.ListDomains();
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      Json list = Json::array();
      for (const auto& d : std::get<std::vector<app::DomainInfo>>(r)) {
        Json item = {{"name", d.name}, {"description", d.description}, {"automata", d.automata},
                     {"source", d.source}};
        if (d.source == "stored") item["version"] = d.version;
        list.push_back(std::move(item));
      }
      SendJson(s, 200, {{"domains", list}});
    }));
    svr_.Post("/domains", Wrap("/domains", [this](auto& q, auto& s) {
      auto body = Body(q, s);
      if (!body) return;
      auto r = core_.CreateDomain(*body);
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      const std::string& name = std::get<std::string>(r);
      s.set_header("Location", "/domains/" + name);
      SendJson(s, 201, {{"name", name}});
    }));
    svr_.Post("/domains/draft", Wrap("/domains/draft", [this](auto& q, auto& s) {
      auto body = Body(q, s);
      if (!body) return;
      if (auto e = CheckKeys(*body, {"description"})) return SendError(s, *e);
      auto d = body->find("description");
      if (d == body->end() || !d->is_string())
        return SendError(s, Bad("\"description\" must be a string: the team in plain words", "/description"));
      auto r = core_.DraftDomain(d->template get<std::string>(), Context(q, nullptr));
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      SendJson(s, 200, std::get<app::DraftAnswer>(r).document);
    }));
    // PDDL in, an action model out (issue 32): {"domain": PDDL text, "problem"?: PDDL text,
    // "name"?, "store"?: false}; 201 with Location when stored, else 200.
    svr_.Post("/domains/import-pddl", Wrap("/domains/import-pddl", [this](auto& q, auto& s) {
      auto body = Body(q, s);
      if (!body) return;
      if (auto e = CheckKeys(*body, {"domain", "problem", "name", "store"})) return SendError(s, *e);
      app::PddlImportCall call;
      auto domain = OptString(*body, "domain", "\"domain\" must be the PDDL domain as a string");
      auto problem = OptString(*body, "problem", "\"problem\" must be the PDDL problem as a string");
      auto name = OptString(*body, "name", "\"name\" must be a string");
      for (auto* v : {&domain, &problem, &name})
        if (auto* e = std::get_if<Error>(v)) return SendError(s, *e);
      call.domain = std::get<std::optional<std::string>>(domain).value_or("");
      call.problem = std::get<std::optional<std::string>>(problem).value_or("");
      call.name = std::get<std::optional<std::string>>(name).value_or("");
      if (body->contains("store")) {
        if (!(*body)["store"].is_boolean()) return SendError(s, Bad("\"store\" must be true or false", "/store"));
        call.store = (*body)["store"].template get<bool>();
      }
      auto r = core_.ImportPddl(call);
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      const auto& a = std::get<app::PddlImportAnswer>(r);
      if (a.stored) s.set_header("Location", "/domains/" + a.action_model.value("name", ""));
      SendJson(s, a.stored ? 201 : 200, a.ToJson());
    }));
    svr_.Get(R"(/domains/([A-Za-z0-9_]+))", Wrap("/domains/{name}", [this](auto& q, auto& s) {
      const std::string expand = q.get_param_value("expand");
      if (!expand.empty() && expand != "true" && expand != "false")
        return SendError(s, {ErrorCode::kInvalidInput, "the query parameter expand must be true or false", {}});
      auto r = core_.GetDomain(q.matches[1], expand != "true");
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      SendJson(s, 200, std::get<Json>(r));
    }));
    svr_.Put(R"(/domains/([A-Za-z0-9_]+))", Wrap("/domains/{name}", [this](auto& q, auto& s) {
      auto body = Body(q, s);
      if (!body) return;
      const std::string name = q.matches[1];
      if (auto e = core_.ReplaceDomain(name, *body)) return SendError(s, *e);
      SendJson(s, 200, {{"name", name}});
    }));
    svr_.Delete(R"(/domains/([A-Za-z0-9_]+))", Wrap("/domains/{name}", [this](auto& q, auto& s) {
      const std::string force = q.get_param_value("force");
      if (!force.empty() && force != "true" && force != "false")
        return SendError(s, {ErrorCode::kInvalidInput, "the query parameter force must be true or false", {}});
      if (auto e = core_.DeleteDomain(q.matches[1], force == "true")) return SendError(s, *e);
      s.status = 204;
    }));
    svr_.Get(R"(/domains/([A-Za-z0-9_]+)/durations)", Wrap("/domains/{name}/durations", [this](auto& q, auto& s) {
      auto r = core_.DomainDurations(q.matches[1]);
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      SendJson(s, 200, std::get<Json>(r));
    }));
    svr_.Get(R"(/domains/([A-Za-z0-9_]+)/diagram)", Wrap("/domains/{name}/diagram", [this](auto& q, auto& s) {
      auto r = core_.DomainDiagram(q.matches[1]);
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      s.set_content(std::get<std::string>(r), "image/svg+xml");
    }));
  }

  // A stream reserves its solver place before its 200 head goes out (server/stream.h).
  std::function<std::shared_ptr<app::JobTicket>()> Reserver() {
    return [this] { return core_.ReserveJob(); };
  }

  // A route that can stream: its body parsed once, here, then WithStreaming() (server/stream.h)
  // takes "stream" out and runs `handle` with or without an event stream.
  using StreamableRoute =
      RouteAnswer (Impl::*)(const httplib::Request&, const Json&, app::Observer*);
  httplib::Server::Handler Streamable(const std::string& route, StreamableRoute handle) {
    return Wrap(route, [this, handle](const httplib::Request& q, httplib::Response& s) {
      auto body = Body(q, s);
      if (!body) return;
      WithStreaming(q, std::move(*body), s, in_flight_, Reserver(),
                    [this, handle](const httplib::Request& q2, const Json& b, app::Observer* o) {
                      return (this->*handle)(q2, b, o);
                    });
    });
  }

  void Routes() {
    SetUpServer();
    svr_.Post("/solve", Streamable("/solve", &Impl::HandleSolve));
    svr_.Post("/replan", Streamable("/replan", &Impl::HandleReplan));
    svr_.Post("/networks/check", Wrap("/networks/check", [this](auto& q, auto& s) {
      auto body = Body(q, s);
      if (!body) return;
      auto r = core_.CheckNetwork(*body);
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      SendJson(s, 200, std::get<Json>(r));
    }));
    svr_.Post("/validate", Wrap("/validate", [this](auto& q, auto& s) { HandleValidate(q, s); }));
    svr_.Post("/translate", Wrap("/translate", [this](auto& q, auto& s) { HandleTranslate(q, s); }));
    svr_.Post("/plan", Streamable("/plan", &Impl::HandlePlan));
    svr_.Get("/eval/suite", Wrap("/eval/suite", [this](auto&, auto& s) {
      auto r = core_.ShippedEvalSuite();
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      SendJson(s, 200, std::get<Json>(r));
    }));
    svr_.Post("/eval", Streamable("/eval", &Impl::HandleEval));
    DomainRoutes();
    ExecutionRoutes();
    svr_.Get(R"(/sessions/([^/]{1,256}))", Wrap("/sessions/{id}", [this](auto& q, auto& s) {
      auto r = core_.GetSession(q.matches[1]);
      if (auto* e = std::get_if<Error>(&r)) return SendError(s, *e);
      SendJson(s, 200, std::get<Json>(r));
    }));
    svr_.Delete(R"(/sessions/([^/]{1,256}))", Wrap("/sessions/{id}", [this](auto& q, auto& s) {
      if (auto e = core_.DeleteSession(q.matches[1])) return SendError(s, *e);
      s.status = 204;
    }));
    svr_.Get("/openapi.json", Wrap("/openapi.json", [](auto&, auto& s) {
      s.set_content(kOpenApiJson, sizeof kOpenApiJson - 1, "application/json");
    }));
    // For the web page: which LLM answers. With keys, a 401 here tells the page to ask for one.
    svr_.Get("/info", Wrap("/info", [this](auto&, auto& s) {
      SendJson(s, 200, {{"llm", {{"mode", core_.LlmMode()}, {"model", cfg_.llm.model}}},
                        {"auth", keys_ ? "bearer" : "none"}});
    }));
    // Liveness: 200 while the process serves, "degraded" when a store fails (a restart would not
    // mend the disk; the server recovers by itself when storage comes back).
    svr_.Get("/healthz", Wrap("/healthz", [this](auto&, auto& s) {
      Json storage = core_.Storage();
      SendJson(s, 200, {{"status", storage["status"] == "ok" ? "ok" : "degraded"}, {"storage", storage}});
    }, false));
    // Readiness: the solver runs and the server is not draining. A failing store does not take the
    // replica out: /solve and the pages need no storage (the storage field says what fails).
    svr_.Get("/readyz", Wrap("/readyz", [this](auto&, auto& s) {
      if (draining_) return SendError(s, {ErrorCode::kUnavailable, "draining", {}});
      if (!core_.SolverReady()) return SendError(s, {ErrorCode::kUnavailable, "minizinc is not runnable", {}});
      SendJson(s, 200, {{"status", "ready"}, {"storage", core_.Storage()}});
    }, false));
    svr_.Get("/metrics", Wrap("/metrics", [this](auto&, auto& s) { s.set_content(MetricsText(), "text/plain; version=0.0.4"); }));
    // Static files (the page) are served by httplib's file handler, outside Wrap(): count them.
    svr_.set_file_request_handler([this](const httplib::Request&, httplib::Response& res) {
      core_.metrics().Request("(static)", res.status == -1 ? 200 : res.status, 0);
    });
    if (!svr_.set_mount_point("/", cfg_.static_dir))
      spdlog::warn("{}", app::LogText("static directory '" + cfg_.static_dir + "' not found: no web page"));
  }

  std::string MetricsText() {
    return core_.metrics().Render() + core_.StorageMetrics() +
           "# HELP ctb_connections_open Connections being served.\n# TYPE ctb_connections_open gauge\n"
           "ctb_connections_open " + std::to_string(svr_.open_connections()) + "\n"
           "# HELP ctb_connections_refused_total Connections refused over the per-address or total cap.\n"
           "# TYPE ctb_connections_refused_total counter\n"
           "ctb_connections_refused_total " + std::to_string(svr_.refused_connections()) + "\n"
           "# HELP ctb_requests_timed_out_total Requests whose head or body did not arrive in time.\n"
           "# TYPE ctb_requests_timed_out_total counter\n"
           "ctb_requests_timed_out_total " + std::to_string(svr_.timed_out_requests()) + "\n";
  }

  const ServerConfig& cfg_;
  Core& core_;
  const app::ApiKeys* keys_;
  GuardedServer svr_;
  std::atomic<int> in_flight_{0};
  std::atomic<bool> draining_{false};
};

HttpFrontEnd::HttpFrontEnd(const ServerConfig& cfg, app::Core& core, const app::ApiKeys* keys)
    : impl_(std::make_unique<Impl>(cfg, core, keys)) {}
HttpFrontEnd::~HttpFrontEnd() = default;
int HttpFrontEnd::Bind() { return impl_->Bind(); }
void HttpFrontEnd::Listen() { impl_->Listen(); }
void HttpFrontEnd::Stop() { impl_->Stop(); }
int HttpFrontEnd::InFlight() const { return impl_->InFlight(); }
void HttpFrontEnd::SetDraining() { impl_->SetDraining(); }

}  // namespace ctb::server
