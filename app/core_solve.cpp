// Core::Solve and Core::Validate, and what every solving use case shares: resolving the domain,
// checking the state plan and the options, and running the planner in a job slot.
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "app/budget.h"
#include "app/core_impl.h"
#include "app/ids.h"
#include "planner/explain/explain.h"
#include "planner/solve/cancel_watch.h"

namespace ctb::app {

Error Bad(const std::string& message, const std::string& pointer) {
  return {ErrorCode::kInvalidInput, message, {{pointer, std::nullopt, message}}};
}

std::map<std::string, std::string> MetricsOf(const SolveResult& r) {
  std::map<std::string, std::string> m;
  const SolveStats& s = r.stats;
  m["solver"] = s.solver;
  if (r.plan && !s.found_by.empty()) m["found_by"] = s.found_by.Name();
  if (Proven(r.status) && !s.proved_by.empty()) m["proved_by"] = s.proved_by.Name();
  m["compile_ms"] = std::to_string(s.compile_ms);
  m["solve_ms"] = std::to_string(s.solve_ms);
  m["first_solution_ms"] = std::to_string(s.first_solution_ms);
  m["variables"] = std::to_string(s.variables);
  m["solver_runs"] = std::to_string(s.solver_runs);
  for (const auto& [k, v] : s.extra.items()) m[k] = v.is_string() ? v.get<std::string>() : v.dump();
  m["horizon"] = std::to_string(r.plan ? r.plan->horizon : r.horizon);
  m["max_horizon"] = std::to_string(r.max_horizon);
  if (auto v = r.Value()) {
    m["cost"] = std::to_string(r.cost);
    m["goal_reached_at"] = v->MakespanJson().dump();
  }
  if (r.scope != InfeasibleScope::kNone) m["infeasible_for"] = InfeasibleScopeName(r.scope);
  return m;
}

Answer AnswerOf(SolveResult result, const Domain& d, const StatePlan& sp) {
  Answer a;
  a.document = ResultJson(result, d, sp);
  a.metrics = MetricsOf(result);
  a.result = std::move(result);
  return a;
}

std::variant<RequestOptions, Error> ParseRequestOptions(const Json& options) {
  RequestOptions r;
  Diagnostics d;
  ObjectReader reader(options, "/options", d);
  reader.CheckKeys({"time_limit_ms", "horizon", "max_horizon", "objective", "controllability",
                    "risk_bound"});
  auto integer = [&](const char* k, std::optional<long>& out) {
    const Json* v = reader.Get(k);
    if (!v) return;
    if (!v->is_number_integer()) return d.Error(reader.Child(k), "must be an integer");
    out = v->get<long>();
  };
  integer("time_limit_ms", r.time_limit_ms);
  integer("horizon", r.horizon);
  integer("max_horizon", r.max_horizon);
  if (auto ob = reader.String("objective", false)) r.objective = *ob;
  if (auto c = reader.String("controllability", false)) r.controllability = *c;
  if (const Json* rb = reader.Get("risk_bound")) {
    if (!rb->is_number() || rb->get<double>() < 0 || rb->get<double>() > 1)
      d.Error(reader.Child("risk_bound"), "must be a number between 0 and 1");
    else
      r.risk_bound = rb->get<double>();
  }
  if (!d.ok()) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid options", d);
  return r;
}

std::variant<std::shared_ptr<const Domain>, Error> Core::Impl::ResolveDomain(
    const DomainRef& ref) const {
  if (ref.loaded && !ref.name && !ref.action_model) return ref.loaded;
  if (ref.name.has_value() == ref.action_model.has_value())
    return Bad("give exactly one of \"domain\" and \"action_model\"", "/domain");
  if (ref.name) return NamedDomain(*ref.name);
  if (auto over = CheckActionModel(*ref.action_model, cfg.budget, "/action_model")) return *over;
  Diagnostics d, prefixed;
  auto dom = LoadDomain(*ref.action_model, d);
  for (const auto& e : d.errors()) prefixed.Error("/action_model" + e.pointer, e.message, e.offset);
  if (!dom) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid action model", prefixed);
  if (auto over = CheckExpandedDomain(*dom, cfg.budget, "/action_model")) return *over;
  return std::make_shared<const Domain>(std::move(*dom));
}

std::variant<StatePlan, Error> Core::Impl::CheckPlan(const Json& j, const Domain& d,
                                                     const std::string& prefix) const {
  Diagnostics diags, prefixed;
  auto sp = LoadStatePlan(j, d, diags);
  for (const auto& e : diags.errors()) prefixed.Error(prefix + e.pointer, e.message, e.offset);
  if (!sp) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid state plan", prefixed);
  return *sp;
}

std::variant<SolveOptions, Error> Core::Impl::MakeOptions(const RequestOptions& r) const {
  SolveOptions o;
  o.minizinc = cfg.minizinc;
  o.memory_limit_mb = cfg.solver_memory_mb;
  o.time_limit_ms = cfg.default_time_limit_ms;
  o.portfolio = 1;  // one core per job: the gate bounds concurrency
  Diagnostics d;
  auto range = [&](const char* k, const std::optional<long>& v, long lo, long hi) {
    if (v && (*v < lo || *v > hi))
      d.Error(std::string("/options/") + k,
              "must be an integer between " + std::to_string(lo) + " and " + std::to_string(hi));
    return v && *v >= lo && *v <= hi;
  };
  if (range("time_limit_ms", r.time_limit_ms, 1, 3600000))
    o.time_limit_ms = std::min(*r.time_limit_ms, cfg.max_time_limit_ms);
  if (range("horizon", r.horizon, 0, cfg.max_horizon_limit)) o.horizon = static_cast<int>(*r.horizon);
  if (range("max_horizon", r.max_horizon, 0, cfg.max_horizon_limit))
    o.max_horizon = static_cast<int>(*r.max_horizon);
  if (r.horizon && r.max_horizon) d.Error("/options/max_horizon", "give horizon or max_horizon, not both");
  if (r.objective) {
    o.objective = ParseObjective(*r.objective);
    if (!o.objective) d.Error("/options/objective", "must be cost, makespan or cost_then_makespan");
  }
  if (r.controllability) {
    auto c = ParseControllability(*r.controllability);
    if (c && *c != Controllability::kAuto) o.controllability = *c;
    else d.Error("/options/controllability", "must be dynamic, strong or none");
  }
  o.risk_bound = r.risk_bound;
  if (!d.ok()) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid options", d);
  return o;
}

std::variant<Answer, Error> Core::Impl::SolveGated(const Domain& d, const StatePlan& sp,
                                                   SolveOptions o, const CallContext& ctx) {
  return RunGated(std::move(o), ctx, [&](const SolveOptions& so) -> std::variant<Answer, Error> {
    auto r = ::ctb::Solve(d, sp, so);
    if (auto* e = std::get_if<Error>(&r)) return *e;
    SolveResult& result = std::get<SolveResult>(r);
    AnnotateAnswer(d, sp, so, result);  // summary, explanation
    return AnswerOf(std::move(result), d, sp);
  });
}

namespace {

class GateTicket : public JobTicket {
 public:
  explicit GateTicket(JobGate& g) : gate_(g) {}
  ~GateTicket() override {
    if (!used_.exchange(true)) gate_.Unreserve();
  }
  // True the first time: the reserved place is this job's.
  bool Use() { return !used_.exchange(true); }

 private:
  JobGate& gate_;
  std::atomic<bool> used_{false};
};

}  // namespace

std::shared_ptr<JobTicket> Core::ReserveJob() {
  if (!impl_->gate.Reserve()) {
    ++impl_->metrics.solver_rejected;
    return nullptr;
  }
  return std::make_shared<GateTicket>(impl_->gate);
}

std::variant<Answer, Error> Core::Impl::RunGated(
    SolveOptions o, const CallContext& ctx,
    const std::function<std::variant<Answer, Error>(const SolveOptions&)>& run) {
  std::variant<Answer, Error> out = Error{ErrorCode::kInternal, "the job did not run", {}};
  if (auto e = InGate(std::move(o), ctx, [&](const SolveOptions& so) { out = run(so); })) return *e;
  return out;
}

std::optional<Error> Core::Impl::InGate(SolveOptions o, const CallContext& ctx,
                                        const std::function<void(const SolveOptions&)>& run) {
  auto* ticket = ctx.observer ? dynamic_cast<GateTicket*>(ctx.observer->ticket.get()) : nullptr;
  if (!gate.Enter(stopping, ticket && ticket->Use())) {
    ++metrics.solver_rejected;
    return Error{ErrorCode::kBusy, "all solver slots are busy; retry later", {}};
  }
  std::atomic<bool> job_cancel{false};
  o.cancel = &job_cancel;
  if (ctx.observer) {
    ctx.observer->OnStage("solving", Json::object());
    Observer* obs = ctx.observer;
    o.on_progress = [obs](const SolveProgress& p) { obs->OnSolution(p); };
  }
  // The watcher trips the job's flag when the front end says so or the core stops (it polls
  // them every 100 ms); a finished job wakes it at once, so the answer never waits for a tick.
  CancelWatch watch(job_cancel, [this, &ctx] { return stopping || (ctx.cancelled && ctx.cancelled()); });
  struct Finish {
    CancelWatch& watch;
    JobGate& gate;
    ~Finish() {
      watch.Stop();
      gate.Leave();
    }
  } finish{watch, gate};
  try {
    run(o);
    return std::nullopt;
  } catch (const std::bad_alloc&) {
    spdlog::error("{}", Json({{"event", "solve_failed"}, {"what", "out of memory"}}).dump());
    return Error{ErrorCode::kUnavailable,
                 "the server ran out of memory for this solve; retry later with a smaller model "
                 "(request id " + ctx.request_id + ")", {}};
  } catch (const std::exception& e) {
    spdlog::error("{}", Json({{"event", "solve_failed"}, {"what", e.what()}})
                            .dump(-1, ' ', false, Json::error_handler_t::replace));
    return Error{ErrorCode::kInternal, "the solve failed (request id " + ctx.request_id + ")", {}};
  }
}

std::variant<Answer, Error> Core::Solve(const SolveCall& call, const CallContext& ctx) {
  const auto t0 = std::chrono::steady_clock::now();
  auto r = SolveChecked(call, ctx);
  if (auto* a = std::get_if<Answer>(&r))
    a->metrics["core_ms"] = std::to_string(std::chrono::duration<double, std::milli>(
                                               std::chrono::steady_clock::now() - t0).count());
  return r;
}

std::variant<Answer, Error> Core::SolveChecked(const SolveCall& call, const CallContext& ctx) {
  auto dom = impl_->ResolveDomain(call.domain);
  if (auto* e = std::get_if<Error>(&dom)) return *e;
  const Domain& domain = *std::get<std::shared_ptr<const Domain>>(dom);
  if (call.state_plan.is_null()) return Bad("missing \"state_plan\"", "/state_plan");
  const long model_strings = call.domain.action_model ? StringBytes(*call.domain.action_model) : 0;
  if (auto over = CheckStatePlan(call.state_plan, impl_->cfg.budget, "/state_plan", model_strings))
    return *over;
  auto sp = impl_->CheckPlan(call.state_plan, domain, "/state_plan");
  if (auto* e = std::get_if<Error>(&sp)) return *e;
  auto opts = impl_->MakeOptions(call.options);
  if (auto* e = std::get_if<Error>(&opts)) return *e;
  if (call.tune) {
    call.tune(std::get<SolveOptions>(opts));
    if (auto e = ValidateSolveOptions(std::get<SolveOptions>(opts))) return *e;
  }
  return impl_->SolveGated(domain, std::get<StatePlan>(sp), std::get<SolveOptions>(opts), ctx);
}

std::variant<ValidateAnswer, Error> Core::Validate(const SolveCall& call) {
  auto dom = impl_->ResolveDomain(call.domain);
  if (auto* e = std::get_if<Error>(&dom)) return *e;
  if (call.state_plan.is_null()) return Bad("missing \"state_plan\"", "/state_plan");
  Diagnostics diags, prefixed;
  auto sp = LoadStatePlan(call.state_plan, *std::get<std::shared_ptr<const Domain>>(dom), diags);
  for (const auto& e : diags.errors()) prefixed.Error("/state_plan" + e.pointer, e.message, e.offset);
  if (!sp) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid state plan", prefixed);
  ValidateAnswer v;
  for (const auto& w : diags.warnings()) v.warnings.push_back({"/state_plan" + w.pointer, w.offset, w.message});
  return v;
}

Json ValidateAnswer::WarningsJson() const {
  Json out = Json::array();
  for (const auto& w : warnings) out.push_back({{"path", w.pointer}, {"message", w.message}});
  return out;
}

}  // namespace ctb::app
