// Loading action events (contract section 15): located errors with suggestions, warnings for
// actions no run can take, the JSON written back, and the restatement in words.
#include <gtest/gtest.h>

#include "planner/explain/summary.h"
#include "test_util.h"

namespace ctb {
namespace {

using testing::MustParse;
using testing::ShippedDomain;

Json Rescue(const Json& constraints) {
  Json sp = MustParse(R"({
    "initial_state": {"robot1": "outside", "robot2": "outside", "door1": "closed",
                      "door2": "closed", "door3": "open"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint": "robot1[i+1]==rescuedPerson1"}})");
  sp["constraints"] = constraints;
  return sp;
}

// Every error as "pointer: message".
std::vector<std::string> Errors(const Json& constraints) {
  Diagnostics diags;
  auto sp = LoadStatePlan(Rescue(constraints), ShippedDomain("search_rescue"), diags);
  EXPECT_FALSE(sp);
  std::vector<std::string> out;
  for (const auto& e : diags.errors()) out.push_back(e.pointer + ": " + e.message);
  return out;
}

::testing::AssertionResult HasError(const std::vector<std::string>& errors, const std::string& pointer,
                                    const std::string& words) {
  for (const auto& e : errors)
    if (e.rfind(pointer + ": ", 0) == 0 && e.find(words) != std::string::npos)
      return ::testing::AssertionSuccess();
  std::string all;
  for (const auto& e : errors) all += "\n  " + e;
  return ::testing::AssertionFailure() << "no error at " << pointer << " with '" << words << "' in:" << all;
}

TEST(ActionLoad, UnknownNamesAreLocatedWithSuggestions) {
  auto e = Errors(MustParse(R"({"actions": {
      "A": {"automaton": "robot3", "command": "goToDoor1"},
      "B": {"automaton": "robot1", "command": "goToDor1"},
      "C": {"automaton": "robot1", "from": "outsid", "to": "goingToDoor1"},
      "D": {"automaton": "robot1"},
      "E": {"automaton": "robot1", "command": "goToDoor1", "occurrence": "sometimes"}},
    "temporal": {"T": {"event1": "A", "event2": "Bee", "ordered": true}},
    "sequence": ["B", "Cee"],
    "forbidden": ["Dx"]})"));
  EXPECT_TRUE(HasError(e, "/constraints/actions/A/automaton", "did you mean 'robot1'"));
  EXPECT_TRUE(HasError(e, "/constraints/actions/B/command", "did you mean 'goToDoor1'"));
  EXPECT_TRUE(HasError(e, "/constraints/actions/C/from", "did you mean 'outside'"));
  EXPECT_TRUE(HasError(e, "/constraints/actions/D", "\"from\" and \"to\""));
  EXPECT_TRUE(HasError(e, "/constraints/actions/E/occurrence", "first, last or every"));
  EXPECT_TRUE(HasError(e, "/constraints/temporal/T/event2", "unknown action 'Bee'"));
  EXPECT_TRUE(HasError(e, "/constraints/sequence/1", "unknown action 'Cee'"));
  EXPECT_TRUE(HasError(e, "/constraints/forbidden/0", "unknown action 'Dx'"));
  // An action that failed is reported once, where it is defined: not again where it is named.
  for (const auto& s : e) EXPECT_EQ(s.find("unknown action 'A'"), std::string::npos) << s;
}

TEST(ActionLoad, ATransitionTheActionDoesNotHaveIsNamed) {
  auto e = Errors(MustParse(R"({"actions": {
      "A": {"automaton": "robot1", "command": "openDoor1", "from": "outside"},
      "B": {"automaton": "robot1", "from": "outside", "to": "rescuedPerson1"}}})"));
  EXPECT_TRUE(HasError(e, "/constraints/actions/A", "command 'openDoor1' causes no transition of 'robot1' from 'outside'"));
  EXPECT_TRUE(HasError(e, "/constraints/actions/A", "'atDoor1' -> 'door1Opening'"));
  EXPECT_TRUE(HasError(e, "/constraints/actions/B", "'robot1' has no transition from 'outside' to 'rescuedPerson1'"));
}

TEST(ActionLoad, EveryOnlyAsTheLaterEndOfAnOrderedConstraint) {
  Json acts = MustParse(R"({"A": {"automaton": "robot1", "command": "goToDoor1", "occurrence": "every"},
                            "B": {"automaton": "robot2", "command": "goToDoor1"}})");
  auto first = Errors({{"actions", acts}, {"temporal", {{"T", {{"event1", "A"}, {"event2", "B"}, {"ordered", true}}}}}});
  EXPECT_TRUE(HasError(first, "/constraints/temporal/T/event1", "only be the later end"));
  auto either = Errors({{"actions", acts}, {"temporal", {{"T", {{"event1", "B"}, {"event2", "A"}}}}}});
  EXPECT_TRUE(HasError(either, "/constraints/temporal/T/event2", "\"ordered\": true"));
  auto seq = Errors({{"actions", acts}, {"sequence", {"B", "A"}}});
  EXPECT_TRUE(HasError(seq, "/constraints/sequence/1", "cannot be a step"));
  auto twice = Errors({{"actions", acts}, {"sequence", {"B", "B"}}});
  EXPECT_TRUE(HasError(twice, "/constraints/sequence/1", "already step 0"));
  auto shared = Errors({{"actions", acts}, {"event", {{"S", {"A", "B"}}}}});
  EXPECT_TRUE(HasError(shared, "/constraints/event/S/0", "every occurrence"));
}

TEST(ActionLoad, BothOrNeitherEndAndBadBounds) {
  Json acts = MustParse(R"({"A": {"automaton": "robot1", "command": "goToDoor1"}})");
  auto e = Errors({{"actions", acts},
                   {"temporal", {{"T", {{"event1", "A"}, {"accepting_event1_constraint", "true"},
                                        {"accepting_event2_constraint", "robot1[i+1]==atDoor1"},
                                        {"ordered", true}}},
                                 {"U", {{"event1", "A"}, {"ordered", true},
                                        {"accepting_event2_constraint", "robot1[i+1]==atDoor1"},
                                        {"lower_bound", 5}, {"upper_bound", 2}}},
                                 {"V", {{"event1", "A"}, {"event2", "A"}, {"ordered", "yes"}}}}},
                   {"forbidden", "A"}});
  EXPECT_TRUE(HasError(e, "/constraints/temporal/T", "not both"));
  EXPECT_TRUE(HasError(e, "/constraints/temporal/U/lower_bound", "greater than upper_bound"));
  EXPECT_TRUE(HasError(e, "/constraints/temporal/V/ordered", "boolean"));
  EXPECT_TRUE(HasError(e, "/constraints/forbidden", "array of action names"));
}

TEST(ActionLoad, AnActionNoRunCanTakeIsAWarning) {
  // Robots start outside; from atDoor2 a robot can never get back to atDoor1's way? It can: so
  // take a robot that starts rescued (final) instead.
  Json sp = Rescue(MustParse(R"({"actions": {"A": {"automaton": "robot2", "command": "goToDoor1"}}})"));
  sp["initial_state"]["robot2"] = "rescuedPerson2";
  Diagnostics diags;
  auto loaded = LoadStatePlan(sp, ShippedDomain("search_rescue"), diags);
  ASSERT_TRUE(loaded) << testing::AllErrors(diags);
  ASSERT_EQ(diags.warnings().size(), 1u);
  EXPECT_EQ(diags.warnings()[0].pointer, "/constraints/actions/A");
  EXPECT_NE(diags.warnings()[0].message.find("no run can take this action"), std::string::npos);
}

TEST(ActionLoad, WrittenBackItLoadsTheSame) {
  Json c = MustParse(R"({
    "actions": {"R1": {"automaton": "robot1", "from": "goingDoor3Person1", "to": "rescuedPerson1"},
                "R2": {"automaton": "robot2", "command": "goToDoor1", "occurrence": "every"},
                "O1": {"automaton": "robot1", "command": "openDoor1"}},
    "temporal": {"Then": {"event1": "R1", "event2": "R2", "ordered": true, "lower_bound": 0,
                          "upper_bound": 30},
                 "Either": {"event1": "O1", "accepting_event2_constraint": "door3l[i+1]==open",
                            "lower_bound": 0, "upper_bound": 5}},
    "sequence": ["O1", "R1"],
    "forbidden": ["R2"]})");
  const Domain& d = ShippedDomain("search_rescue");
  Diagnostics diags;
  auto sp = LoadStatePlan(Rescue(c), d, diags);
  ASSERT_TRUE(sp) << testing::AllErrors(diags);
  EXPECT_EQ(sp->actions.size(), 3u);
  EXPECT_EQ(sp->orders.size(), 3u);  // two named, one sequence step
  EXPECT_TRUE(sp->temporals.empty());
  Json back = StatePlanToJson(*sp, d);
  EXPECT_EQ(back["constraints"]["actions"], c["actions"]);
  EXPECT_EQ(back["constraints"]["sequence"], c["sequence"]);
  EXPECT_EQ(back["constraints"]["forbidden"], c["forbidden"]);
  EXPECT_EQ(back["constraints"]["temporal"]["Then"]["ordered"], true);
  auto again = LoadStatePlan(back, d, diags);
  ASSERT_TRUE(again) << testing::AllErrors(diags);
  EXPECT_EQ(StatePlanToJson(*again, d), back);
}

TEST(ActionLoad, TheRestatementSaysTheOrderInWords) {
  Json c = MustParse(R"({
    "actions": {"R1": {"automaton": "robot1", "command": "openDoor1"},
                "R2": {"automaton": "robot2", "command": "enterRoom1"},
                "Bad": {"automaton": "robot2", "command": "openDoor2"}},
    "temporal": {"Then": {"event1": "R1", "event2": "R2", "ordered": true, "upper_bound": 60}},
    "sequence": ["R1", "R2"],
    "forbidden": ["Bad"]})");
  const Domain& d = ShippedDomain("search_rescue");
  Diagnostics diags;
  auto sp = LoadStatePlan(Rescue(c), d, diags);
  ASSERT_TRUE(sp) << testing::AllErrors(diags);
  std::map<std::string, std::string> text;
  for (const auto& s : SummarizeStatePlan(d, *sp)) text[s["pointer"]] = s["text"];
  EXPECT_NE(text["/constraints/temporal/Then"].find(
                "First robot1 takes command openDoor1 (the first time) [action R1]; then, at that "
                "moment or later, robot2 takes command enterRoom1"),
            std::string::npos)
      << text["/constraints/temporal/Then"];
  EXPECT_NE(text["/constraints/temporal/Then"].find("within 0 to 60 s later"), std::string::npos);
  EXPECT_NE(text["/constraints/sequence"].find("then robot2 takes command enterRoom1"), std::string::npos);
  EXPECT_EQ(text["/constraints/forbidden"], "Never: robot2 takes command openDoor2 [action Bad].");
}

}  // namespace
}  // namespace ctb
