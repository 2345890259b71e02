// The gRPC front end's conversions between messages and JSON (grpc/proto_json.h) walk the
// messages by reflection. They must say what protobuf's own JSON mapping says, without the text
// in between: each is compared here with protobuf's printer and parser (the oracle, only in this
// test) on every shipped action model and state plan and on solved answers, and the places where
// they deliberately differ (a Value without a kind, a number JSON cannot hold) are checked.
#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ctburton/v1/planner.pb.h"
#include "grpc/proto_json.h"
#include "planner/model/catalog.h"
#include "planner/solve/solve.h"

namespace ctb::grpcfront {
namespace {

namespace pb = ::ctburton::v1;
using google::protobuf::Message;

std::string Src() { return CTB_TEST_SOURCE_DIR; }

Json Read(const std::string& path) {
  std::ifstream in(path);
  return Json::parse(in);
}

// The oracle: protobuf's printer (proto field names) and its text parsed.
Json Printed(const Message& m) {
  google::protobuf::util::JsonPrintOptions o;
  o.preserve_proto_field_names = true;
  std::string text;
  EXPECT_TRUE(google::protobuf::util::MessageToJsonString(m, &text, o).ok());
  return Json::parse(text);
}

// The oracle's parser, unknown keys ignored.
template <typename M>
M Parsed(const Json& j) {
  M m;
  google::protobuf::util::JsonParseOptions o;
  o.ignore_unknown_fields = true;
  auto st = google::protobuf::util::JsonStringToMessage(j.dump(), &m, o);
  EXPECT_TRUE(st.ok()) << st.message();
  return m;
}

// j into M both ways: the same message; and the message back to JSON both ways: the same JSON.
template <typename M>
void Agrees(const Json& j, const std::string& what) {
  SCOPED_TRACE(what);
  const M oracle = Parsed<M>(j);
  M walked;
  auto err = JsonValueToMessage(j, &walked);
  ASSERT_FALSE(err) << *err;
  std::string diff;
  google::protobuf::util::MessageDifferencer d;
  d.ReportDifferencesToString(&diff);
  EXPECT_TRUE(d.Compare(oracle, walked)) << diff;
  // As text: 2 and 2.0 are equal JSON values but not the same document for a loader that wants
  // an integer.
  EXPECT_EQ(MessageToJsonValue(oracle).dump(), Printed(oracle).dump());
}

// The section-5 document with a timeline's segments wrapped, as grpc/convert.cpp sends it.
Json Wrapped(Json doc) {
  for (auto& [name, segs] : doc["timelines"].items()) segs = {{"segments", segs}};
  doc.erase("state_plan_summary");
  doc.erase("explanation");
  return doc;
}

TEST(ProtoJson, ShippedModelsAndStatePlansConvertAsProtobufsMappingDoes) {
  int models = 0, plans = 0;
  for (const auto& e : std::filesystem::directory_iterator(Src() + "/config/templates"))
    Agrees<google::protobuf::Struct>(Read(e.path()), e.path());  // how gRPC carries a domain document
  for (const auto& e : std::filesystem::directory_iterator(Src() + "/config/domains")) {
    Agrees<pb::ActionModel>(Read(e.path()), e.path());
    ++models;
  }
  for (const auto& dir : std::filesystem::directory_iterator(Src() + "/config/examples"))
    for (const auto& e : std::filesystem::directory_iterator(dir.path())) {
      const Json j = Read(e.path());
      if (!j.contains("initial_state")) continue;  // actions.json, orders.json hold other things
      Agrees<pb::StatePlan>(j, e.path());
      ++plans;
    }
  EXPECT_GE(models, 3);
  EXPECT_GE(plans, 8);
}

TEST(ProtoJson, SolvedAnswersConvertAsProtobufsMappingDoes) {
  for (const char* ex : {"presentation/test1_cot", "search_rescue/test1", "assembly/test",
                         "presentation/impossible_off_within59"}) {
    const std::string name = std::string(ex).substr(0, std::string(ex).find('/'));
    Diagnostics diags;
    auto d = LoadDomainByNameOrPath(name, Src() + "/config", diags);
    ASSERT_TRUE(d) << ex;
    auto sp = LoadStatePlan(Read(Src() + "/config/examples/" + ex + ".json"), *d, diags);
    ASSERT_TRUE(sp) << ex;
    SolveOptions o;
    o.time_limit_ms = 20000;
    auto r = SolveDocument(*d, *sp, o);
    ASSERT_TRUE(std::holds_alternative<Json>(r)) << ex;
    Agrees<pb::Trajectory>(Wrapped(std::get<Json>(r)), ex);
  }
}

TEST(ProtoJson, WhereItDepartsFromTheTextMappingTheCoreStillRefusesThePart) {
  // A duration [1, <a Value without a kind>]: {} at its place (the printer left it out, so the
  // list became [1] and the malformed part vanished).
  pb::Transition t;
  t.mutable_duration()->add_values()->set_number_value(1);
  t.mutable_duration()->add_values();
  EXPECT_EQ(MessageToJsonValue(t)["duration"], Json::parse(R"([1, {}])"));
  // A number JSON cannot hold is a string, which no loader takes for a number.
  google::protobuf::Value v;
  v.set_number_value(std::numeric_limits<double>::infinity());
  EXPECT_EQ(MessageToJsonValue(v), "Infinity");
  // 64-bit integers are strings, enums names, unknown keys and nulls leave fields unset.
  pb::PlanResult pr;
  ASSERT_FALSE(JsonValueToMessage(Json::parse(R"({"status": "SOLVED_OPTIMALLY", "nosuch": 1,
      "trajectory": {"cost": "7", "horizon": null}})"), &pr));
  EXPECT_EQ(pr.status(), pb::SOLVED_OPTIMALLY);
  EXPECT_EQ(pr.trajectory().cost(), 7);
  EXPECT_FALSE(pr.trajectory().has_horizon());
  EXPECT_EQ(MessageToJsonValue(pr)["trajectory"]["cost"], "7");
  // A value that does not fit its field is an error naming the field.
  auto err = JsonValueToMessage(Json::parse(R"({"status": "NO_SUCH_STATUS"})"), &pr);
  ASSERT_TRUE(err);
  EXPECT_NE(err->find("status"), std::string::npos) << *err;
  err = JsonValueToMessage(Json::parse(R"({"trajectory": {"cost": 1.5}})"), &pr);
  ASSERT_TRUE(err);
  EXPECT_NE(err->find("cost"), std::string::npos) << *err;
}

}  // namespace
}  // namespace ctb::grpcfront
