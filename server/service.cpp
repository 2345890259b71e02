#include "server/service.h"

#include <httplib.h>
#include <signal.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <thread>

#include "planner/explain/explain.h"
#include "planner/model/catalog.h"
#include "planner/solve/runner.h"
#include "planner/solve/solve.h"
#include "server/budget.h"
#include "server/conn_watch.h"
#include "server/session_doc.h"
#include "server/session_store.h"
#include "server/ids.h"
#include "server/limits.h"
#include "server/log_context.h"
#include "server/metrics.h"
#include "server/stream.h"
#include "server/openapi_json.h"
#include "translator/pipeline.h"
#include "translator/text.h"

namespace ctb::server {

namespace {

using Clock = std::chrono::steady_clock;

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


class Service {
 public:
  explicit Service(const ServerConfig& cfg)
      : cfg_(cfg), gate_(cfg.solver_workers, cfg.solver_queue, metrics_) {}

  int Run() {
    if (!LoadDomains()) return 2;
    {
      SessionStoreConfig sc{cfg_.session_store, cfg_.data_dir, cfg_.max_sessions, cfg_.session_idle_s};
      auto store = OpenSessionStore(sc);
      if (auto* e = std::get_if<Error>(&store)) {
        spdlog::error("{}", Json(fmt::format("session store: {}", e->message)).dump(-1, ' ', false, Json::error_handler_t::replace));
        return 2;
      }
      sessions_ = std::move(std::get<std::unique_ptr<SessionStore>>(store));
    }
    if (cfg_.demo && cfg_.llm.base_url.empty() && cfg_.llm.replay_dir.empty()) {
      auto replay = MakeReplayClient(cfg_.recordings_dir, cfg_.llm.model);
      if (auto* c = std::get_if<std::unique_ptr<LlmClient>>(&replay)) demo_llm_ = std::move(*c);
      else spdlog::warn("{}", Json(fmt::format("--demo: no recordings in '{}'", cfg_.recordings_dir)).dump(-1, ' ', false, Json::error_handler_t::replace));
    }
    SetSolverMemoryLimitMb(cfg_.solver_memory_mb);
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
    if (!svr_.RaiseBacklog())
      spdlog::warn("{}", Json("cannot raise the listen backlog; bursts of connections may wait").dump());
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
      if (domains_.count(name)) {
        spdlog::error("{}", Json(fmt::format("domain file {} repeats the domain name '{}' of another file",
                                             f.path().string(), name)).dump(-1, ' ', false, Json::error_handler_t::replace));
        return false;
      }
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
  static void SendError(httplib::Response& res, const Error& e, const Json& limit = nullptr) {
    Json err = {{"code", CodeName(e.code)}, {"message", e.message}};
    if (!limit.is_null()) err["limit"] = limit;
    if (const std::string rid = res.get_header_value("X-Request-Id"); !rid.empty()) err["request_id"] = rid;
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
    // Before the JSON parser: its messages quote the input, and bytes that are not UTF-8 could
    // not be sent back. A NUL is never part of a JSON text (a parser reading C strings would stop
    // there and accept whatever came before).
    if (auto at = InvalidUtf8Offset(req.body)) {
      Error e{ErrorCode::kInvalidInput, "request body is not valid UTF-8 (byte offset " + std::to_string(*at) + ")",
              {{"/", *at, "invalid UTF-8 at byte offset " + std::to_string(*at)}}};
      SendError(res, e);
      return std::nullopt;
    }
    if (auto nul = req.body.find('\0'); nul != std::string::npos) {
      Error e{ErrorCode::kInvalidInput, "request body contains a NUL byte (byte offset " + std::to_string(nul) + ")",
              {{"/", nul, "NUL byte at byte offset " + std::to_string(nul)}}};
      SendError(res, e);
      return std::nullopt;
    }
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
  // Over the model budget: a kTooLarge Error, and `limit` set to the limit's description.
  std::variant<std::shared_ptr<const Domain>, Error> ResolveDomain(const Json& body, Json& limit) {
    bool has_name = body.contains("domain"), has_model = body.contains("action_model");
    if (has_name == has_model) return Bad("give exactly one of \"domain\" and \"action_model\"", "/domain");
    if (has_name) {
      if (!body["domain"].is_string()) return Bad("\"domain\" must be a string", "/domain");
      auto it = domains_.find(body["domain"].get<std::string>());
      if (it == domains_.end())
        return Error{ErrorCode::kNotFound, "unknown domain '" + Echo(body["domain"].get<std::string>()) + "'",
                     {{"/domain", std::nullopt, "see GET /domains"}}};
      return std::shared_ptr<const Domain>(std::shared_ptr<const Domain>(), &it->second);
    }
    if (auto over = CheckActionModel(body["action_model"], cfg_.budget, "/action_model")) {
      limit = over->ToJson();
      return over->error;
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
    const int local_port = req.local_port, remote_port = req.remote_port;
    // The watcher never throws (a throw in a thread terminates the process), and is stopped and
    // joined, and the slot released, however the solve ends: by a result or by an exception.
    std::thread watch([this, &job_cancel, &done, request_id, local_port, remote_port]() noexcept {
      try {
        while (!done) {
          if (cancel_ || !ClientConnected(local_port, remote_port)) {
            if (!cancel_) {
              SetThreadRequestId(request_id);
              spdlog::info("{}", Json({{"event", "client_gone"}, {"remote_port", remote_port}}).dump());
            }
            job_cancel = true;
            return;
          }
          std::this_thread::sleep_for(std::chrono::milliseconds(200));
        }
      } catch (...) {
        job_cancel = true;
      }
    });
    struct Finish {
      std::atomic<bool>& done;
      std::thread& watch;
      JobGate& gate;
      ~Finish() {
        done = true;
        if (watch.joinable()) watch.join();
        gate.Leave();
      }
    } finish{done, watch, gate_};
    try {
      auto r = Solve(d, sp, o);
      if (auto* j = std::get_if<Json>(&r)) AnnotateAnswer(d, sp, o, *j);  // summary, explanation
      return r;
    } catch (const std::bad_alloc&) {
      spdlog::error("{}", Json({{"event", "solve_failed"}, {"what", "out of memory"}}).dump());
      return Error{ErrorCode::kUnavailable, "the server ran out of memory for this solve; retry later "
                                           "with a smaller model (request id " + request_id + ")", {}};
    } catch (const std::exception& e) {
      spdlog::error("{}", Json({{"event", "solve_failed"}, {"what", e.what()}})
                              .dump(-1, ' ', false, Json::error_handler_t::replace));
      return Error{ErrorCode::kInternal, "the solve failed (request id " + request_id + ")", {}};
    }
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
    Json limit;
    auto dom = ResolveDomain(*body, limit);
    if (auto* e = std::get_if<Error>(&dom)) return SendError(res, *e, limit);
    const Domain& domain = *std::get<std::shared_ptr<const Domain>>(dom);
    if (!body->contains("state_plan")) return SendError(res, Bad("missing \"state_plan\"", "/state_plan"));
    const long model_strings = body->contains("action_model") ? StringBytes((*body)["action_model"]) : 0;
    if (auto over = CheckStatePlan((*body)["state_plan"], cfg_.budget, "/state_plan", model_strings))
      return SendError(res, over->error, over->ToJson());
    auto sp = CheckPlan((*body)["state_plan"], domain, "/state_plan");
    if (auto* e = std::get_if<Error>(&sp)) return SendError(res, *e);
    auto opts = Options(*body);
    if (auto* e = std::get_if<Error>(&opts)) return SendError(res, *e);
    auto r = SolveGated(domain, std::get<StatePlan>(sp), std::get<SolveOptions>(opts), req);
    if (auto* e = std::get_if<Error>(&r)) return SendError(res, *e);
    SendJson(res, 200, std::get<Json>(r));
  }

  // The LLM: the configured endpoint; else, with --demo, the recordings (loaded once at start).
  std::variant<std::unique_ptr<LlmClient>, Error> Llm() {
    LlmConfig c = cfg_.llm;
    if (c.base_url.empty() && c.replay_dir.empty()) {
      if (!demo_llm_)
        return Error{ErrorCode::kUnavailable, "no LLM endpoint configured: set CTB_LLM_BASE_URL, "
                                              "CTB_LLM_API_KEY and CTB_LLM_MODEL (or start with --demo)", {}};
      return std::unique_ptr<LlmClient>(std::make_unique<SharedLlm>(demo_llm_));
    }
    return MakeClient(c);
  }
  // A per-request handle on the one demo client (LlmClient::Complete is thread-safe).
  class SharedLlm : public LlmClient {
   public:
    explicit SharedLlm(std::shared_ptr<LlmClient> c) : c_(std::move(c)) {}
    std::variant<ChatResponse, Error> Complete(const ChatRequest& req) override { return c_->Complete(req); }
    std::string model() const override { return c_->model(); }
    int attempts() const override { return c_->attempts(); }

   private:
    std::shared_ptr<LlmClient> c_;
  };

  struct Translated {
    TranslateResult result;
    std::shared_ptr<const Domain> domain;
  };

  std::variant<Translated, Error> DoTranslate(const Json& body, const Session* session) {
    Json limit;
    auto dom = ResolveDomain(body, limit);
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

  static void SendConflict(httplib::Response& res, const std::string& message) {
    Json err = {{"code", "conflict"}, {"message", message}, {"path", "/session"}};
    if (const std::string rid = res.get_header_value("X-Request-Id"); !rid.empty()) err["request_id"] = rid;
    SendJson(res, 409, {{"error", err}});
  }
  static Error StoreFailed() { return {ErrorCode::kUnavailable, "the session store failed; retry later", {}}; }

  void HandlePlan(const httplib::Request& req, httplib::Response& res) {
    auto body = Body(req, res);
    if (!body) return;
    Diagnostics d;
    ObjectReader(*body, "", d).CheckKeys({"domain", "command", "prompting", "session", "options"});
    if (!d.ok()) return SendError(res, Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid request", d));
    // Everything cheap is checked before any LLM call or solve: the session (or the cap on new
    // ones) and the options.
    std::optional<StoredSession> stored;
    std::optional<Session> session;
    if (body->contains("session")) {
      if (!(*body)["session"].is_string()) return SendError(res, Bad("\"session\" must be a string", "/session"));
      const std::string id = (*body)["session"];
      auto got = sessions_->Get(id);
      if (auto* e = std::get_if<Error>(&got)) return SendError(res, *e);
      stored = std::get<std::optional<StoredSession>>(got);
      if (!stored)
        return SendError(res, {ErrorCode::kNotFound, "unknown or expired session '" + Echo(id) + "'",
                               {{"/session", std::nullopt, "start a new dialogue without \"session\""}}});
      session = SessionFromDoc(stored->doc);
      if (body->contains("domain") && (*body)["domain"] != session->domain)
        return SendError(res, Bad("a session keeps its domain", "/domain"));
      (*body)["domain"] = session->domain;
    } else {
      const long n = sessions_->Count();
      if (n < 0) return SendError(res, StoreFailed());
      if (n >= cfg_.max_sessions) return SendError(res, {ErrorCode::kBusy, "too many open sessions; retry later", {}});
    }
    auto opts = Options(*body);
    if (auto* e = std::get_if<Error>(&opts)) return SendError(res, *e);
    auto t = DoTranslate(*body, session ? &*session : nullptr);
    if (auto* e = std::get_if<Error>(&t)) return SendError(res, *e);
    auto& tr = std::get<Translated>(t);
    auto sp = CheckPlan(tr.result.state_plan, *tr.domain, "/state_plan");
    if (auto* e = std::get_if<Error>(&sp)) return SendError(res, *e);
    auto solved = SolveGated(*tr.domain, std::get<StatePlan>(sp), std::get<SolveOptions>(opts), req);
    if (auto* e = std::get_if<Error>(&solved)) return SendError(res, *e);
    const Json& trajectory = std::get<Json>(solved);
    const Json turn = TurnRecord((*body)["command"], tr.result.reasoning, tr.result.state_plan, trajectory);
    auto conversation = tr.result.conversation;
    if (auto note = DialogueNote(trajectory); !note.empty())
      conversation.push_back({"assistant", note});  // the next turn knows why it failed
    std::string id;
    if (stored) {
      UpdateSessionDoc(stored->doc, conversation, tr.result.state_plan, turn);
      switch (sessions_->Update(*stored)) {
        case StoreResult::kOk: break;
        case StoreResult::kConflict:
          return SendConflict(res, "another turn of this session was stored while this one was planned; "
                                   "reload the session (GET /sessions/{id}) and send the command again");
        case StoreResult::kNotFound:
          return SendError(res, {ErrorCode::kNotFound, "the session expired or was deleted during this turn",
                                 {{"/session", std::nullopt, "start a new dialogue without \"session\""}}});
        default: return SendError(res, StoreFailed());
      }
      id = stored->id;
    } else {
      StoredSession fresh;
      fresh.id = RandomHex(16);
      fresh.doc = NewSessionDoc(tr.domain->name);
      UpdateSessionDoc(fresh.doc, conversation, tr.result.state_plan, turn);
      switch (sessions_->Create(fresh)) {
        case StoreResult::kOk: break;
        case StoreResult::kFull: return SendError(res, {ErrorCode::kBusy, "too many open sessions; retry later", {}});
        default: return SendError(res, StoreFailed());
      }
      id = fresh.id;
    }
    Json out = {{"state_plan", tr.result.state_plan}, {"reasoning", tr.result.reasoning},
                {"trajectory", trajectory}, {"session", id}};
    if (!tr.result.warnings.empty()) out["warnings"] = WarningsJson(tr.result.warnings);
    SendJson(res, 200, out);
  }

  void HandleGetSession(const httplib::Request& req, httplib::Response& res) {
    const std::string id = req.matches[1];
    auto got = sessions_->Get(id);
    if (auto* e = std::get_if<Error>(&got)) return SendError(res, *e);
    const auto& stored = std::get<std::optional<StoredSession>>(got);
    if (!stored) return SendError(res, {ErrorCode::kNotFound, "unknown or expired session '" + Echo(id) + "'", {}});
    SendJson(res, 200, SessionView(*stored));
  }

  void HandleDeleteSession(const httplib::Request& req, httplib::Response& res) {
    const std::string id = req.matches[1];
    switch (sessions_->Delete(id)) {
      case StoreResult::kOk: res.status = 204; return;
      case StoreResult::kNotFound:
        return SendError(res, {ErrorCode::kNotFound, "unknown or expired session '" + Echo(id) + "'", {}});
      default: return SendError(res, StoreFailed());
    }
  }

  void Routes() {
    svr_.set_tcp_nodelay(true);  // headers and body go out in two writes: no 40 ms Nagle stall
    svr_.set_read_timeout(cfg_.read_timeout_s, 0);
    svr_.set_write_timeout(cfg_.write_timeout_s, 0);
    svr_.set_payload_max_length(static_cast<std::size_t>(cfg_.max_body_bytes));
    // Connections are admitted, timed and checked by GuardedServer (server/limits.h). The pool has
    // more threads than admitted connections, so a refusal or /healthz never waits for a thread.
    ConnectionLimits limits;
    limits.per_address = cfg_.max_connections_per_address;
    limits.total = cfg_.max_connections;
    limits.head_timeout_ms = cfg_.read_timeout_s * 1000L;
    limits.body_timeout_ms = cfg_.body_timeout_s * 1000L;
    limits.keep_alive_ms = cfg_.keep_alive_s * 1000L;
    limits.max_body_bytes = cfg_.max_body_bytes;
    svr_.SetLimits(limits);
    svr_.set_keep_alive_timeout(cfg_.keep_alive_s);
    const int threads = cfg_.max_connections + 16;
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
    svr_.Get(R"(/sessions/([^/]{1,256}))", Wrap("/sessions/{id}", [this](auto& q, auto& s) { HandleGetSession(q, s); }));
    svr_.Delete(R"(/sessions/([^/]{1,256}))", Wrap("/sessions/{id}", [this](auto& q, auto& s) { HandleDeleteSession(q, s); }));
    svr_.Get("/openapi.json", Wrap("/openapi.json", [](auto&, auto& s) {
      s.set_content(kOpenApiJson, sizeof kOpenApiJson - 1, "application/json");
    }));
    // For the web page: which LLM answers (an endpoint, a replay directory, the shipped
    // recordings with --demo, or none).
    svr_.Get("/info", Wrap("/info", [this](auto&, auto& s) {
      const LlmConfig& l = cfg_.llm;
      const char* mode = !l.replay_dir.empty() ? "replay"
                         : !l.base_url.empty() ? "endpoint"
                         : demo_llm_           ? "recordings"
                                               : "none";
      SendJson(s, 200, {{"llm", {{"mode", mode}, {"model", l.model}}}});
    }));
    svr_.Get("/healthz", Wrap("/healthz", [](auto&, auto& s) { SendJson(s, 200, {{"status", "ok"}}); }));
    svr_.Get("/readyz", Wrap("/readyz", [this](auto&, auto& s) {
      if (draining_) return SendError(s, {ErrorCode::kUnavailable, "draining", {}});
      if (!ready_) return SendError(s, {ErrorCode::kUnavailable, "minizinc is not runnable", {}});
      SendJson(s, 200, {{"status", "ready"}});
    }));
    svr_.Get("/metrics", Wrap("/metrics", [this](auto&, auto& s) {
      std::string text = metrics_.Render();
      text += "# HELP ctb_connections_open Connections being served.\n# TYPE ctb_connections_open gauge\n"
              "ctb_connections_open " + std::to_string(svr_.open_connections()) + "\n"
              "# HELP ctb_connections_refused_total Connections refused over the per-address or total cap.\n"
              "# TYPE ctb_connections_refused_total counter\n"
              "ctb_connections_refused_total " + std::to_string(svr_.refused_connections()) + "\n"
              "# HELP ctb_requests_timed_out_total Requests whose head or body did not arrive in time.\n"
              "# TYPE ctb_requests_timed_out_total counter\n"
              "ctb_requests_timed_out_total " + std::to_string(svr_.timed_out_requests()) + "\n";
      s.set_content(text, "text/plain; version=0.0.4");
    }));
    // Static files (the page) are served by httplib's file handler, outside Wrap(): count them.
    svr_.set_file_request_handler([this](const httplib::Request&, httplib::Response& res) {
      metrics_.Request("(static)", res.status == -1 ? 200 : res.status, 0);
    });
    if (!svr_.set_mount_point("/", cfg_.static_dir))
      spdlog::warn("{}", Json(fmt::format("static directory '{}' not found: no web page", cfg_.static_dir)).dump(-1, ' ', false, Json::error_handler_t::replace));
  }

  const ServerConfig& cfg_;
  GuardedServer svr_;
  Metrics metrics_;
  JobGate gate_;
  std::map<std::string, Domain> domains_;
  std::unique_ptr<SessionStore> sessions_;
  std::shared_ptr<LlmClient> demo_llm_;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> draining_{false};
  std::atomic<int> in_flight_{0};
  bool ready_ = false;
};

}  // namespace

int Serve(const ServerConfig& cfg) { return Service(cfg).Run(); }

}  // namespace ctb::server
