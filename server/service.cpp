#include "server/service.h"

#include <httplib.h>
#include <signal.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <random>
#include <thread>

#include "planner/explain/explain.h"
#include "planner/model/catalog.h"
#include "planner/solve/runner.h"
#include "planner/solve/solve.h"
#include "server/conn_watch.h"
#include "server/log_context.h"
#include "server/metrics.h"
#include "server/stream.h"
#include "translator/pipeline.h"
#include "translator/text.h"

namespace ctb::server {

namespace {

using Clock = std::chrono::steady_clock;

std::string RandomHex(int bytes) {
  static thread_local std::mt19937_64 rng(std::random_device{}());
  std::string s;
  const char* hex = "0123456789abcdef";
  for (int i = 0; i < bytes; ++i) {
    auto b = rng() & 0xff;
    s += hex[b >> 4];
    s += hex[b & 15];
  }
  return s;
}

bool SaneRequestId(const std::string& id) {
  if (id.empty() || id.size() > 64) return false;
  for (char c : id)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) return false;
  return true;
}

// Solver slots: at most `workers` solves run; at most `queue` wait; beyond that, refuse.
class JobGate {
 public:
  JobGate(int workers, int queue, Metrics& m) : workers_(workers), queue_(queue), m_(m) {}
  bool Enter(const std::atomic<bool>& stopping) {
    std::unique_lock<std::mutex> lock(mu_);
    if (running_ >= workers_) {
      if (waiting_ >= queue_) return false;
      ++waiting_;
      m_.solver_queued = waiting_;
      cv_.wait(lock, [&] { return running_ < workers_ || stopping.load(); });
      --waiting_;
      m_.solver_queued = waiting_;
      if (stopping.load()) {
        cv_.notify_all();
        return false;
      }
    }
    m_.solver_running = ++running_;
    return true;
  }
  void Leave() {
    std::lock_guard<std::mutex> lock(mu_);
    m_.solver_running = --running_;
    cv_.notify_one();
  }
  void WakeAll() { cv_.notify_all(); }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  int running_ = 0, waiting_ = 0;
  const int workers_, queue_;
  Metrics& m_;
};

struct Session {
  std::string domain;
  std::vector<ChatMessage> conversation;
  Json state_plan;
  Clock::time_point last_used;
};

class Service {
 public:
  explicit Service(const ServerConfig& cfg)
      : cfg_(cfg), gate_(cfg.solver_workers, cfg.solver_queue, metrics_) {}

  int Run() {
    if (!LoadDomains()) return 2;
    ready_ = MiniZincAvailable(cfg_.minizinc);
    if (!ready_) spdlog::warn("{}", Json(fmt::format("minizinc is not runnable: /readyz answers 503 and /solve fails")).dump(-1, ' ', false, Json::error_handler_t::replace));
    Routes();
    // Signals: a dedicated thread waits for them (no work in a signal handler).
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGINT);
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
    int port = cfg_.port == 0 ? svr_.bind_to_any_port(cfg_.host) : (svr_.bind_to_port(cfg_.host, cfg_.port) ? cfg_.port : -1);
    if (port < 0) {
      spdlog::error("{}", Json(fmt::format("cannot listen on {}:{}", cfg_.host, cfg_.port)).dump(-1, ' ', false, Json::error_handler_t::replace));
      return 2;
    }
    spdlog::info("{}", Json({{"event", "listening"}, {"host", cfg_.host}, {"port", port},
                             {"config", cfg_.ToLogJson()}}).dump());
    std::thread signals([this, set] {
      int sig = 0;
      sigwait(&set, &sig);
      if (sig == SIGUSR1) return;  // woken by Run() on its own exit
      spdlog::info("{}", Json({{"event", "draining"}, {"signal", sig}}).dump());
      draining_ = true;
      svr_.stop();
      auto until = Clock::now() + std::chrono::milliseconds(cfg_.shutdown_grace_ms);
      while (in_flight_ > 0 && Clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(20));
      cancel_ = true;  // solver jobs stop; their processes are killed by the runner
      gate_.WakeAll();
    });
    svr_.listen_after_bind();
    cancel_ = true;
    gate_.WakeAll();
    if (!draining_) pthread_kill(signals.native_handle(), SIGTERM);
    signals.join();
    spdlog::info("{}", Json({{"event", "stopped"}}).dump());
    return 0;
  }

 private:
  bool LoadDomains() {
    std::error_code ec;
    for (const auto& f : std::filesystem::directory_iterator(cfg_.config_dir + "/domains", ec)) {
      if (f.path().extension() != ".json") continue;
      Diagnostics d;
      auto dom = LoadDomainFile(f.path().string(), d);
      if (!dom) {
        spdlog::error("{}", Json(fmt::format("domain file {} is invalid: {}", f.path().string(), d.errors()[0].ToString())).dump(-1, ' ', false, Json::error_handler_t::replace));
        return false;
      }
      std::string name = dom->name;
      domains_.emplace(name, std::move(*dom));
    }
    return !domains_.empty();
  }

  // --- responses ---
  static void SendJson(httplib::Response& res, int status, const Json& j) {
    res.status = status;
    // Text from an LLM or an upstream error may hold invalid UTF-8: replaced, never thrown.
    res.set_content(j.dump(-1, ' ', false, Json::error_handler_t::replace), "application/json");
  }
  static void SendError(httplib::Response& res, const Error& e) {
    Json err = {{"code", CodeName(e.code)}, {"message", e.message}};
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
    if (e.code == ErrorCode::kBusy) res.set_header("Retry-After", "2");
    SendJson(res, HttpStatus(e.code), {{"error", err}});
  }
  static Error Bad(const std::string& msg, const std::string& path = "") {
    return {ErrorCode::kInvalidInput, msg, {{path, std::nullopt, msg}}};
  }

  // Wraps a handler: in-flight count, metrics, one JSON log line, last-resort exception guard.
  httplib::Server::Handler Wrap(const std::string& route,
                                std::function<void(const httplib::Request&, httplib::Response&)> fn) {
    return [this, route, fn](const httplib::Request& req, httplib::Response& res) {
      auto t0 = Clock::now();
      ++in_flight_;
      SetThreadRequestId(res.get_header_value("X-Request-Id"));
      try {
        fn(req, res);
      } catch (const std::exception& e) {
        spdlog::error("{}", Json(fmt::format("unhandled exception in {}: {}", route, e.what())).dump(-1, ' ', false, Json::error_handler_t::replace));
        SendError(res, {ErrorCode::kInternal, "internal error", {}});
      }
      --in_flight_;
      if (res.status == -1) res.status = 200;
      double secs = std::chrono::duration<double>(Clock::now() - t0).count();
      metrics_.Request(route, res.status, secs);
      spdlog::info("{}", Json({{"event", "request"}, {"method", req.method}, {"path", req.path},
                               {"route", route}, {"status", res.status},
                               {"ms", std::lround(secs * 1000)}}).dump(-1, ' ', false, Json::error_handler_t::replace));
      SetThreadRequestId("");
    };
  }

  std::optional<Json> Body(const httplib::Request& req, httplib::Response& res) {
    Diagnostics d;
    ParseLimits limits;
    limits.max_bytes = static_cast<std::size_t>(cfg_.max_body_bytes);
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

  // Domain from "domain" (a name) or "action_model" (inline JSON).
  std::variant<std::shared_ptr<const Domain>, Error> ResolveDomain(const Json& body) {
    bool has_name = body.contains("domain"), has_model = body.contains("action_model");
    if (has_name == has_model) return Bad("give exactly one of \"domain\" and \"action_model\"", "/domain");
    if (has_name) {
      if (!body["domain"].is_string()) return Bad("\"domain\" must be a string", "/domain");
      auto it = domains_.find(body["domain"].get<std::string>());
      if (it == domains_.end())
        return Error{ErrorCode::kNotFound, "unknown domain '" + body["domain"].get<std::string>() + "'",
                     {{"/domain", std::nullopt, "see GET /domains"}}};
      return std::shared_ptr<const Domain>(std::shared_ptr<const Domain>(), &it->second);
    }
    Diagnostics d, prefixed;
    auto dom = LoadDomain(body["action_model"], d);
    for (const auto& e : d.errors()) prefixed.Error("/action_model" + e.pointer, e.message, e.offset);
    if (!dom) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid action model", prefixed);
    return std::make_shared<const Domain>(std::move(*dom));
  }

  std::variant<SolveOptions, Error> Options(const Json& body) {
    SolveOptions o;
    o.minizinc = cfg_.minizinc;
    o.time_limit_ms = cfg_.default_time_limit_ms;
    o.cancel = &cancel_;
    o.portfolio = 1;  // one core per job: the pool bounds concurrency
    if (!body.contains("options")) return o;
    Diagnostics d;
    ObjectReader r(body["options"], "/options", d);
    r.CheckKeys({"time_limit_ms", "horizon", "max_horizon", "objective"});
    auto integer = [&](const char* k, long lo, long hi) -> std::optional<long> {
      const Json* v = r.Get(k);
      if (!v) return std::nullopt;
      if (!v->is_number_integer() || v->get<long long>() < lo || v->get<long long>() > hi) {
        d.Error(r.Child(k), "must be an integer between " + std::to_string(lo) + " and " + std::to_string(hi));
        return std::nullopt;
      }
      return v->get<long>();
    };
    if (auto t = integer("time_limit_ms", 1, 3600000)) o.time_limit_ms = std::min(*t, cfg_.max_time_limit_ms);
    if (auto h = integer("horizon", 0, cfg_.max_horizon_limit)) o.horizon = static_cast<int>(*h);
    if (auto h = integer("max_horizon", 0, cfg_.max_horizon_limit)) o.max_horizon = static_cast<int>(*h);
    if (r.Has("horizon") && r.Has("max_horizon")) d.Error("/options/max_horizon", "give horizon or max_horizon, not both");
    if (auto ob = r.String("objective", false)) {
      o.objective = ParseObjective(*ob);
      if (!o.objective) d.Error("/options/objective", "must be cost, makespan or cost_then_makespan");
    }
    if (!d.ok()) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid options", d);
    return o;
  }

  // Runs a solve in a pool slot. The job is cancelled (its solver killed) when the server stops
  // or when the client's connection is gone.
  std::variant<Json, Error> SolveGated(const Domain& d, const StatePlan& sp, SolveOptions o,
                                       const httplib::Request& req) {
    if (!gate_.Enter(cancel_)) {
      ++metrics_.solver_rejected;
      return Error{ErrorCode::kBusy, "all solver slots are busy; retry later", {}};
    }
    std::atomic<bool> job_cancel{false}, done{false};
    o.cancel = &job_cancel;
    const std::string request_id = ThreadRequestId();  // the sanitized one, set by Wrap()
    StreamStage("solving");
    o.on_progress = StreamSolutionReporter();
    std::thread watch([&] {
      while (!done) {
        if (cancel_ || !ClientConnected(req.local_port, req.remote_port)) {
          if (!cancel_) {
            SetThreadRequestId(request_id);
            spdlog::info("{}", Json({{"event", "client_gone"}, {"remote_port", req.remote_port}}).dump());
          }
          job_cancel = true;
          return;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
      }
    });
    auto r = Solve(d, sp, o);
    if (auto* j = std::get_if<Json>(&r)) AnnotateAnswer(d, sp, o, *j);  // summary, explanation
    done = true;
    watch.join();
    gate_.Leave();
    return r;
  }

  std::variant<StatePlan, Error> CheckPlan(const Json& j, const Domain& d, const std::string& prefix) {
    Diagnostics diags, prefixed;
    auto sp = LoadStatePlan(j, d, diags);
    for (const auto& e : diags.errors()) prefixed.Error(prefix + e.pointer, e.message, e.offset);
    if (!sp) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid state plan", prefixed);
    return *sp;
  }

  void HandleSolve(const httplib::Request& req, httplib::Response& res) {
    auto body = Body(req, res);
    if (!body) return;
    Diagnostics d;
    ObjectReader(*body, "", d).CheckKeys({"domain", "action_model", "state_plan", "options"});
    if (!d.ok()) return SendError(res, Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid request", d));
    auto dom = ResolveDomain(*body);
    if (auto* e = std::get_if<Error>(&dom)) return SendError(res, *e);
    const Domain& domain = *std::get<std::shared_ptr<const Domain>>(dom);
    if (!body->contains("state_plan")) return SendError(res, Bad("missing \"state_plan\"", "/state_plan"));
    auto sp = CheckPlan((*body)["state_plan"], domain, "/state_plan");
    if (auto* e = std::get_if<Error>(&sp)) return SendError(res, *e);
    auto opts = Options(*body);
    if (auto* e = std::get_if<Error>(&opts)) return SendError(res, *e);
    auto r = SolveGated(domain, std::get<StatePlan>(sp), std::get<SolveOptions>(opts), req);
    if (auto* e = std::get_if<Error>(&r)) return SendError(res, *e);
    SendJson(res, 200, std::get<Json>(r));
  }

  // The LLM: the configured endpoint, else the shipped recordings.
  std::variant<std::unique_ptr<LlmClient>, Error> Llm() {
    LlmConfig c = cfg_.llm;
    if (c.base_url.empty() && c.replay_dir.empty()) {
      auto replay = MakeReplayClient(cfg_.recordings_dir, c.model);
      if (std::holds_alternative<Error>(replay))
        return Error{ErrorCode::kUnavailable, "no LLM endpoint configured: set CTB_LLM_BASE_URL, "
                                              "CTB_LLM_API_KEY and CTB_LLM_MODEL", {}};
      return replay;
    }
    return MakeClient(c);
  }

  struct Translated {
    TranslateResult result;
    std::shared_ptr<const Domain> domain;
  };

  std::variant<Translated, Error> DoTranslate(const Json& body, const Session* session) {
    auto dom = ResolveDomain(body);
    if (auto* e = std::get_if<Error>(&dom)) return *e;
    if (!body.contains("command") || !body["command"].is_string())
      return Bad("\"command\" must be a string", "/command");
    TranslateOptions to;
    to.prompts_dir = cfg_.prompts_dir;
    to.max_repairs = cfg_.llm.max_repairs;
    to.response_format = cfg_.llm.response_format;
    if (body.contains("prompting")) {
      auto p = body["prompting"].is_string() ? ParsePrompting(body["prompting"]) : std::nullopt;
      if (!p) return Bad("\"prompting\" must be cot or direct", "/prompting");
      to.prompting = *p;
    }
    if (session) {
      to.history = session->conversation;
      to.previous_state_plan = session->state_plan;
    }
    auto llm = Llm();
    if (auto* e = std::get_if<Error>(&llm)) return *e;
    auto client = StreamReportingLlm(std::move(std::get<std::unique_ptr<LlmClient>>(llm)));
    auto r = Translate(*std::get<std::shared_ptr<const Domain>>(dom), body["command"], *client, to);
    if (auto* e = std::get_if<Error>(&r)) {
      if (e->code == ErrorCode::kUnavailable && cfg_.llm.base_url.empty())
        e->message += " (no LLM endpoint configured: set CTB_LLM_BASE_URL, CTB_LLM_API_KEY and CTB_LLM_MODEL)";
      // The key never leaves in a response, whatever the upstream put into its message.
      e->message = MaskSecret(e->message, cfg_.llm.api_key);
      for (auto& d : e->details) d.message = MaskSecret(d.message, cfg_.llm.api_key);
      return *e;
    }
    metrics_.LlmCall(std::get<TranslateResult>(r).llm_calls, std::get<TranslateResult>(r).repairs);
    return Translated{std::move(std::get<TranslateResult>(r)), std::get<std::shared_ptr<const Domain>>(dom)};
  }

  void HandleTranslate(const httplib::Request& req, httplib::Response& res) {
    auto body = Body(req, res);
    if (!body) return;
    Diagnostics d;
    ObjectReader(*body, "", d).CheckKeys({"domain", "command", "prompting"});
    if (!d.ok()) return SendError(res, Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid request", d));
    auto t = DoTranslate(*body, nullptr);
    if (auto* e = std::get_if<Error>(&t)) return SendError(res, *e);
    const auto& r = std::get<Translated>(t).result;
    Json out = {{"state_plan", r.state_plan}, {"reasoning", r.reasoning}};
    if (!r.warnings.empty()) out["warnings"] = WarningsJson(r.warnings);
    SendJson(res, 200, out);
  }

  void HandlePlan(const httplib::Request& req, httplib::Response& res) {
    auto body = Body(req, res);
    if (!body) return;
    Diagnostics d;
    ObjectReader(*body, "", d).CheckKeys({"domain", "command", "prompting", "session", "options"});
    if (!d.ok()) return SendError(res, Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid request", d));
    std::optional<Session> session;
    std::string id;
    if (body->contains("session")) {
      if (!(*body)["session"].is_string()) return SendError(res, Bad("\"session\" must be a string", "/session"));
      id = (*body)["session"];
      std::lock_guard<std::mutex> lock(sessions_mu_);
      ExpireSessions();
      auto it = sessions_.find(id);
      if (it == sessions_.end())
        return SendError(res, {ErrorCode::kNotFound, "unknown or expired session '" + id + "'",
                               {{"/session", std::nullopt, "start a new dialogue without \"session\""}}});
      session = it->second;
      if (body->contains("domain") && (*body)["domain"] != session->domain)
        return SendError(res, Bad("a session keeps its domain", "/domain"));
      (*body)["domain"] = session->domain;
    }
    auto t = DoTranslate(*body, session ? &*session : nullptr);
    if (auto* e = std::get_if<Error>(&t)) return SendError(res, *e);
    auto& tr = std::get<Translated>(t);
    auto sp = CheckPlan(tr.result.state_plan, *tr.domain, "/state_plan");
    if (auto* e = std::get_if<Error>(&sp)) return SendError(res, *e);
    auto opts = Options(*body);
    if (auto* e = std::get_if<Error>(&opts)) return SendError(res, *e);
    auto solved = SolveGated(*tr.domain, std::get<StatePlan>(sp), std::get<SolveOptions>(opts), req);
    if (auto* e = std::get_if<Error>(&solved)) return SendError(res, *e);
    {
      std::lock_guard<std::mutex> lock(sessions_mu_);
      ExpireSessions();
      if (id.empty()) {
        if (static_cast<int>(sessions_.size()) >= cfg_.max_sessions)
          return SendError(res, {ErrorCode::kBusy, "too many open sessions; retry later", {}});
        id = RandomHex(16);
      }
      Session& s = sessions_[id];
      s.domain = tr.domain->name;
      s.conversation = tr.result.conversation;
      if (auto note = DialogueNote(std::get<Json>(solved)); !note.empty())
        s.conversation.push_back({"assistant", note});  // the next turn knows why it failed
      s.state_plan = tr.result.state_plan;
      s.last_used = Clock::now();
    }
    Json out = {{"state_plan", tr.result.state_plan}, {"reasoning", tr.result.reasoning},
                {"trajectory", std::get<Json>(solved)}, {"session", id}};
    if (!tr.result.warnings.empty()) out["warnings"] = WarningsJson(tr.result.warnings);
    SendJson(res, 200, out);
  }

  void ExpireSessions() {
    auto now = Clock::now();
    for (auto it = sessions_.begin(); it != sessions_.end();)
      it = now - it->second.last_used > std::chrono::seconds(cfg_.session_idle_s) ? sessions_.erase(it) : std::next(it);
  }

  void Routes() {
    svr_.set_tcp_nodelay(true);  // headers and body go out in two writes: no 40 ms Nagle stall
    svr_.set_read_timeout(cfg_.read_timeout_s, 0);
    svr_.set_write_timeout(cfg_.write_timeout_s, 0);
    svr_.set_payload_max_length(static_cast<std::size_t>(cfg_.max_body_bytes));
    const int threads = cfg_.solver_workers + cfg_.solver_queue + 8;
    svr_.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
    svr_.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      std::string id = req.get_header_value("X-Request-Id");
      res.set_header("X-Request-Id", SaneRequestId(id) ? id : RandomHex(8));
      // Chunked bodies would dodge the length limit (cpp-httplib 0.11): refuse them.
      if (req.has_header("Transfer-Encoding")) {
        SendError(res, {ErrorCode::kTooLarge, "chunked request bodies are not accepted; send Content-Length", {}});
        res.status = 411;
        metrics_.Request("(refused)", 411, 0);
        return httplib::Server::HandlerResponse::Handled;
      }
      if (req.has_header("Content-Length") &&
          std::atoll(req.get_header_value("Content-Length").c_str()) > cfg_.max_body_bytes) {
        SendError(res, {ErrorCode::kTooLarge, "request body larger than " + std::to_string(cfg_.max_body_bytes) + " bytes", {}});
        metrics_.Request("(refused)", 413, 0);
        return httplib::Server::HandlerResponse::Handled;
      }
      return httplib::Server::HandlerResponse::Unhandled;
    });
    svr_.set_error_handler([](const httplib::Request&, httplib::Response& res) {
      if (!res.body.empty()) return;
      Error e{ErrorCode::kNotFound, "no such route", {}};
      if (res.status == 413) e = {ErrorCode::kTooLarge, "request body too large", {}};
      else if (res.status == 400) e = {ErrorCode::kInvalidInput, "malformed request", {}};
      else if (res.status != 404) e = {ErrorCode::kInternal, "request failed", {}};
      int status = res.status;
      SendError(res, e);
      res.status = status;
    });
    svr_.Post("/solve", Wrap("/solve", [this](auto& q, auto& s) {
      WithStreaming(q, s, in_flight_, [this](auto& q2, auto& s2) { HandleSolve(q2, s2); });
    }));
    svr_.Post("/translate", Wrap("/translate", [this](auto& q, auto& s) { HandleTranslate(q, s); }));
    svr_.Post("/plan", Wrap("/plan", [this](auto& q, auto& s) {
      WithStreaming(q, s, in_flight_, [this](auto& q2, auto& s2) { HandlePlan(q2, s2); });
    }));
    svr_.Get("/domains", Wrap("/domains", [this](auto&, auto& s) {
      Json list = Json::array();
      for (const auto& [name, d] : domains_) {
        Json automata = Json::array();
        for (const auto& a : d.automata) automata.push_back(a.name);
        list.push_back({{"name", name}, {"description", d.description}, {"automata", automata}});
      }
      SendJson(s, 200, {{"domains", list}});
    }));
    svr_.Get(R"(/domains/([A-Za-z0-9_]+))", Wrap("/domains/{name}", [this](auto& q, auto& s) {
      auto it = domains_.find(q.matches[1]);
      if (it == domains_.end()) return SendError(s, {ErrorCode::kNotFound, "unknown domain", {}});
      SendJson(s, 200, DomainToJson(it->second));
    }));
    // For the web page: which LLM answers (an endpoint, a replay directory, or the shipped
    // recordings when none is configured).
    svr_.Get("/info", Wrap("/info", [this](auto&, auto& s) {
      const LlmConfig& l = cfg_.llm;
      const char* mode = !l.replay_dir.empty() ? "replay" : !l.base_url.empty() ? "endpoint" : "recordings";
      SendJson(s, 200, {{"llm", {{"mode", mode}, {"model", l.model}}}});
    }));
    svr_.Get("/healthz", Wrap("/healthz", [](auto&, auto& s) { SendJson(s, 200, {{"status", "ok"}}); }));
    svr_.Get("/readyz", Wrap("/readyz", [this](auto&, auto& s) {
      if (draining_) return SendError(s, {ErrorCode::kUnavailable, "draining", {}});
      if (!ready_) return SendError(s, {ErrorCode::kUnavailable, "minizinc is not runnable", {}});
      SendJson(s, 200, {{"status", "ready"}});
    }));
    svr_.Get("/metrics", Wrap("/metrics", [this](auto&, auto& s) {
      s.set_content(metrics_.Render(), "text/plain; version=0.0.4");
    }));
    if (!svr_.set_mount_point("/", cfg_.static_dir))
      spdlog::warn("{}", Json(fmt::format("static directory '{}' not found: no web page", cfg_.static_dir)).dump(-1, ' ', false, Json::error_handler_t::replace));
  }

  const ServerConfig& cfg_;
  httplib::Server svr_;
  Metrics metrics_;
  JobGate gate_;
  std::map<std::string, Domain> domains_;
  std::mutex sessions_mu_;
  std::map<std::string, Session> sessions_;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> draining_{false};
  std::atomic<int> in_flight_{0};
  bool ready_ = false;
};

}  // namespace

int Serve(const ServerConfig& cfg) { return Service(cfg).Run(); }

}  // namespace ctb::server
