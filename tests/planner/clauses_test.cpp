// Conditions as clauses over location facts (planner/analyze/clauses.h) and the first-plan
// engine's choice of one fact per clause (planner/search/goal_clauses.h).
#include "planner/analyze/clauses.h"

#include <limits>

#include <gtest/gtest.h>

#include "planner/search/goal_clauses.h"
#include "test_util.h"

namespace ctb {
namespace {

// The goal's clauses on the shipped search_rescue domain (robot1 = 0, robot2 = 1).
Clauses GoalClauses(const std::string& goal) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  Json j = testing::MustParse(R"({
    "initial_state": {"robot1": "outside", "robot2": "outside", "door1": "closed",
                      "door2": "closed", "door3": "open"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint": ""}})");
  j["end_state"]["goal_constraint"] = goal;
  Diagnostics diags;
  auto sp = LoadStatePlan(j, d, diags);
  if (!sp) {
    ADD_FAILURE() << goal << testing::AllErrors(diags);
    return {};
  }
  return ToClauses(sp->goal.expr);
}

int Loc(const std::string& name) {
  const auto& locs = testing::ShippedDomain("search_rescue").automata[0].locations;
  return static_cast<int>(std::find(locs.begin(), locs.end(), name) - locs.begin());
}

TEST(Clauses, ADisjunctionPerPersonIsAClausePerPerson) {
  const Clauses c = GoalClauses(
      "(robot1l[i+1]==rescuedPerson1 \\/ robot2l[i+1]==rescuedPerson1) /\\ "
      "(robot1l[i+1]==rescuedPerson2 \\/ robot2l[i+1]==rescuedPerson2)");
  const int p1 = Loc("rescuedPerson1"), p2 = Loc("rescuedPerson2");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0], (Clause{{0, p1}, {1, p1}}));
  EXPECT_EQ(c[1], (Clause{{0, p2}, {1, p2}}));
}

TEST(Clauses, AConjunctionInADisjunctionIsDistributed) {
  const Clauses c = GoalClauses(
      "(robot1l[i+1]==rescuedPerson1 /\\ robot2l[i+1]==rescuedPerson2) \\/ "
      "robot1l[i+1]==rescuedPerson2");
  const int p1 = Loc("rescuedPerson1"), p2 = Loc("rescuedPerson2");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0], (Clause{{0, p1}, {0, p2}}));
  EXPECT_EQ(c[1], (Clause{{1, p2}, {0, p2}}));
}

TEST(Clauses, OtherLiteralsSatisfyTheirClause) {
  // A negation needs nothing; in a disjunction it makes the whole clause free.
  EXPECT_TRUE(GoalClauses("robot1l[i+1]!=outside").empty());
  EXPECT_TRUE(GoalClauses("robot1l[i+1]!=outside \\/ robot2l[i+1]==rescuedPerson1").empty());
  const Clauses c = GoalClauses("robot1l[i+1]!=outside /\\ robot2l[i+1]==rescuedPerson1");
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0], (Clause{{1, Loc("rescuedPerson1")}}));
}

TEST(Clauses, ProductsAreCapped) {
  // Ten disjunctions of two conjunctions of ten: 10^10 clauses in full.
  std::string goal;
  for (int k = 0; k < 10; ++k) {
    goal += k ? " \\/ " : "";
    goal += "(robot1l[i+1]==rescuedPerson1 /\\ robot2l[i+1]==rescuedPerson2)";
  }
  EXPECT_LE(GoalClauses(goal).size(), kMaxClauses);
}

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(ChooseFacts, OneLocationPerAutomatonOnOneStage) {
  // Automaton 0 is the cheaper for both clauses; on one stage it can serve one of them only.
  const Clauses c = {{{0, 1}, {1, 1}}, {{0, 2}, {1, 2}}};
  auto cost = [](const LocationAtom& f) { return f.first == 0 ? 1.0 : 5.0; };
  std::vector<LocationAtom> out;
  ASSERT_TRUE(search::ChooseFacts(c, true, cost, out));
  EXPECT_EQ(out, (std::vector<LocationAtom>{{0, 1}, {1, 2}}));
  out.clear();
  ASSERT_TRUE(search::ChooseFacts(c, false, cost, out));  // a change: two stages
  EXPECT_EQ(out, (std::vector<LocationAtom>{{0, 1}, {0, 2}}));
}

TEST(ChooseFacts, AFactServesEveryClauseThatHoldsIt) {
  const Clauses c = {{{0, 1}, {1, 3}}, {{1, 2}, {0, 1}}};
  auto cost = [](const LocationAtom& f) { return f == LocationAtom{0, 1} ? 2.0 : 1.0; };
  std::vector<LocationAtom> out;
  ASSERT_TRUE(search::ChooseFacts(c, true, cost, out));
  // (1,3) first (cheapest), then (1,2) conflicts with it: (0,1) serves the second clause.
  EXPECT_EQ(out, (std::vector<LocationAtom>{{1, 3}, {0, 1}}));
}

TEST(ChooseFacts, NothingConsistentLeftTakesTheCheapest) {
  const Clauses c = {{{0, 1}}, {{0, 2}}};  // contradictory on one stage
  auto cost = [](const LocationAtom& f) { return static_cast<double>(f.second); };
  std::vector<LocationAtom> out;
  ASSERT_TRUE(search::ChooseFacts(c, true, cost, out));
  EXPECT_EQ(out, (std::vector<LocationAtom>{{0, 1}, {0, 2}}));
}

TEST(ChooseFacts, AnUnreachableClauseIsDead) {
  const Clauses c = {{{0, 1}}, {{0, 2}, {1, 2}}};
  auto cost = [](const LocationAtom& f) { return f.second == 2 ? kInf : 1.0; };
  std::vector<LocationAtom> out;
  EXPECT_FALSE(search::ChooseFacts(c, true, cost, out));
  EXPECT_FALSE(search::ChooseFacts({Clause{}}, true, cost, out));  // false
  out.clear();
  EXPECT_TRUE(search::ChooseFacts({}, true, cost, out));  // true
  EXPECT_TRUE(out.empty());
}

}  // namespace
}  // namespace ctb
