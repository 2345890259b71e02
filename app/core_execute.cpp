// Core's executions (contract section 14): the plan to execute (a session's, or solved or
// replanned from the request), then the live executions of app/executions.h.
#include "app/core_impl.h"
#include "app/executions.h"
#include "app/ids.h"
#include "app/session_doc.h"

namespace ctb::app {

namespace {

constexpr double kMaxSpeed = 10000;

Json OptionsJson(const RequestOptions& o) {
  Json j = Json::object();
  if (o.objective) j["objective"] = *o.objective;
  if (o.time_limit_ms) j["time_limit_ms"] = *o.time_limit_ms;
  if (o.max_horizon) j["max_horizon"] = *o.max_horizon;
  if (o.controllability) j["controllability"] = *o.controllability;
  if (o.risk_bound) j["risk_bound"] = *o.risk_bound;
  return j;
}

std::optional<Error> CheckCall(const ExecutionCall& call) {
  Diagnostics diags;
  const std::string& a = call.adapter;
  if (a != "sim" && a != "mqtt" && a != "grpc" && a != "external")
    diags.Error("/adapter", "must be sim, mqtt, grpc or external");
  if (!(call.speed > 0 && call.speed <= kMaxSpeed))
    diags.Error("/speed", "must be plan seconds per wall second, in (0, 10000]");
  if (!call.sim.is_null() && a != "sim") diags.Error("/sim", "faults are injected by the sim adapter only");
  if (call.options.horizon) diags.Error("/options/horizon", "an execution grows its horizon; use max_horizon");
  if (call.session && (call.domain.name || call.domain.action_model || !call.state_plan.is_null() ||
                       !call.trajectory.is_null()))
    diags.Error("/session", "a session executes its own last plan: give no domain, state plan or trajectory");
  if (!diags.ok()) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid execution request", diags);
  return std::nullopt;
}

// A plan to execute is a plan, with its network (the dispatcher's input).
std::optional<Error> NothingToExecute(const SolveResult& r) {
  if ((r.status == Termination::kOptimal || r.status == Termination::kFeasible) && r.network &&
      r.network->is_object())
    return std::nullopt;
  return Error{ErrorCode::kUnprocessable,
               std::string("there is no plan to execute: the planner answered ") +
                   TerminationName(r.status) + (r.message.empty() ? "" : " (" + r.message + ")"),
               {}};
}

}  // namespace

std::variant<std::string, Error> Core::StartExecution(const ExecutionCall& request, const CallContext& ctx) {
  ExecutionCall call = request;
  if (call.adapter.empty()) call.adapter = impl_->mqtt_configured ? "mqtt" : "sim";
  if (auto e = CheckCall(call)) return *e;
  if (call.adapter == "mqtt" && !impl_->mqtt_configured)
    return Error{ErrorCode::kUnavailable, "no MQTT broker is configured: start the server with --mqtt-url",
                 {{"/adapter", std::nullopt, "use sim or external, or configure MQTT"}}};
  DomainRef ref = call.domain;
  Json state_plan = call.state_plan;
  Json plan;
  if (call.session) {
    auto got = impl_->sessions->Get(*call.session);
    if (auto* e = std::get_if<Error>(&got)) return *e;
    const auto& s = std::get<std::optional<StoredDocument>>(got);
    if (!s) return Error{ErrorCode::kNotFound, "unknown or expired session '" + Echo(*call.session) + "'", {}};
    Session sess = SessionFromDoc(s->doc);
    if (sess.state_plan.is_null() || !s->doc.contains("trajectory"))
      return Bad("the session has no plan to execute yet", "/session");
    ref.name = sess.domain;
    state_plan = sess.state_plan;
    plan = s->doc["trajectory"];
    // The session's stored plan: its document is all there is.
    const std::string status = plan.value("status", "");
    if ((status != "optimal" && status != "feasible") || !plan.contains("network") ||
        !plan["network"].is_object())
      return Error{ErrorCode::kUnprocessable,
                   "there is no plan to execute: the planner answered " +
                       (status.empty() ? "nothing" : status) +
                       (plan.contains("message") ? " (" + plan.value("message", "") + ")" : ""),
                   {}};
  } else if (!call.trajectory.is_null()) {
    ReplanCall rc;
    rc.domain = ref;
    rc.state_plan = state_plan;
    rc.request = {{"now", 0}, {"executed", Json::array()}, {"trajectory", call.trajectory}};
    rc.options = call.options;
    rc.keep = "min_change";
    auto r = Replan(rc, ctx);
    if (auto* e = std::get_if<Error>(&r)) return *e;
    if (auto e = NothingToExecute(std::get<Answer>(r).result)) return *e;
    plan = std::move(std::get<Answer>(r).document);
  } else {
    SolveCall sc;
    sc.domain = ref;
    sc.state_plan = state_plan;
    sc.options = call.options;
    auto r = Solve(sc, ctx);
    if (auto* e = std::get_if<Error>(&r)) return *e;
    if (auto e = NothingToExecute(std::get<Answer>(r).result)) return *e;
    plan = std::move(std::get<Answer>(r).document);
  }
  auto dom = impl_->ResolveDomain(ref);
  if (auto* e = std::get_if<Error>(&dom)) return *e;
  Json doc = {{"state_plan", state_plan}, {"adapter", call.adapter}, {"speed", call.speed}, {"replan", call.replan},
              {"options", OptionsJson(call.options)}};
  if (ref.name) doc["domain"] = *ref.name;
  if (ref.action_model) doc["action_model"] = *ref.action_model;
  if (ref.loaded && !ref.name && !ref.action_model) doc["domain"] = ref.loaded->name;
  if (call.session) doc["session"] = *call.session;
  if (!call.sim.is_null()) doc["sim"] = call.sim;
  return impl_->executions->Start(std::get<std::shared_ptr<const Domain>>(dom), std::move(doc), plan,
                                  call.options);
}

std::variant<Json, Error> Core::GetExecution(const std::string& id) { return impl_->executions->Get(id); }

std::variant<Json, Error> Core::ReportExecution(const std::string& id, const Json& report) {
  return impl_->executions->Report(id, report);
}

std::optional<Error> Core::StopExecution(const std::string& id) { return impl_->executions->Stop(id); }

std::optional<Error> Core::ChangeExecutionStatePlan(const std::string& id, const Json& state_plan) {
  auto dom = impl_->executions->DomainOfLive(id);
  if (auto* e = std::get_if<Error>(&dom)) return *e;
  auto sp = impl_->CheckPlan(state_plan, *std::get<std::shared_ptr<const Domain>>(dom), "");
  if (auto* e = std::get_if<Error>(&sp)) return *e;
  return impl_->executions->ChangeStatePlan(id, state_plan);
}

std::variant<std::vector<ExecutionEvent>, Error> Core::ExecutionEvents(const std::string& id, long after,
                                                                      long wait_ms, bool* ended) {
  return impl_->executions->Events(id, after, wait_ms, ended);
}

void Core::SetCommandSink(const std::string& adapter, std::shared_ptr<CommandSink> sink,
                          const std::string& execution) {
  if (adapter == "mqtt") impl_->mqtt_configured = sink != nullptr;
  impl_->executions->SetSink(adapter, std::move(sink), execution);
}

// Opens the execution store beside the sessions' and resumes what was running.
std::optional<Error> OpenExecutions(Core& core, Core::Impl& impl) {
  const DocumentStoreConfig sc{impl.cfg.session_store, impl.cfg.data_dir, "execution", impl.cfg.max_executions,
                               impl.cfg.execution_idle_s};
  auto store = GuardDocumentStore([sc] { return OpenDocumentStore(sc); }, "execution", impl.storage);
  const bool shared = impl.cfg.session_store.rfind("redis://", 0) == 0;
  impl.executions = std::make_shared<Executions>(core, std::move(store), impl.cfg.execution_lease_ms, shared);
  for (const auto& [adapter, sink] : impl.cfg.command_sinks) core.SetCommandSink(adapter, sink);
  impl.executions->Resume([&impl](const Json& doc) -> std::variant<std::shared_ptr<const Domain>, Error> {
    DomainRef ref;
    if (doc.contains("action_model")) ref.action_model = doc["action_model"];
    else ref.name = doc.value("domain", "");
    return impl.ResolveDomain(ref);
  });
  return std::nullopt;
}

}  // namespace ctb::app
