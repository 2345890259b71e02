// The application core (contract section 10): every use case of the service as a typed call,
// with no HTTP or gRPC type inside. The HTTP server (server/), the gRPC server (grpc/) and the
// CLI's local mode are thin adapters: they turn their wire format into these calls and the
// results back into JSON or protobuf.
//
// Inputs that are documents in the contract (a state plan, an action model, a command) stay
// JSON values here: both front ends carry them as JSON (gRPC through protobuf's JSON mapping).
// Everything else is typed. Errors are ctb::Error values whose details carry the JSON pointer
// of each problem (relative to the request body: "/state_plan/goal...", "/options/horizon").
//
// Progress reaches a front end through an Observer; cancellation through the call's
// `cancelled` predicate, which the core polls (every 100 ms while a solver runs) besides its
// own shutdown flag. A job gate bounds the solves running at once for all front ends together.
//
// Thread-safe: one Core serves every front end's threads. Never throws.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "app/budget.h"
#include "app/metrics.h"
#include "app/solution_event.h"
#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/json_io.h"
#include "planner/solve/solve.h"
#include "translator/llm.h"
#include "translator/pipeline.h"

namespace ctb::app {

class CommandSink;

struct CoreConfig {
  std::string config_dir;      // shipped domains: <config_dir>/domains/*.json
  std::string prompts_dir;
  std::string recordings_dir;  // answers /plan and /translate with `demo` and no LLM
  std::string minizinc = "minizinc";
  long solver_memory_mb = 2048;
  ModelBudget budget;          // the model-size budget of one request (app/budget.h)
  int solver_workers = 2;      // solves at once (all front ends)
  int solver_queue = 8;        // solves waiting; beyond: kBusy
  long default_time_limit_ms = 30000;
  long max_time_limit_ms = 60000;  // a request's time_limit_ms is capped to this
  int max_horizon_limit = 64;
  std::string data_dir = "./data";
  std::string session_store;  // "" / "sqlite", "redis://host:port/db", or "memory" (CLI)
  int max_sessions = 1000;
  int session_idle_s = 1800;
  int max_executions = 1000;           // stored at once (running and ended)
  int execution_idle_s = 7 * 86400;    // an execution untouched this long is dropped
  // A replica's claim on a running execution lasts this long unless renewed; with a shared
  // (Redis) store another replica takes over an execution whose claim ran out.
  long execution_lease_ms = 3000;
  bool demo = false;
  // Runs a one-variable model at start-up to learn whether MiniZinc works (/readyz, a warning in
  // the log). The CLI's one-shot core skips it (a third of a small solve's process time): a solve
  // that needs MiniZinc and cannot run it says so itself.
  bool probe_solver = true;
  LlmConfig llm;
  // Adapters registered before the stored executions resume (as SetCommandSink would), so that a
  // resumed execution's first commands find theirs: adapter name ("mqtt") -> sink.
  std::map<std::string, std::shared_ptr<CommandSink>> command_sinks;
};

// What a front end hears while a call runs. Called on the calling thread; default: nothing.
class Observer {
 public:
  virtual ~Observer() = default;
  // stage: "translating" | "repairing" | "solving"; info: {"llm_call"?}.
  virtual void OnStage(const std::string& /*stage*/, const Json& /*info*/) {}
  // Each improving verified plan, typed; SolutionEventJson writes it as the contract's event.
  virtual void OnSolution(const SolveProgress& /*progress*/) {}
  // An eval item's line (Core::Eval), as it ends.
  virtual void OnItem(const Json& /*line*/) {}
  // A stream's place among the solver jobs, reserved before its 200 head went out
  // (Core::ReserveJob); its job enters the gate with it. Null otherwise.
  std::shared_ptr<class JobTicket> ticket;
};

// A solver place held ahead (Core::ReserveJob); given back when dropped unused.
class JobTicket {
 public:
  virtual ~JobTicket() = default;
};

// Per call: who listens, when to stop, and the request id for the logs.
struct CallContext {
  Observer* observer = nullptr;  // its ticket, when it has one, is the job's reserved place
  std::function<bool()> cancelled;  // polled; true stops the job (its solver is killed)
  std::string request_id;
};

struct RequestOptions {
  std::optional<std::string> objective;  // cost | makespan | cost_then_makespan
  std::optional<long> time_limit_ms;
  std::optional<long> horizon;
  std::optional<long> max_horizon;
  // Contingent transitions (contract section 13): dynamic | strong | none; default: dynamic
  // where the domain has contingent transitions.
  std::optional<std::string> controllability;
  std::optional<double> risk_bound;  // in [0, 1]
};

// A domain by name, or an inline action model (exactly one); or, from a trusted local caller (the
// CLI, which read and checked it from a file), the domain already loaded.
struct DomainRef {
  std::optional<std::string> name;
  std::optional<Json> action_model;
  std::shared_ptr<const Domain> loaded;
};

struct SolveCall {
  DomainRef domain;
  Json state_plan;
  RequestOptions options;
  // Local callers only (the CLI's engine flags, benchmarks): adjusts the planner's options after
  // the request's own are applied. Front ends never set it.
  std::function<void(SolveOptions&)> tune;
};

struct TranslateCall {
  DomainRef domain;
  Json command;                         // must be a string (checked)
  std::optional<std::string> prompting;  // cot | direct
  // Local callers (the eval): what the translation did, also when it failed. Not owned.
  TranslateOptions::Progress* progress = nullptr;
};

struct PlanCall {
  std::optional<std::string> domain;
  Json command;
  std::optional<std::string> prompting;
  std::optional<std::string> session;
  RequestOptions options;
};

// Replanning during execution (contract section 11): in a session (its current state plan and
// plan; the replan becomes a turn), or with a domain, a state plan and the plan being executed.
struct ReplanCall {
  std::optional<std::string> session;
  DomainRef domain;      // without a session
  Json state_plan;       // without a session
  // The body's replanning fields, read by planner/replan: now, executed, observed, blocked and
  // trajectory (in a session, the session's current plan when absent). Pointers stay the body's.
  Json request;
  RequestOptions options;
  std::string keep = "none";  // none | started | min_change
  // What happened, in words ("robot 2 cannot open door 1"): the LLM turns it into `observed` and
  // `blocked` (translator/report.h), merged with the request's own; the answer's "report" says
  // what was understood.
  std::optional<std::string> command;
};

// Executing a plan on devices (contract section 14; app/core_execute.cpp): a session's last
// plan, or a domain and a state plan (solved first; with `trajectory`, replanned from 0 keeping
// as much of it as an optimal plan allows, so that what is dispatched is always a verified plan).
struct ExecutionCall {
  std::optional<std::string> session;
  DomainRef domain;
  Json state_plan;
  Json trajectory;               // optional, without a session
  // sim | mqtt | grpc | external (commands only as events); "": mqtt where configured, else sim.
  std::string adapter;
  double speed = 1;              // plan seconds per wall second (simulations run faster)
  Json sim;                      // the sim adapter's faults: {"fail", "late", "late_by", "seed"}
  RequestOptions options;        // for the first solve and every replan
  // false: a departure from the plan ends the execution `failed` instead of replanning (to
  // measure what replanning buys).
  bool replan = true;
};

// Measuring how well the configured LLM translates (contract section 15; app/core_eval.cpp): a
// suite of {"domain", "command", "reference"}; each command translated, its state plan and the
// reference solved, and compared.
struct EvalCall {
  Json suite;                            // the list of items
  std::string pointer;                   // where the list sits in the request ("" or "/suite")
  std::optional<std::string> prompting;  // cot | direct
  std::optional<long> time_limit_ms;     // per solve (default 10000, capped by the service's)
};

// One item's line: {"item", "domain", "parsed", "valid", "solvable", "verdict", "ms", "tokens"}
// (+ "why" unless equivalent); called as each item ends.
using EvalSink = std::function<void(const Json& line)>;

// Where an adapter hears the commands of the executions it carries.
class CommandSink {
 public:
  virtual ~CommandSink() = default;
  // {"automaton", "command", "from", "to", "at"}; called on the execution's thread.
  virtual void Send(const std::string& execution, const Json& command) = 0;
};

// One execution event (contract 14's SSE): seq counts from 1 per execution.
struct ExecutionEvent {
  long seq = 0;
  std::string name;  // dispatched | reported | replanned | finished
  Json data;
};

// A planner answer: the typed result front ends map (planner/solve/solve_result.h: status,
// plan, objective value, bound, proof reach, engines, statistics) and the contract's document,
// written from it once by the core (section 5, with state_plan_summary and, when infeasible,
// explanation; a replan's now, keep, diff, report and session), which HTTP returns as is.
struct Answer {
  SolveResult result;
  std::optional<Json> diff;    // a replan's: the future against the previous plan
  std::optional<Json> report;  // a replan from words: what was understood
  std::string session;         // a replan in a session: the session's id
  // The statistics as text (solver, solve_ms, horizon, cost, ...); core_ms: the whole call inside
  // the core (checks, gate, planner, summary, explanation), which front ends report (HTTP:
  // Server-Timing).
  std::map<std::string, std::string> metrics;
  Json document;
};

struct TranslateAnswer {
  Json state_plan;
  std::string reasoning;
  Json warnings;  // [] or [{"path"?, "message"}]
  int llm_calls = 0;  // requests sent to the LLM, repairs included
  int repairs = 0;    // of which repair requests
};

struct PlanAnswer {
  TranslateAnswer translation;
  Answer answer;
  std::string session;
};

struct ValidateAnswer {
  std::vector<Diagnostic> warnings;  // pointers relative to the request ("/state_plan/...")
  Json WarningsJson() const;         // [{"path", "message"}], as HTTP and gRPC give them
};

struct DomainInfo {
  std::string name, description;
  std::vector<std::string> automata;  // after template expansion
  std::string source = "shipped";     // "shipped" (config/domains) | "stored" (through the API)
  long version = 0;                   // stored domains: 1 on creation, +1 per replacement
};

// An action model drafted from words (contract section 12): never stored by the core.
// A PDDL 2.1 temporal domain (and problem) to import as an action model (docs/pddl.md).
struct PddlImportCall {
  std::string domain;   // the PDDL domain text
  std::string problem;  // the PDDL problem text; "" = none (the domain's constants ground it)
  std::string name;     // the action model's name; "" = the PDDL domain's, sanitized
  bool store = false;   // also create it as a stored domain (contract section 12)
};

struct PddlImportAnswer {
  Json action_model;  // contract section 2
  Json state_plan;    // the problem's initial state, goal and objective; null without a problem
  // {"line", "column", "action"?, "message"}: what was approximated.
  Json warnings = Json::array();
  std::size_t ground_actions = 0;
  // {"command", "automaton", "pddl", "durative"}: how the model names each ground action.
  Json actions = Json::array();
  bool stored = false;

  // The answer as HTTP gives it (gRPC maps it, leaving a null state_plan unset).
  Json ToJson() const;
};

struct DraftAnswer {
  Json document;  // {"action_model", "restatement", "questions", "warnings"?}
};

class Core {
 public:
  // Loads the shipped domains and opens the session store; an Error says what failed.
  static std::variant<std::unique_ptr<Core>, Error> Open(const CoreConfig& cfg);
  ~Core();

  // A place among the solver jobs for a call that will come (a stream, before its head is
  // sent, so that a busy server can still answer 503 with Retry-After); null when every place is
  // taken. The call finds it in its observer's ticket.
  std::shared_ptr<JobTicket> ReserveJob();

  std::variant<Answer, Error> Solve(const SolveCall& call, const CallContext& ctx);
  std::variant<ValidateAnswer, Error> Validate(const SolveCall& call);
  std::variant<TranslateAnswer, Error> Translate(const TranslateCall& call, const CallContext& ctx);
  std::variant<PlanAnswer, Error> Plan(const PlanCall& call, const CallContext& ctx);
  // The totals {"items", "equivalent", "not_equivalent", "unparsed", "invalid", "unknown"}; the
  // suite is checked whole first (every reference must load: kInvalidInput at its pointer).
  std::variant<Json, Error> Eval(const EvalCall& call, const CallContext& ctx, const EvalSink& each);
  // The shipped suite (<config_dir>/eval/thesis.json), for the page; kNotFound when absent.
  std::variant<Json, Error> ShippedEvalSuite() const;
  // The answer document carries "session" when the call named one.
  std::variant<Answer, Error> Replan(const ReplanCall& call, const CallContext& ctx);

  // {"session", "domain", "turns", "created", "updated"} (contract section 9).
  std::variant<Json, Error> GetSession(const std::string& id);
  std::optional<Error> DeleteSession(const std::string& id);

  // Domains (contract section 12; app/core_domains.cpp). Shipped and stored domains share one
  // namespace; shipped ones cannot be replaced or deleted (kConflict). A document is checked
  // like an inline action model (templates allowed; pointers relative to the document) and
  // stored as written. The store is the session store's (SQLite file or Redis), so stored
  // domains survive restarts and every replica sees them.
  std::variant<std::vector<DomainInfo>, Error> ListDomains() const;
  // Shipped: the document as loaded; stored: as the client wrote it, or with `as_written` false
  // as plain automata (templates expanded). kNotFound when unknown.
  std::variant<Json, Error> GetDomain(const std::string& name, bool as_written = true) const;
  // The new domain's name (the document's "name"); kConflict when the name exists.
  std::variant<std::string, Error> CreateDomain(const Json& document);
  // kNotFound when no stored domain has the name; the document's name must be `name`.
  std::optional<Error> ReplaceDomain(const std::string& name, const Json& document);
  // kConflict while a live session uses the domain, unless `force`.
  std::optional<Error> DeleteDomain(const std::string& name, bool force);
  // Every automaton of the domain drawn as one SVG document.
  std::variant<std::string, Error> DomainDiagram(const std::string& name) const;
  // PDDL in, an action model out (app/core_pddl.cpp): the import's problems are kInvalidInput with
  // one detail each at /domain or /problem (the offset of the line and column in that text); the
  // model is held to the request budget (kTooLarge), at most budget.max_transitions ground
  // actions; with `store`, created like CreateDomain (kConflict when the name exists).
  std::variant<PddlImportAnswer, Error> ImportPddl(const PddlImportCall& call);
  // An LLM drafts an action model from a description of the team; checked and repaired.
  std::variant<DraftAnswer, Error> DraftDomain(const std::string& description,
                                               const CallContext& ctx);

  // A bare temporal network (contract section 13, `POST /networks/check`): the body
  // {"points", "links"} checked for consistency, strong and dynamic controllability;
  // {"consistent", "strong", "dynamic", "conflict"?, "ms"}. Located kInvalidInput errors; kTooLarge
  // beyond kMaxNetworkPoints / kMaxNetworkLinks. Runs on the calling thread (no solver, no gate).
  std::variant<Json, Error> CheckNetwork(const Json& body);

  // Executions (contract section 14). Start: the new execution's id; the plan is dispatched by a
  // thread of the core from then on. kInvalidInput for a bad call, kUnprocessable when there is
  // no plan to execute (infeasible or none found in time).
  std::variant<std::string, Error> StartExecution(const ExecutionCall& call, const CallContext& ctx);
  // {"execution", "state", "now", "history", "plan", "replans", "events", ...}; kNotFound.
  std::variant<Json, Error> GetExecution(const std::string& id);
  // Stores a device's report ({"automaton", "location" | "failed", "time"}) before answering:
  // {"stored": true, "duplicate": bool}. Located kInvalidInput; kConflict once it has ended.
  std::variant<Json, Error> ReportExecution(const std::string& id, const Json& report);
  std::optional<Error> StopExecution(const std::string& id);
  // A new goal while it runs (contract 14: a changed goal replans): the state plan is checked
  // against the execution's domain (pointers relative to it), stored, and the future replanned
  // from what happened. kNotFound, kConflict once it has ended.
  std::optional<Error> ChangeExecutionStatePlan(const std::string& id, const Json& state_plan);
  // The events after `after` (seq), waiting up to `wait_ms` for one; `ended` once the execution
  // has ended and every event was given. kNotFound when unknown.
  std::variant<std::vector<ExecutionEvent>, Error> ExecutionEvents(const std::string& id, long after,
                                                                  long wait_ms, bool* ended);
  // Learned durations (contract 14): {"transitions": [{"automaton", "from", "to", "count", "min",
  // "max", "mean"}], "suggested": a domain document or null} over the stored executions of a
  // named domain; kNotFound for an unknown domain.
  std::variant<Json, Error> DomainDurations(const std::string& name);
  // The adapter that carries commands of `adapter` ("mqtt", "grpc") executions; nullptr removes.
  // A grpc sink is per execution: `execution` names it.
  void SetCommandSink(const std::string& adapter, std::shared_ptr<CommandSink> sink,
                      const std::string& execution = "");

  // "replay" | "endpoint" | "recordings" | "none": which LLM answers /plan.
  std::string LlmMode() const;
  bool SolverReady() const;
  // What the stores last did (app/storage.h StorageHealth::ToJson): for /healthz and /readyz.
  Json Storage() const;
  std::string StorageMetrics() const;  // Prometheus lines
  // Stops every running job (their solvers are killed) and refuses new ones.
  void Shutdown();
  Metrics& metrics();

  struct Impl;  // opaque (app/core_impl.h)

 private:
  std::variant<Answer, Error> SolveChecked(const SolveCall& call, const CallContext& ctx);
  explicit Core(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Core::CheckNetwork without a Core (the CLI's local mode): the same answer and errors.
inline constexpr std::size_t kMaxNetworkPoints = 100000;
inline constexpr std::size_t kMaxNetworkLinks = 400000;
std::variant<Json, Error> CheckNetworkBody(const Json& body);

// Request-side checks shared by the front ends. The JSON form of options ("/options" of a body)
// into RequestOptions: type errors at their pointers.
std::variant<RequestOptions, Error> ParseRequestOptions(const Json& options);

// The "/options" of a replanning request (HTTP body, the CLI's --request): "keep" taken out (a
// string; the core checks its value), the rest as ParseRequestOptions reads it.
struct ReplanRequestOptions {
  RequestOptions options;
  std::string keep = "none";
};
std::variant<ReplanRequestOptions, Error> ParseReplanOptions(Json options);

}  // namespace ctb::app
