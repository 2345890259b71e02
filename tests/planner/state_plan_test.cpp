#include "planner/model/state_plan.h"

#include <cmath>

#include <gtest/gtest.h>

#include "test_util.h"

namespace ctb {
// A namespace of its own: the test executable's unity build puts files with same-named
// helpers side by side.
namespace state_plan_test {
namespace {

using testing::HasError;
using testing::MustParse;

Json Plan() {
  return MustParse(R"({
    "initial_state": {"comp": "compOff", "conn": "disconnected", "proj": "projOff"},
    "end_state": {"maintenance_constraint": "true",
                  "goal_constraint": "compl[i+1]==compOff /\\ projl[i+1]==projOff"},
    "constraints": {
      "episodes": {"On": {"accepting_constraint": "projl[i]==projOn",
                          "state_constraint": "projl[i]==projOn",
                          "lower_bound": 1800, "upper_bound": 1800}},
      "temporal": {"first60": {"accepting_event1_constraint": "projl[i]==projOff /\\ projl[i+1]==projWarmUp",
                               "accepting_event2_constraint": "projl[i+1]==projOn /\\ temporalAcceptConstraint_Traj_first60[i]==tempActive",
                               "lower_bound": 0, "upper_bound": 60}},
      "event": {"together": ["On.end", "first60.event2"]}
    },
    "objective": "makespan"
  })");
}

std::optional<StatePlan> Load(const Json& j, Diagnostics& d) {
  return LoadStatePlan(j, testing::ShippedDomain("presentation"), d);
}

TEST(LoadStatePlan, LoadsEveryPart) {
  Diagnostics d;
  auto sp = Load(Plan(), d);
  ASSERT_TRUE(sp) << testing::AllErrors(d);
  EXPECT_EQ(sp->initial, (std::vector<int>{0, 0, 0}));
  ASSERT_EQ(sp->episodes.size(), 1u);
  EXPECT_EQ(sp->episodes[0].lower, 1800);
  ASSERT_EQ(sp->temporals.size(), 1u);
  EXPECT_TRUE(sp->temporals[0].event1.info.IsChange());
  ASSERT_EQ(sp->events.size(), 1u);
  EXPECT_EQ(sp->events[0].endpoints[0].kind, EndpointKind::kEpisodeEnd);
  EXPECT_EQ(sp->events[0].endpoints[1].kind, EndpointKind::kEvent2);
  EXPECT_EQ(sp->objective, Objective::kMakespan);
}

TEST(LoadStatePlan, DefaultsWhenOptionalPartsAreMissing) {
  Json j = Plan();
  j.erase("constraints");
  j.erase("objective");
  j["end_state"].erase("maintenance_constraint");
  Diagnostics d;
  auto sp = Load(j, d);
  ASSERT_TRUE(sp) << testing::AllErrors(d);
  EXPECT_EQ(sp->objective, Objective::kCost);
  EXPECT_EQ(sp->maintenance.text, "true");
  EXPECT_TRUE(sp->episodes.empty());
}

struct Case {
  const char* what;
  std::function<void(Json&)> mutate;
  std::string pointer;
  std::string message_part;
  std::optional<std::size_t> offset = std::nullopt;
};

TEST(LoadStatePlan, EachErrorKindIsReportedAtItsPointer) {
  std::vector<Case> cases = {
      {"unknown top field", [](Json& j) { j["plan"] = 1; }, "/plan", "unknown field"},
      {"missing initial state", [](Json& j) { j.erase("initial_state"); }, "/initial_state",
       "missing required"},
      {"automaton missing from initial state", [](Json& j) { j["initial_state"].erase("conn"); },
       "/initial_state", "missing initial location of automaton 'conn'"},
      {"unknown automaton", [](Json& j) { j["initial_state"]["projector"] = "projOff"; },
       "/initial_state/projector", "unknown automaton 'projector'"},
      {"unknown location", [](Json& j) { j["initial_state"]["proj"] = "projOf"; },
       "/initial_state/proj", "did you mean 'projOff'?"},
      {"location wrong type", [](Json& j) { j["initial_state"]["proj"] = 0; },
       "/initial_state/proj", "expected a location name"},
      {"missing goal", [](Json& j) { j["end_state"].erase("goal_constraint"); },
       "/end_state/goal_constraint", "missing required"},
      {"goal wrong type", [](Json& j) { j["end_state"]["goal_constraint"] = true; },
       "/end_state/goal_constraint", "expected a string, got boolean"},
      {"goal injection", [](Json& j) { j["end_state"]["goal_constraint"] = "true; include \"x\""; },
       "/end_state/goal_constraint", "unexpected character ';'", std::size_t{4}},
      {"goal unknown location",
       [](Json& j) { j["end_state"]["goal_constraint"] = "compl[i+1]==compOff /\\ projl[i+1]==projOnn"; },
       "/end_state/goal_constraint", "unknown location 'projOnn' of automaton 'proj'", std::size_t{35}},
      {"episode negative bound",
       [](Json& j) { j["constraints"]["episodes"]["On"]["lower_bound"] = -5; },
       "/constraints/episodes/On/lower_bound", "must not be negative"},
      {"episode NaN bound",
       [](Json& j) { j["constraints"]["episodes"]["On"]["upper_bound"] = NAN; },
       "/constraints/episodes/On/upper_bound", "not finite"},
      {"episode lower > upper",
       [](Json& j) { j["constraints"]["episodes"]["On"]["lower_bound"] = 1900; },
       "/constraints/episodes/On/lower_bound", "greater than upper_bound"},
      {"episode missing bound",
       [](Json& j) { j["constraints"]["episodes"]["On"].erase("upper_bound"); },
       "/constraints/episodes/On/upper_bound", "missing required"},
      {"episode absurd bound",
       [](Json& j) { j["constraints"]["episodes"]["On"]["upper_bound"] = 1e12; },
       "/constraints/episodes/On/upper_bound", "beyond"},
      {"episode bound string",
       [](Json& j) { j["constraints"]["episodes"]["On"]["upper_bound"] = "1800"; },
       "/constraints/episodes/On/upper_bound", "expected a number"},
      {"episode unknown field",
       [](Json& j) { j["constraints"]["episodes"]["On"]["duration"] = 3; },
       "/constraints/episodes/On/duration", "unknown field"},
      {"episode bad name",
       [](Json& j) { j["constraints"]["episodes"]["bad name"] = j["constraints"]["episodes"]["On"]; },
       "/constraints/episodes/bad name", "not a valid name"},
      {"temporal missing event",
       [](Json& j) { j["constraints"]["temporal"]["first60"].erase("accepting_event2_constraint"); },
       "/constraints/temporal/first60/accepting_event2_constraint", "missing required"},
      {"temporal typo in self reference",
       [](Json& j) {
         j["constraints"]["temporal"]["first60"]["accepting_event2_constraint"] =
             "temporalAcceptConstraint_Traj_first6[i]==tempActive";
       },
       "/constraints/temporal/first60/accepting_event2_constraint", "did you mean 'first60'?",
       std::size_t{0}},
      {"constraints wrong type", [](Json& j) { j["constraints"] = Json::array(); }, "/constraints",
       "expected an object"},
      {"episodes wrong type", [](Json& j) { j["constraints"]["episodes"] = "x"; },
       "/constraints/episodes", "expected an object"},
      {"bad endpoint", [](Json& j) { j["constraints"]["event"]["together"][1] = "first60.start"; },
       "/constraints/event/together/1", "unknown endpoint 'first60.start'"},
      {"single endpoint", [](Json& j) { j["constraints"]["event"]["together"] = {"On.end"}; },
       "/constraints/event/together", "at least two endpoints"},
      {"unknown objective", [](Json& j) { j["objective"] = "fastest"; }, "/objective",
       "unknown objective 'fastest'"},
      {"not an object", [](Json& j) { j = Json::array(); }, "", "expected an object"},
  };
  for (const auto& c : cases) {
    Json j = Plan();
    c.mutate(j);
    Diagnostics d;
    EXPECT_FALSE(Load(j, d)) << c.what;
    EXPECT_TRUE(HasError(d, c.pointer, c.message_part, c.offset))
        << c.what << "; got:\n" << testing::AllErrors(d);
  }
}

TEST(LoadStatePlan, ReportsSeveralErrorsInOneRun) {
  Json j = Plan();
  j["initial_state"]["proj"] = "x";
  j["objective"] = "y";
  j["constraints"]["episodes"]["On"]["lower_bound"] = -1;
  Diagnostics d;
  EXPECT_FALSE(Load(j, d));
  EXPECT_GE(d.errors().size(), 3u);
}

TEST(StatePlanToJson, RoundTrips) {
  Diagnostics d;
  auto sp = Load(Plan(), d);
  ASSERT_TRUE(sp);
  Json again = StatePlanToJson(*sp, testing::ShippedDomain("presentation"));
  Diagnostics d2;
  auto sp2 = Load(again, d2);
  ASSERT_TRUE(sp2) << testing::AllErrors(d2);
  EXPECT_EQ(StatePlanToJson(*sp2, testing::ShippedDomain("presentation")), again);
}

}  // namespace
}  // namespace state_plan_test
}  // namespace ctb
