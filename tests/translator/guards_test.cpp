// Meaning guards.
#include "translator/guards.h"

#include <gtest/gtest.h>

#include "../planner/test_util.h"

namespace ctb {
// A namespace of its own: the test executable's unity build puts files with same-named
// helpers side by side.
namespace guards_test {
namespace {

const Domain& Presentation() { return ctb::testing::ShippedDomain("presentation"); }

StatePlan Load(const Json& j) {
  Diagnostics d;
  auto sp = LoadStatePlan(j, Presentation(), d);
  if (!sp) ADD_FAILURE() << (d.errors().empty() ? "" : d.errors()[0].ToString());
  return sp ? *sp : StatePlan{};
}

Json Off(const std::string& goal) {
  return {{"initial_state", {{"comp", "compOff"}, {"conn", "disconnected"}, {"proj", "projOff"}}},
          {"end_state", {{"maintenance_constraint", "true"}, {"goal_constraint", goal}}}};
}

TEST(StatedDurations, NumbersWithTimeUnitsOnly) {
  auto d = StatedDurations(
      "stay on for 1800 seconds, off within 10 min, in 2h; rescue Person 1 and 3 robots");
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0], "1800 seconds");
  EXPECT_EQ(d[1], "10 min");
  EXPECT_EQ(d[2], "2h");
  EXPECT_TRUE(StatedDurations("Both robots must rescue Person 1 as fast as possible.").empty());
}

TEST(GoalHoldsAtStart, AnEmptyPlanIsCaughtAChangeOrAConstraintIsNot) {
  EXPECT_TRUE(
      GoalHoldsAtStart(Load(Off("projl[i+1]==projOff /\\ compl[i+1]==compOff")), Presentation()));
  EXPECT_FALSE(GoalHoldsAtStart(Load(Off("projl[i+1]==projOn")), Presentation()));
  EXPECT_FALSE(
      GoalHoldsAtStart(Load(Off("projl[i]==projOn /\\ projl[i+1]==projOff")), Presentation()));
  Json with_episode = Off("projl[i+1]==projOff");
  with_episode["constraints"]["episodes"]["On"] = {{"accepting_constraint", "projl[i]==projOn"},
                                                   {"state_constraint", "projl[i]==projOn"},
                                                   {"lower_bound", 10},
                                                   {"upper_bound", 10}};
  EXPECT_FALSE(GoalHoldsAtStart(Load(with_episode), Presentation()));
}

TEST(CheckMeaning, DurationsWithoutConstraintsBlock) {
  Json j = Off("projl[i+1]==projOn");
  auto f = CheckMeaning(j, Load(j), Presentation(), "Turn the projector on within 60 seconds.");
  ASSERT_EQ(f.blocking.size(), 1u);
  EXPECT_EQ(f.blocking[0].pointer, "/constraints");
  EXPECT_NE(f.blocking[0].message.find("\"60 seconds\""), std::string::npos);
  EXPECT_TRUE(CheckMeaning(j, Load(j), Presentation(), "Turn the projector on.").blocking.empty());
}

// An order between actions (contract section 15) carries the command's durations: no block, and a
// goal that holds at the start with an order is not an empty plan (found by the eval suite).
TEST(CheckMeaning, AnOrderCarriesDurations) {
  Json j = Off("projl[i+1]==projOff");
  j["constraints"] = {{"actions", {{"Connect", {{"automaton", "conn"}, {"command", "connect"}}},
                                   {"Disconnect", {{"automaton", "conn"}, {"command", "disconnect"}}}}},
                      {"temporal", {{"Later", {{"event1", "Connect"}, {"event2", "Disconnect"},
                                               {"ordered", true}, {"lower_bound", 60}}}}}};
  auto f = CheckMeaning(j, Load(j), Presentation(), "Connect, then disconnect at least 60 seconds later.");
  EXPECT_TRUE(f.blocking.empty()) << f.blocking[0].message;
  EXPECT_TRUE(f.doubtful.empty()) << f.doubtful[0].message;
}

TEST(CheckMeaning, AnEmptyPlanIsADoubt) {
  Json j = Off("projl[i+1]==projOff");
  auto f = CheckMeaning(j, Load(j), Presentation(), "Everything off.");
  EXPECT_TRUE(f.blocking.empty());
  ASSERT_EQ(f.doubtful.size(), 1u);
  EXPECT_EQ(f.doubtful[0].pointer, "/end_state/goal_constraint");
}

TEST(DefaultedStateConstraints, OneWarningPerEpisodeWithoutOne) {
  Json j = Off("projl[i+1]==projOff");
  j["constraints"]["episodes"]["A"] = {
      {"accepting_constraint", "projl[i]==projOn"}, {"lower_bound", 1}, {"upper_bound", 1}};
  j["constraints"]["episodes"]["B"] = {{"accepting_constraint", "projl[i]==projOn"},
                                       {"state_constraint", "projl[i]==projOn"},
                                       {"lower_bound", 1},
                                       {"upper_bound", 1}};
  auto w = DefaultedStateConstraints(j);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].pointer, "/constraints/episodes/A/state_constraint");
}

TEST(Dropped, ConstraintsAndGoalPartsLostInARepair) {
  Json before = Off("projl[i+1]==projOff /\\ compl[i+1]==compOff");
  before["constraints"]["temporal"]["T1"] = Json::object();
  before["constraints"]["temporal"]["T2"] = Json::object();
  Json after = Off("projl[i+1]==projOff");
  after["constraints"]["temporal"]["T1"] = Json::object();
  auto d = Dropped(before, after);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0].pointer, "/constraints/temporal");
  EXPECT_NE(d[0].message.find("'T2'"), std::string::npos);
  EXPECT_EQ(d[1].pointer, "/end_state/goal_constraint");
  EXPECT_NE(d[1].message.find("compl[i+1]"), std::string::npos) << d[1].message;
  EXPECT_TRUE(Dropped(after, before).empty());
  EXPECT_TRUE(Dropped(before, before).empty());
}

}  // namespace
}  // namespace guards_test
}  // namespace ctb
