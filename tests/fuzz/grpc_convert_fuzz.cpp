// Fuzz target: the protobuf-to-core conversion of the gRPC front end (grpc/convert.*). The input
// is the bytes of a SolveRequest as they arrive on the wire; they are parsed and converted as
// Planner/Solve converts them (ToJson of the action model and the state plan, OptionsOf), then the
// documents go through the core's first checks: the budget, LoadDomain (an inline action model,
// or the named shipped domain), LoadStatePlan. Checked: the conversion never crashes; ToJson of
// a message gives an object; FromJson takes it back to an equal message (protobuf's JSON mapping
// round trip); every loader error carries a JSON pointer.
#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/field_comparator.h>
#include <google/protobuf/util/message_differencer.h>

#include <cstdint>

#include "app/budget.h"
#include "grpc/convert.h"
#include "tests/fuzz/fuzz_util.h"

namespace {

using namespace ctb;
namespace pb = ::ctburton::v1;

// True when j holds a number JSON cannot carry, written by protobuf's mapping as a string
// ("NaN", "Infinity", "-Infinity"); read back, a google.protobuf.Value holds that string (the
// core then refuses the document at the value's pointer: a number is expected).
bool HasNonFinite(const Json& j) {
  if (j.is_string()) {
    const auto& s = j.get_ref<const std::string&>();
    return s == "NaN" || s == "Infinity" || s == "-Infinity";
  }
  if (j.is_structured())
    for (const auto& v : j) if (HasNonFinite(v)) return true;
  return false;
}

// What ToJson promises for a google.protobuf.Value without a kind: it reads back as {}.
void MarkUnsetValues(google::protobuf::Message* m) {
  using google::protobuf::FieldDescriptor;
  if (m->GetDescriptor() == google::protobuf::Value::descriptor()) {
    auto* v = static_cast<google::protobuf::Value*>(m);
    if (v->kind_case() == google::protobuf::Value::KIND_NOT_SET) v->mutable_struct_value();
  }
  const auto* desc = m->GetDescriptor();
  const auto* refl = m->GetReflection();
  for (int i = 0; i < desc->field_count(); ++i) {
    const FieldDescriptor* f = desc->field(i);
    if (f->cpp_type() != FieldDescriptor::CPPTYPE_MESSAGE) continue;
    if (f->is_repeated()) {
      for (int k = 0; k < refl->FieldSize(*m, f); ++k)
        MarkUnsetValues(refl->MutableRepeatedMessage(m, f, k));
    } else if (refl->HasField(*m, f)) {
      MarkUnsetValues(refl->MutableMessage(m, f));
    }
  }
}

// ToJson, then FromJson into a fresh message equal to m (NaN equal to NaN; unset Values as {}).
Json RoundTrip(const google::protobuf::Message& m) {
  Json j = grpcfront::ToJson(m);
  if (!j.is_object()) fuzz::Fail("ToJson of a message is not an object");
  if (HasNonFinite(j)) return j;
  std::unique_ptr<google::protobuf::Message> back(m.New());
  if (auto err = grpcfront::FromJson(j, back.get())) {
    std::fprintf(stderr, "FromJson: %s\n", err->c_str());
    fuzz::Fail("FromJson refused what ToJson wrote");
  }
  // Fields of unknown number or of the wrong wire type are kept as unknown fields by the parser
  // and left out by the JSON mapping (proto3 semantics): not compared.
  std::unique_ptr<google::protobuf::Message> known(m.New());
  known->CopyFrom(m);
  known->DiscardUnknownFields();
  MarkUnsetValues(known.get());
  google::protobuf::util::DefaultFieldComparator cmp;
  cmp.set_treat_nan_as_equal(true);
  google::protobuf::util::MessageDifferencer diff;
  diff.set_field_comparator(&cmp);
  std::string report;
  diff.ReportDifferencesToString(&report);
  if (!diff.Compare(*known, *back)) {
    std::fprintf(stderr, "%s\n", report.c_str());
    fuzz::Fail("ToJson/FromJson changed a message");
  }
  return j;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const Domain presentation = fuzz::LoadShippedDomain("config/domains/presentation.json");
  static const Domain search_rescue = fuzz::LoadShippedDomain("config/domains/search_rescue.json");
  static const Domain assembly = fuzz::LoadShippedDomain("config/domains/assembly.json");

  static const bool quiet = [] {  // protobuf logs every string field that is not UTF-8
    google::protobuf::SetLogHandler(nullptr);
    return true;
  }();
  (void)quiet;
  pb::SolveRequest q;
  if (!q.ParseFromArray(data, static_cast<int>(size))) return 0;
  (void)RoundTrip(q);
  (void)grpcfront::OptionsOf(q.options());

  // The domain: inline, or a shipped one by name.
  std::optional<Domain> inline_domain;
  const Domain* dom = nullptr;
  if (q.model_case() == pb::SolveRequest::kActionModel) {
    const Json model = RoundTrip(q.action_model());
    if (app::CheckActionModel(model, app::ModelBudget{}, "/action_model")) return 0;
    Diagnostics d;
    inline_domain = LoadDomain(model, d);
    fuzz::CheckDiagnostics(d);
    if (!inline_domain) {
      if (d.ok()) fuzz::Fail("LoadDomain failed without an error");
      return 0;
    }
    dom = &*inline_domain;
  } else if (q.domain() == "presentation") {
    dom = &presentation;
  } else if (q.domain() == "search_rescue") {
    dom = &search_rescue;
  } else if (q.domain() == "assembly") {
    dom = &assembly;
  } else {
    return 0;
  }
  if (!q.has_state_plan()) return 0;
  const Json plan = RoundTrip(q.state_plan());
  if (app::CheckStatePlan(plan, app::ModelBudget{}, "/state_plan")) return 0;
  Diagnostics d;
  std::optional<StatePlan> sp = LoadStatePlan(plan, *dom, d);
  fuzz::CheckDiagnostics(d);
  if (!sp && d.ok()) fuzz::Fail("LoadStatePlan failed without an error");
  return 0;
}
