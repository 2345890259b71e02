// Core::Eval (contract section 15): how well the configured LLM translates. For each item of a
// suite the command is translated (with the configured endpoint, or offline from recordings),
// the translation and the reference state plan are solved, and they are compared:
//   equivalent      both infeasible; or both optimal with the same optimum and each optimal plan
//                   a plan for the other state plan (planner/solve/plan_check.h);
//   not_equivalent  one infeasible and not the other, other optima, or a plan the other refuses;
//   unparsed        no answer could be read as JSON; invalid: JSON that never became a valid
//                   state plan (after the translator's repairs);
//   unknown         a solve or a check was cut off, or the LLM call failed: never equivalent.
// A translation that is the reference itself, once written back, is solved once.
#include <chrono>

#include "app/core.h"
#include "app/core_impl.h"
#include "planner/solve/plan_check.h"

namespace ctb::app {

namespace {

constexpr std::size_t kMaxItems = 500;
constexpr long kDefaultEvalSolveMs = 10000;

struct Item {
  std::string domain;
  std::string command;
  std::shared_ptr<const Domain> d;
  StatePlan reference;
};

// The suite checked whole before any LLM call: every domain known, every reference loads.
std::variant<std::vector<Item>, Error> CheckSuite(Core::Impl& core, const EvalCall& call) {
  const std::string& at = call.pointer;
  if (!call.suite.is_array() || call.suite.empty() || call.suite.size() > kMaxItems)
    return Bad("a suite is a list of 1 to " + std::to_string(kMaxItems) +
                   " items {\"domain\", \"command\", \"reference\"}",
               at.empty() ? "/" : at);
  std::vector<Item> items;
  Diagnostics diags;
  for (std::size_t k = 0; k < call.suite.size(); ++k) {
    const std::string p = at + "/" + std::to_string(k);
    ObjectReader r(call.suite[k], p, diags);
    if (!r.valid()) continue;
    r.CheckKeys({"domain", "command", "reference", "note"});
    auto domain = r.String("domain", true);
    auto command = r.String("command", true);
    const Json* reference = r.Get("reference");
    if (!reference) diags.Error(p + "/reference", "missing required field \"reference\"");
    if (!domain || !command || !reference) continue;
    auto d = core.NamedDomain(*domain);
    if (auto* e = std::get_if<Error>(&d)) {
      diags.Error(p + "/domain", e->message);
      continue;
    }
    auto sp = core.CheckPlan(*reference, *std::get<std::shared_ptr<const Domain>>(d), p + "/reference");
    if (auto* e = std::get_if<Error>(&sp)) {
      for (const auto& x : e->details) diags.Error(x.pointer, x.message, x.offset);
      continue;
    }
    items.push_back({*domain, *command, std::get<std::shared_ptr<const Domain>>(d),
                     std::move(std::get<StatePlan>(sp))});
  }
  if (!diags.ok())
    return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid eval suite", diags);
  return items;
}

struct Solved {
  std::string status;  // optimal | feasible | infeasible | unknown | error
  Json objective;
  Trajectory plan;
  std::string infeasible_for;  // any_horizon | max_horizon (infeasible only)
};

Solved SolveOne(const Domain& d, const StatePlan& sp, const SolveOptions& o) {
  Solved s;
  SolveOptions x = o;
  x.plan_out = &s.plan;
  x.derive_network = false;
  auto r = ::ctb::Solve(d, sp, x);
  if (auto* res = std::get_if<SolveResult>(&r)) {
    s.status = TerminationName(res->status);
    s.objective = ObjectiveJson(*res);
    s.infeasible_for = InfeasibleScopeName(res->scope);
    if ((s.status == "optimal" || s.status == "feasible") && !res->verified()) s.status = "unknown";
  } else {
    s.status = "error";
  }
  return s;
}

// The verdict of a valid translation against its reference, with why when not equivalent.
std::pair<std::string, std::string> Compare(const Item& item, const StatePlan& candidate,
                                            const SolveOptions& o, bool& solvable) {
  const Domain& d = *item.d;
  Solved ref = SolveOne(d, item.reference, o);
  // A translation that restates the reference exactly (the same state plan written back) has
  // the reference's answer: it is solved once.
  const bool same = StatePlanToJson(candidate, d) == StatePlanToJson(item.reference, d);
  Solved got = same ? ref : SolveOne(d, candidate, o);
  solvable = got.status == "optimal" || got.status == "feasible";
  auto decided = [](const std::string& s) { return s == "optimal" || s == "infeasible"; };
  if (!decided(ref.status)) return {"unknown", "the reference's solve ended " + ref.status};
  if (!decided(got.status)) return {"unknown", "the translation's solve ended " + got.status};
  if (ref.status == "infeasible" && got.status == "infeasible") {
    // Infeasible up to the horizon only is not a proof that neither has a plan.
    if (ref.infeasible_for != "any_horizon" || got.infeasible_for != "any_horizon")
      return {"unknown", "both are infeasible, but only up to the horizon tried"};
    return {"equivalent", ""};
  }
  if (ref.status != got.status)
    return {"not_equivalent", "the reference is " + ref.status + ", the translation " + got.status};
  if (ref.objective != got.objective)
    return {"not_equivalent", "optimum " + got.objective.dump() + ", the reference's " + ref.objective.dump()};
  if (same) return {"equivalent", ""};  // its verified optimal plan is a plan for itself
  const PlanCheck a = CheckPlanAgainst(got.plan, d, item.reference, o);
  if (a == PlanCheck::kInvalid)
    return {"not_equivalent", "the translation's optimal plan is not a plan for the reference"};
  const PlanCheck b = CheckPlanAgainst(ref.plan, d, candidate, o);
  if (b == PlanCheck::kInvalid)
    return {"not_equivalent", "the reference's optimal plan is not a plan for the translation"};
  if (a == PlanCheck::kUnknown || b == PlanCheck::kUnknown)
    return {"unknown", "checking one plan against the other state plan was cut off"};
  return {"equivalent", ""};
}

}  // namespace

std::variant<Json, Error> Core::Eval(const EvalCall& call, const CallContext& ctx, const EvalSink& each) {
  auto checked = CheckSuite(*impl_, call);
  if (auto* e = std::get_if<Error>(&checked)) return *e;
  if (call.time_limit_ms && (*call.time_limit_ms < 1 || *call.time_limit_ms > impl_->cfg.max_time_limit_ms))
    return Bad("time_limit_ms must be between 1 and " + std::to_string(impl_->cfg.max_time_limit_ms),
               "/time_limit_ms");
  if (auto llm = impl_->Llm(); std::holds_alternative<Error>(llm)) return std::get<Error>(llm);
  RequestOptions ro;
  ro.time_limit_ms = call.time_limit_ms.value_or(std::min(kDefaultEvalSolveMs, impl_->cfg.max_time_limit_ms));
  auto opts = impl_->MakeOptions(ro);
  if (auto* e = std::get_if<Error>(&opts)) return *e;
  Json totals = {{"items", 0},   {"equivalent", 0}, {"not_equivalent", 0},
                 {"unparsed", 0}, {"invalid", 0},    {"unknown", 0}};
  const auto& items = std::get<std::vector<Item>>(checked);
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (impl_->stopping || (ctx.cancelled && ctx.cancelled())) break;
    const Item& item = items[k];
    const auto t0 = std::chrono::steady_clock::now();
    TranslateOptions::Progress progress;
    TranslateCall tc;
    tc.domain.name = item.domain;
    tc.command = item.command;
    tc.prompting = call.prompting;
    tc.progress = &progress;
    Json line = {{"item", k}, {"domain", item.domain}, {"parsed", false}, {"valid", false},
                 {"solvable", false}};
    auto tr = Translate(tc, CallContext{nullptr, ctx.cancelled, ctx.request_id});
    std::string verdict, why;
    if (auto* e = std::get_if<Error>(&tr)) {
      line["parsed"] = progress.read_json;
      verdict = e->code != ErrorCode::kUnprocessable ? "unknown" : progress.read_json ? "invalid" : "unparsed";
      why = e->details.empty() ? e->message : e->message + ": " + e->details[0].ToString();
    } else {
      line["parsed"] = true;
      auto sp = impl_->CheckPlan(std::get<TranslateAnswer>(tr).state_plan, *item.d, "");
      if (auto* e = std::get_if<Error>(&sp)) {
        verdict = "invalid";
        why = e->message;
      } else {
        line["valid"] = true;
        bool solvable = false;
        auto run = [&](const SolveOptions& o) {
          std::tie(verdict, why) = Compare(item, std::get<StatePlan>(sp), o, solvable);
        };
        // The item's solves in one job place, quietly: a stream hears items, not their solves.
        Observer quiet;
        if (ctx.observer) quiet.ticket = ctx.observer->ticket;
        if (auto e = impl_->InGate(std::get<SolveOptions>(opts),
                                   CallContext{&quiet, ctx.cancelled, ctx.request_id}, run)) {
          verdict = "unknown";
          why = e->message;
        }
        line["solvable"] = solvable;
      }
    }
    line["verdict"] = verdict;
    if (!why.empty()) line["why"] = why;
    line["ms"] = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0).count();
    line["tokens"] = progress.tokens;
    totals["items"] = totals["items"].get<int>() + 1;
    totals[verdict] = totals[verdict].get<int>() + 1;
    if (each) each(line);
    if (ctx.observer) ctx.observer->OnItem(line);
  }
  return totals;
}

std::variant<Json, Error> Core::ShippedEvalSuite() const {
  Diagnostics diags;
  const std::string path = impl_->cfg.config_dir + "/eval/thesis.json";
  auto j = ReadJsonFile(path, diags);
  if (!j) return Error{ErrorCode::kNotFound, "no shipped eval suite (" + path + ")", {}};
  return *j;
}

}  // namespace ctb::app
