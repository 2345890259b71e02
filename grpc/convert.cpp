#include "grpc/convert.h"

#include <google/protobuf/struct.pb.h>

#include <memory>

#include "google/rpc/error_details.pb.h"
#include "google/rpc/status.pb.h"
#include "grpc/proto_json.h"

namespace ctb::grpcfront {

namespace {

// The section-5 document with the wrappers protobuf needs: a timeline's segments.
Json WrapForProto(Json doc) {
  if (doc.contains("timelines") && doc["timelines"].is_object())
    for (auto& [name, segs] : doc["timelines"].items()) segs = {{"segments", segs}};
  return doc;
}

google::protobuf::Value ValueOf(const Json& j) {
  google::protobuf::Value v;
  FromJson(j, &v);
  return v;
}

grpc::StatusCode CodeOf(ErrorCode c) {
  switch (c) {
    case ErrorCode::kInvalidInput: return grpc::StatusCode::INVALID_ARGUMENT;
    case ErrorCode::kNotFound: return grpc::StatusCode::NOT_FOUND;
    case ErrorCode::kTooLarge: return grpc::StatusCode::RESOURCE_EXHAUSTED;
    case ErrorCode::kUnprocessable: return grpc::StatusCode::FAILED_PRECONDITION;
    case ErrorCode::kBusy: return grpc::StatusCode::RESOURCE_EXHAUSTED;
    case ErrorCode::kUnavailable: return grpc::StatusCode::UNAVAILABLE;
    case ErrorCode::kUpstreamFailed: return grpc::StatusCode::UNAVAILABLE;
    case ErrorCode::kUpstreamTimeout: return grpc::StatusCode::DEADLINE_EXCEEDED;
    case ErrorCode::kInternal: return grpc::StatusCode::INTERNAL;
    case ErrorCode::kConflict: return grpc::StatusCode::ABORTED;
    case ErrorCode::kUnauthenticated: return grpc::StatusCode::UNAUTHENTICATED;
  }
  return grpc::StatusCode::INTERNAL;
}

}  // namespace

// Found by fuzzing (docs/reliability.md), when this went through protobuf's JSON printer and the
// text was parsed back: the printer wrote nothing for a google.protobuf.Value without a kind (a
// duration [lo, <unset>] became [lo]) nor for a ListValue holding only unknown fields, so a
// malformed part vanished before the core could refuse it. The reflection walk (proto_json.h)
// writes {} for the first and [] for the second, which the loaders refuse at their pointers.
Json ToJson(const google::protobuf::Message& m) { return MessageToJsonValue(m); }

std::optional<std::string> FromJson(const Json& j, google::protobuf::Message* m) {
  return JsonValueToMessage(j, m);
}

app::RequestOptions OptionsOf(const pb::Options& o) {
  app::RequestOptions r;
  if (o.has_objective()) r.objective = o.objective();
  if (o.has_time_limit_ms()) r.time_limit_ms = o.time_limit_ms();
  if (o.has_horizon()) r.horizon = o.horizon();
  if (o.has_max_horizon()) r.max_horizon = o.max_horizon();
  if (o.has_controllability()) r.controllability = o.controllability();
  if (o.has_risk_bound()) r.risk_bound = o.risk_bound();
  return r;
}

pb::PlanStatus StatusOf(const app::Answer& a) {
  switch (a.result.status) {
    case Termination::kOptimal: return pb::SOLVED_OPTIMALLY;
    case Termination::kFeasible: return pb::SOLVED_SATISFICING;
    case Termination::kInfeasible:
      return a.result.scope == InfeasibleScope::kAnyHorizon ? pb::UNSOLVABLE_PROVEN
                                                             : pb::UNSOLVABLE_INCOMPLETELY;
    case Termination::kUnknown: return pb::TIMEOUT;
  }
  return pb::INTERNAL_ERROR;
}

// The typed answer mapped field by field; the trajectory (the contract's own message) through
// protobuf's JSON mapping of the answer's document.
pb::PlanResult ResultOf(const app::Answer& a) {
  const SolveResult& res = a.result;
  pb::PlanResult r;
  r.set_status(StatusOf(a));
  Json traj = WrapForProto(a.document);
  traj.erase("state_plan_summary");
  traj.erase("explanation");
  if (res.status == Termination::kInfeasible) traj["infeasible_for"] = InfeasibleScopeName(res.scope);
  FromJson(traj, r.mutable_trajectory());
  const auto value = res.Value();
  *r.mutable_objective() = ValueOf(value ? value->ToJson() : Json());
  if (res.bound) *r.mutable_bound() = ValueOf(res.bound->ToJson());
  if (res.summary)
    for (const auto& s : *res.summary) FromJson(s, r.add_state_plan_summary());
  if (res.explanation) FromJson(ExplanationJson(*res.explanation), r.mutable_explanation());
  if (a.diff) FromJson(*a.diff, r.mutable_diff());
  if (a.report) FromJson(*a.report, r.mutable_report());
  for (const auto& [k, v] : a.metrics) (*r.mutable_metrics())[k] = v;
  return r;
}

pb::PlanResult IntermediateOf(const SolveProgress& progress) {
  pb::PlanResult r;
  r.set_status(pb::INTERMEDIATE);
  const Json p = app::SolutionEventJson(progress);
  *r.mutable_objective() = ValueOf(p["objective"]);
  *r.mutable_bound() = ValueOf(progress.bound.ToJson());
  for (auto& [k, v] : p.items())
    if (!v.is_null() && !v.is_object())
      (*r.mutable_metrics())[k] = v.is_string() ? v.get<std::string>() : v.dump();
  return r;
}

grpc::Status StatusOf(const Error& e) {
  std::string text = e.message;
  google::rpc::BadRequest bad;
  for (const auto& d : e.details) {
    const std::string where = d.pointer.empty() ? "/" : d.pointer;
    text += "\n" + where + ": " + (d.offset ? "offset " + std::to_string(*d.offset) + ": " : "") +
            d.message;
    auto* v = bad.add_field_violations();
    v->set_field(where);
    v->set_description(d.offset ? "offset " + std::to_string(*d.offset) + ": " + d.message
                                : d.message);
  }
  if (e.limit) text += "\nlimit: " + app::LimitJson(*e.limit).dump();
  const grpc::StatusCode code = CodeOf(e.code);
  // Busy or unavailable: when to try again, as HTTP's Retry-After says it (2 s and 1 s).
  const bool retry = e.code == ErrorCode::kBusy || e.code == ErrorCode::kUnavailable;
  if (e.details.empty() && !retry) return grpc::Status(code, text);
  google::rpc::Status st;
  st.set_code(static_cast<int>(code));
  st.set_message(text);
  if (!e.details.empty()) st.add_details()->PackFrom(bad);
  if (retry) {
    google::rpc::RetryInfo info;
    info.mutable_retry_delay()->set_seconds(e.code == ErrorCode::kBusy ? 2 : 1);
    st.add_details()->PackFrom(info);
  }
  return grpc::Status(code, text, st.SerializeAsString());
}

}  // namespace ctb::grpcfront
