// Static analysis: infeasibility proved without search (issue 10, part 2). Soundness against the
// real solver is checked in explain_test.cpp (solver group).
#include "planner/analyze/analyze.h"

#include <gtest/gtest.h>

#include <chrono>
#include <set>

#include "test_util.h"

namespace ctb {
namespace {

StatePlan Data(const std::string& domain, const std::string& name) {
  return testing::ShippedStatePlan(domain, testing::SourceDir() + "/tests/data/" + name);
}

std::optional<double> HintFor(const StaticConflict& c, const std::string& pointer) {
  for (const auto& h : c.hints)
    if (h.pointer == pointer) return h.value;
  return std::nullopt;
}

std::set<std::string> Parts(const std::optional<StaticConflict>& c) {
  return c ? std::set<std::string>(c->parts.begin(), c->parts.end()) : std::set<std::string>{};
}

TEST(Analyze, DeadlineBelowWarmUp) {
  const Domain& d = testing::ShippedDomain("presentation");
  auto c = FindStaticConflict(d, Data("presentation", "deadline_infeasible.json"));
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind, "deadline");
  EXPECT_EQ(Parts(c), std::set<std::string>{"/constraints/temporal/OnWithin10"});
  ASSERT_TRUE(c->hint);
  EXPECT_EQ(c->hint->pointer, "/constraints/temporal/OnWithin10/upper_bound");
  EXPECT_EQ(c->hint->value, 30);  // the warm-up
  EXPECT_NE(c->text.find("30 s"), std::string::npos) << c->text;
  EXPECT_NE(c->text.find("10 s"), std::string::npos) << c->text;
}

TEST(Analyze, DeadlineBelowBoot) {
  const Domain& d = testing::ShippedDomain("presentation");
  auto c = FindStaticConflict(d, Data("presentation", "explain/deadline_boot.json"));
  ASSERT_TRUE(c);
  EXPECT_EQ(Parts(c), std::set<std::string>{"/constraints/temporal/BootedWithin10"});
  ASSERT_TRUE(c->hint);
  EXPECT_EQ(c->hint->value, 15);
}

TEST(Analyze, ChangeNoTransitionAllows) {
  const Domain& d = testing::ShippedDomain("presentation");
  auto c = FindStaticConflict(d, Data("presentation", "explain/change_not_allowed.json"));
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind, "never_holds");
  EXPECT_EQ(Parts(c), std::set<std::string>{"/constraints/episodes/StraightOn"});
  EXPECT_NE(c->text.find("no transition takes proj from projOff to projOn"), std::string::npos)
      << c->text;
}

TEST(Analyze, ThesisDirectAnswerToTestPrompt2) {
  const Domain& d = testing::ShippedDomain("presentation");
  auto c = FindStaticConflict(
      d, testing::ShippedStatePlan("presentation", testing::ConfigDir() + "/examples/presentation/test2_direct.json"));
  ASSERT_TRUE(c);
  EXPECT_EQ(Parts(c), std::set<std::string>{"/constraints/temporal/last600"});
  EXPECT_NE(c->text.find("no transition takes comp from compOn to compBooting"), std::string::npos)
      << c->text;
}

TEST(Analyze, UnreachableGoalLocation) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  auto c = FindStaticConflict(d, Data("search_rescue", "explain/unreachable.json"));
  ASSERT_TRUE(c);
  EXPECT_EQ(Parts(c), std::set<std::string>{"/end_state/goal_constraint"});
  EXPECT_NE(c->text.find("robot1 cannot reach rescuedPerson1 from rescuedPerson2"), std::string::npos)
      << c->text;
}

TEST(Analyze, EpisodesThatMustStartTogetherButCannot) {
  const Domain& d = testing::ShippedDomain("presentation");
  auto c = FindStaticConflict(d, Data("presentation", "explain/overlap.json"));
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind, "shared_event");
  EXPECT_EQ(Parts(c), (std::set<std::string>{"/constraints/event/TogetherFromTheStart",
                                              "/constraints/episodes/ProjectorOn",
                                              "/constraints/episodes/ProjectorDark"}));
}

TEST(Analyze, MaintenanceBlocksTheOnlyRoute) {
  const Domain& d = testing::ShippedDomain("presentation");
  auto c = FindStaticConflict(d, Data("presentation", "explain/maintenance_blocks.json"));
  ASSERT_TRUE(c);
  EXPECT_EQ(Parts(c), (std::set<std::string>{"/end_state/goal_constraint",
                                              "/end_state/maintenance_constraint"}));
  // Without the maintenance constraint the goal is fine: the guard (connected) is what blocks.
  Json j = testing::MustParse(R"({"initial_state": {"comp": "compOff", "conn": "disconnected",
      "proj": "projOff"}, "end_state": {"goal_constraint": "projl[i+1]==projOn"}})");
  Diagnostics diags;
  auto sp = LoadStatePlan(j, d, diags);
  ASSERT_TRUE(sp);
  EXPECT_FALSE(FindStaticConflict(d, *sp));
}

TEST(Analyze, DoorsKeptShutBlockEveryRoute) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  Json j = testing::MustParse(R"({"initial_state": {"robot1": "outside", "robot2": "outside",
      "door1": "closed", "door2": "closed", "door3": "open"},
      "end_state": {"maintenance_constraint": "door1[i]==closed /\\ door2[i]==closed",
                    "goal_constraint": "robot1[i+1]==rescuedPerson1"}})");
  Diagnostics diags;
  auto sp = LoadStatePlan(j, d, diags);
  ASSERT_TRUE(sp) << testing::AllErrors(diags);
  auto c = FindStaticConflict(d, *sp);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->parts.size(), 2u);
  // One door shut leaves the other way.
  j["end_state"]["maintenance_constraint"] = "door1[i]==closed";
  sp = LoadStatePlan(j, d, diags);
  ASSERT_TRUE(sp);
  EXPECT_FALSE(FindStaticConflict(d, *sp));
}

// The computer on within 20 s and the projector on (and connected) within 40 s, the connection
// only while the computer is off: whichever comes first, the other is late. The time network
// splits on the order of the two events (a disjunctive temporal network); at the connection the
// computer is off (the maintenance constraint on the stage before, and the connect guard).
TEST(Analyze, ConflictsInEitherOrderAreProvenByASplit) {
  const Domain& d = testing::ShippedDomain("presentation");
  auto c = FindStaticConflict(d, Data("presentation", "explain/three_together.json"));
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind, "time_network");
  EXPECT_EQ(Parts(c), (std::set<std::string>{"/end_state/maintenance_constraint",
                                             "/constraints/temporal/ComputerOnWithin20",
                                             "/constraints/temporal/ProjectorOnWithin40"}));
  EXPECT_NE(c->text.find("whichever order"), std::string::npos) << c->text;
  // Projector first: on at 30 s at the earliest, then the computer boots 15 s: 45 s.
  EXPECT_EQ(HintFor(*c, "/constraints/temporal/ComputerOnWithin20/upper_bound"), 45);
  // Computer first (on at 15 s), then 30 s to shut it down before connecting: 45 s. The real
  // least is 75 s, the warm-up after the connection: beyond the network, and the zone search's
  // hint replaces it.
  EXPECT_EQ(HintFor(*c, "/constraints/temporal/ProjectorOnWithin40/upper_bound"), 75);
  auto network = FindStaticConflict(d, Data("presentation", "explain/three_together.json"),
                                    AnalysisOptions{.zones = false});
  ASSERT_TRUE(network);
  EXPECT_EQ(HintFor(*network, "/constraints/temporal/ProjectorOnWithin40/upper_bound"), 45);
}

// Beyond the time network (it refutes the projector deadline below 45 s; 75 s are needed: the
// warm-up comes after the connection, an event no part names): the zone search proves it.
TEST(Analyze, ConflictsBeyondTheNetworkAreTheZoneSearchs) {
  const Domain& d = testing::ShippedDomain("presentation");
  const StatePlan sp = Data("presentation", "explain/three_together_60.json");
  EXPECT_FALSE(FindStaticConflict(d, sp, AnalysisOptions{.zones = false}));
  auto c = FindStaticConflict(d, sp);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind, "zones");
  EXPECT_EQ(Parts(c), (std::set<std::string>{"/end_state/maintenance_constraint",
                                             "/constraints/temporal/ComputerOnWithin20",
                                             "/constraints/temporal/ProjectorOnWithin40"}));
  ASSERT_TRUE(c->hint);
  EXPECT_EQ(HintFor(*c, "/constraints/temporal/ProjectorOnWithin40/upper_bound"), 75);
}

TEST(Analyze, FeasibleShippedExamplesHaveNoConflictAndTakeMilliseconds) {
  const char* feasible[][2] = {{"presentation", "presentation/test1_cot.json"},
                               {"presentation", "presentation/test1_direct.json"},
                               {"presentation", "presentation/test2_cot.json"},
                               {"presentation", "presentation/incontext.json"},
                               {"search_rescue", "search_rescue/test1.json"},
                               {"search_rescue", "search_rescue/test2.json"},
                               {"search_rescue", "search_rescue/incontext.json"},
                               {"assembly", "assembly/test.json"},
                               {"assembly", "assembly/incontext.json"}};
  for (auto& [dom, file] : feasible) {
    SCOPED_TRACE(file);
    const Domain& d = testing::ShippedDomain(dom);
    StatePlan sp = testing::ShippedStatePlan(dom, testing::ConfigDir() + "/examples/" + file);
    auto t0 = std::chrono::steady_clock::now();
    auto all = FindStaticConflicts(d, sp);
    auto ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_TRUE(all.empty()) << all[0].text;
    EXPECT_LT(ms, 200) << "static checks are meant to take milliseconds";
  }
}

TEST(Analyze, ShortestTimeFollowsLowerDurations) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Data("presentation", "deadline_infeasible.json");
  const int proj = d.AutomatonIndex("proj");
  const Automaton& p = d.automata[proj];
  EXPECT_EQ(ShortestTime(d, sp, proj, p.LocationIndex("projWarmUp"), p.LocationIndex("projOn")), 30);
  EXPECT_EQ(ShortestTime(d, sp, proj, p.LocationIndex("projOn"), p.LocationIndex("projOff")), 60);
  EXPECT_EQ(ShortestTime(d, sp, proj, p.LocationIndex("projOff"), p.LocationIndex("projOn")), 30);
}


// The time network (issue 20): the three impossible requests of the issue, proven for any number
// of events, with the parts on the negative cycle and the least bounds it no longer refutes.
StatePlan Impossible(const std::string& domain, const std::string& name) {
  return testing::ShippedStatePlan(domain, testing::ConfigDir() + "/examples/" + domain + "/" + name);
}

TEST(Analyze, OffWithinLessThanTheCoolDownAfterLeavingOn) {
  const Domain& d = testing::ShippedDomain("presentation");
  auto c = FindStaticConflict(d, Impossible("presentation", "impossible_off_within59.json"));
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind, "time_network");
  EXPECT_EQ(Parts(c), std::set<std::string>{"/constraints/temporal/OffWithin59"});
  EXPECT_EQ(HintFor(*c, "/constraints/temporal/OffWithin59/upper_bound"), 60);
}

TEST(Analyze, OnForLongerThanTheDeadlineAfterWarmUpAllows) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Impossible("presentation", "impossible_on1800_off1500.json");
  auto c = FindStaticConflict(d, sp);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind, "time_network");
  EXPECT_EQ(Parts(c), (std::set<std::string>{"/constraints/episodes/ProjectorOnDuration",
                                             "/constraints/temporal/OffWithin1500OfWarmUp"}));
  // 30 s warm-up + 1800 s on + 60 s cool-down.
  EXPECT_EQ(HintFor(*c, "/constraints/temporal/OffWithin1500OfWarmUp/upper_bound"), 1890);
  EXPECT_EQ(HintFor(*c, "/constraints/episodes/ProjectorOnDuration/lower_bound"), 1410);
  // At 1890 s the network has nothing to say.
  sp.temporals[0].upper = 1890;
  EXPECT_FALSE(FindStaticConflict(d, sp));
}

TEST(Analyze, DoorKeptShutAndARescueDeadline) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  StatePlan sp = Impossible("search_rescue", "impossible_door_shut_deadline.json");
  auto c = FindStaticConflict(d, sp);
  ASSERT_TRUE(c);
  EXPECT_EQ(Parts(c), (std::set<std::string>{"/constraints/temporal/RescueWithin12",
                                             "/end_state/maintenance_constraint"}));
  // Door 2 opens 1 s after a robot reaches it (10 s), then 2 s to person 1.
  EXPECT_EQ(HintFor(*c, "/constraints/temporal/RescueWithin12/upper_bound"), 13);
  sp.temporals[0].upper = 13;
  EXPECT_FALSE(FindStaticConflict(d, sp));
}

}  // namespace
}  // namespace ctb
