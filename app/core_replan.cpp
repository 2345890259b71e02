// Core::Replan (contract section 11): the planner's replanning (planner/replan) behind the job
// gate; in a session, the session's current state plan and plan, and the replan as a turn.
#include "app/core_impl.h"
#include "app/ids.h"
#include "app/session_doc.h"
#include "planner/explain/summary.h"
#include "planner/replan/replan.h"
#include "translator/pipeline.h"
#include "translator/report.h"

namespace ctb::app {

namespace {

// What the turn records about a replan: the request's own fields (not the plan it replans).
Json ReplanRecord(const Json& request, const std::string& keep) {
  Json r = {{"keep", keep}};
  for (const char* k : {"now", "executed", "observed", "blocked"})
    if (request.contains(k)) r[k] = request[k];
  return r;
}

// The request with the report's fields: its observations where the request has none for that
// automaton, its blocked transitions first (so /blocked/k of the report's is its own index).
Json Merged(const Json& request, const Json& fields) {
  Json out = request;
  if (fields.contains("observed") && fields["observed"].is_object()) {
    Json obs = fields["observed"];
    if (request.contains("observed") && request["observed"].is_object())
      for (const auto& [k, v] : request["observed"].items()) obs[k] = v;
    out["observed"] = obs;
  }
  if (fields.contains("blocked") && fields["blocked"].is_array()) {
    Json blocked = fields["blocked"];
    if (request.contains("blocked") && request["blocked"].is_array())
      for (const auto& b : request["blocked"]) blocked.push_back(b);
    out["blocked"] = blocked;
  }
  return out;
}

// Checks a replanning request against the domain and state plan without solving.
std::optional<Error> CheckRequest(const Domain& d, const StatePlan& sp, const Json& request) {
  ReplanRequest rr;
  if (auto e = ReadReplanRequest(request, rr, nullptr)) return e;
  return CheckReplanRequest(d, sp, rr);
}

// The replan's answer, its document written once: the trajectory with now, keep and diff
// (ReplanJson), the state plan's summary, and the report in words when there was one.
Answer ReplanAnswer(ReplanResult r, const Domain& d, const StatePlan& sp, const Json& report) {
  r.answer.summary = SummarizeStatePlan(d, sp);
  Answer a;
  a.document = ReplanJson(r, d, sp);
  if (!report.is_null()) {
    a.document["report"] = report;
    a.report = report;
  }
  a.metrics = MetricsOf(r.answer);
  a.diff = std::move(r.diff);
  a.result = std::move(r.answer);
  return a;
}

}  // namespace

std::variant<Json, Error> Core::Impl::ReadReportInWords(const Domain& d, const StatePlan& sp,
                                                        const Json& request,
                                                        const std::string& command,
                                                        const CallContext& ctx) const {
  if (!request.contains("trajectory") || !request["trajectory"].is_object())
    return Bad("a report in words needs the plan being executed", "/trajectory");
  if (!request.contains("now") || !request["now"].is_number())
    return Bad("a report in words needs the present time", "/now");
  if (auto e = CheckRequest(d, sp, request)) return *e;  // the client's part is checked first
  auto llm = Llm();
  if (auto* e = std::get_if<Error>(&llm)) return *e;
  if (ctx.observer) ctx.observer->OnStage("translating", Json::object());
  ReportOptions o;
  o.max_repairs = cfg.llm.max_repairs;
  o.prompts_dir = cfg.prompts_dir;
  auto check = [&](const Json& fields) -> std::vector<Diagnostic> {
    auto e = CheckRequest(d, sp, Merged(request, fields));
    return e ? e->details : std::vector<Diagnostic>{};
  };
  auto r = ReadReport(d, request["trajectory"], request["now"].get<double>(), command,
                      *std::get<std::unique_ptr<LlmClient>>(llm), check, o);
  if (auto* e = std::get_if<Error>(&r)) return *e;
  const ReportResult& rep = std::get<ReportResult>(r);
  Json report = {{"command", command}, {"restatement", rep.restatement}};
  for (const char* k : {"observed", "blocked"})
    if (rep.fields.contains(k)) report[k] = rep.fields[k];
  if (!rep.warnings.empty()) report["warnings"] = WarningsJson(rep.warnings);
  return Json{{"request", Merged(request, rep.fields)}, {"report", report}};
}

std::variant<ReplanRequestOptions, Error> ParseReplanOptions(Json options) {
  ReplanRequestOptions out;
  if (options.is_object() && options.contains("keep")) {
    if (!options["keep"].is_string()) return Bad("keep must be none, started or min_change", "/options/keep");
    out.keep = options["keep"];
    options.erase("keep");
  }
  auto parsed = ParseRequestOptions(options);
  if (auto* e = std::get_if<Error>(&parsed)) return *e;
  out.options = std::get<RequestOptions>(parsed);
  return out;
}

std::variant<Answer, Error> Core::Replan(const ReplanCall& call, const CallContext& ctx) {
  std::optional<StoredDocument> stored;
  DomainRef ref = call.domain;
  Json state_plan = call.state_plan;
  Json request = call.request.is_object() ? call.request : Json::object();
  if (call.session) {
    if (ref.name || ref.action_model || !state_plan.is_null())
      return Bad("a session replans its own domain and state plan", "/session");
    auto got = impl_->sessions->Get(*call.session);
    if (auto* e = std::get_if<Error>(&got)) return *e;
    stored = std::get<std::optional<StoredDocument>>(got);
    if (!stored)
      return Error{ErrorCode::kNotFound, "unknown or expired session '" + Echo(*call.session) + "'",
                   {{"/session", std::nullopt, "start a new dialogue without \"session\""}}};
    Session s = SessionFromDoc(stored->doc);
    if (s.state_plan.is_null() || !stored->doc.contains("trajectory"))
      return Bad("the session has no plan to replan yet", "/session");
    ref.name = s.domain;
    state_plan = s.state_plan;
    if (!request.contains("trajectory")) request["trajectory"] = stored->doc["trajectory"];
  }
  auto dom = impl_->ResolveDomain(ref);
  if (auto* e = std::get_if<Error>(&dom)) return *e;
  const Domain& domain = *std::get<std::shared_ptr<const Domain>>(dom);
  if (state_plan.is_null()) return Bad("missing \"state_plan\"", "/state_plan");
  auto sp = impl_->CheckPlan(state_plan, domain, "/state_plan");
  if (auto* e = std::get_if<Error>(&sp)) return *e;
  auto opts = impl_->MakeOptions(call.options);
  if (auto* e = std::get_if<Error>(&opts)) return *e;
  Json report;
  if (call.command) {
    auto read = impl_->ReadReportInWords(domain, std::get<StatePlan>(sp), request, *call.command, ctx);
    if (auto* e = std::get_if<Error>(&read)) return *e;
    request = std::get<Json>(read)["request"];
    report = std::get<Json>(read)["report"];
  }
  ReplanRequest rr;
  if (auto e = ReadReplanRequest(request, rr, nullptr)) return *e;
  ReplanOptions ro;
  auto keep = ParseKeep(call.keep);
  if (!keep) return Bad("keep must be none, started or min_change", "/options/keep");
  ro.keep = *keep;
  const StatePlan& plan = std::get<StatePlan>(sp);
  auto answered = impl_->RunGated(std::get<SolveOptions>(opts), ctx,
                                  [&](const SolveOptions& so) -> std::variant<Answer, Error> {
                                    ReplanOptions o = ro;
                                    o.solve = so;
                                    auto r = ::ctb::Replan(domain, plan, rr, o);
                                    if (auto* e = std::get_if<Error>(&r)) return *e;
                                    return ReplanAnswer(std::get<ReplanResult>(std::move(r)),
                                                        domain, plan, report);
                                  });
  if (auto* e = std::get_if<Error>(&answered)) return *e;
  Answer answer = std::move(std::get<Answer>(answered));
  if (!stored) return answer;
  // The replan is a turn of the session; a plan it found becomes the session's current one.
  Json turn = TurnRecord(call.command.value_or("(replan)"), "", state_plan, answer.document);
  turn["replan"] = ReplanRecord(request, call.keep);
  UpdateSessionDoc(stored->doc, SessionFromDoc(stored->doc).conversation, state_plan, turn);
  switch (impl_->sessions->Update(*stored)) {
    case StoreResult::kOk: break;
    case StoreResult::kConflict:
      return Error{ErrorCode::kConflict,
                   "another turn of this session was stored while this replan ran; reload the "
                   "session and replan again",
                   {{"/session", std::nullopt, "changed meanwhile"}}};
    case StoreResult::kNotFound:
      return Error{ErrorCode::kNotFound, "the session expired or was deleted during this replan",
                   {{"/session", std::nullopt, "start a new dialogue without \"session\""}}};
    default: return impl_->StoreFailed("session");
  }
  answer.document["session"] = stored->id;
  answer.session = stored->id;
  return answer;
}

}  // namespace ctb::app
