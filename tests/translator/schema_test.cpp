// The JSON Schema of the state plan: generated from the domain, accepts every shipped example,
// rejects broken ones.
#include "translator/schema.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>

#include "../planner/test_util.h"
#include "schema_validator.h"

namespace ctb {
namespace {

using ctb::testing::Validate;

Json ReadJson(const std::string& path) {
  Diagnostics d;
  auto j = ReadJsonFile(path, d);
  if (!j) ADD_FAILURE() << path;
  return j ? *j : Json();
}

TEST(StatePlanSchema, NamesTheAutomataAndTheirLocations) {
  Json s = StatePlanSchema(ctb::testing::ShippedDomain("presentation"));
  const Json& init = s["properties"]["initial_state"];
  EXPECT_EQ(init["required"], Json({"comp", "conn", "proj"}));
  EXPECT_EQ(init["properties"]["proj"]["enum"],
            Json({"projOff", "projWarmUp", "projOn", "projConfirm", "projCoolDown"}));
  EXPECT_EQ(init["additionalProperties"], false);
  EXPECT_EQ(s["required"], Json({"initial_state", "end_state"}));
  const Json& ep = s["properties"]["constraints"]["properties"]["episodes"]["additionalProperties"];
  EXPECT_EQ(ep["required"].size(), 4u);
  EXPECT_EQ(ep["properties"]["lower_bound"]["type"], "number");
  EXPECT_EQ(s, StatePlanSchema(ctb::testing::ShippedDomain("presentation"))) << "deterministic";
}

TEST(StatePlanSchema, AcceptsEveryShippedExample) {
  int checked = 0;
  for (const auto& dir :
       std::filesystem::directory_iterator(ctb::testing::ConfigDir() + "/examples")) {
    const Json schema =
        StatePlanSchema(ctb::testing::ShippedDomain(dir.path().filename().string()));
    for (const auto& f : std::filesystem::directory_iterator(dir.path())) {
      auto errors = Validate(schema, ReadJson(f.path().string()));
      EXPECT_TRUE(errors.empty()) << f.path() << ": " << errors[0];
      ++checked;
    }
  }
  EXPECT_GE(checked, 10);
}

TEST(StatePlanSchema, RejectsBrokenPlans) {
  const Json schema = StatePlanSchema(ctb::testing::ShippedDomain("presentation"));
  const Json good = ReadJson(ctb::testing::ConfigDir() + "/examples/presentation/test1_cot.json");
  ASSERT_TRUE(Validate(schema, good).empty());
  struct Break {
    const char* what;
    std::function<void(Json&)> apply;
  };
  std::vector<Break> breaks = {
      {"unknown location", [](Json& j) { j["initial_state"]["proj"] = "projOnn"; }},
      {"unknown automaton", [](Json& j) { j["initial_state"]["projector"] = "projOff"; }},
      {"missing automaton", [](Json& j) { j["initial_state"].erase("conn"); }},
      {"no initial_state", [](Json& j) { j.erase("initial_state"); }},
      {"no goal", [](Json& j) { j["end_state"].erase("goal_constraint"); }},
      {"bound as a string",
       [](Json& j) {
         j["constraints"]["episodes"]["ProjectorOnDuration"]["lower_bound"] = "30 min";
       }},
      {"negative bound",
       [](Json& j) { j["constraints"]["temporal"]["ProjectorOnWithin60"]["upper_bound"] = -1; }},
      {"no state_constraint",
       [](Json& j) {
         j["constraints"]["episodes"]["ProjectorOnDuration"].erase("state_constraint");
       }},
      {"unknown key", [](Json& j) { j["reasoning"] = "..."; }},
      {"bad constraint name",
       [](Json& j) {
         j["constraints"]["temporal"]["on within 60"] =
             j["constraints"]["temporal"]["ProjectorOnWithin60"];
       }},
      {"bad objective", [](Json& j) { j["objective"] = "fastest"; }},
      {"bad endpoint",
       [](Json& j) {
         j["constraints"]["event"]["E"] = {"ProjectorOnDuration.finish",
                                           "ShutdownWithin600.event1"};
       }},
      {"one endpoint",
       [](Json& j) { j["constraints"]["event"]["E"] = {"ProjectorOnDuration.end"}; }},
      {"empty condition", [](Json& j) { j["end_state"]["goal_constraint"] = ""; }},
  };
  for (const auto& b : breaks) {
    Json j = good;
    b.apply(j);
    EXPECT_FALSE(Validate(schema, j).empty()) << b.what;
  }
  Json with_event = good;
  with_event["constraints"]["event"]["E"] = {"ProjectorOnDuration.end", "ShutdownWithin600.event1"};
  EXPECT_TRUE(Validate(schema, with_event).empty());
}

TEST(ResponseFormatMember, EachSetting) {
  const Domain& d = ctb::testing::ShippedDomain("presentation");
  EXPECT_TRUE(ResponseFormatMember(ResponseFormat::kNone, d).is_null());
  EXPECT_EQ(ResponseFormatMember(ResponseFormat::kJsonObject, d), Json({{"type", "json_object"}}));
  Json m = ResponseFormatMember(ResponseFormat::kJsonSchema, d);
  EXPECT_EQ(m["type"], "json_schema");
  EXPECT_EQ(m["json_schema"]["name"], "state_plan");
  EXPECT_EQ(m["json_schema"]["schema"], StatePlanSchema(d));
}

}  // namespace
}  // namespace ctb
