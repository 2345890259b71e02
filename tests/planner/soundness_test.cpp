// Regression tests for the planner's statuses (issue 8): each defect found in review, with the
// real minizinc and Gecode.
#include <gtest/gtest.h>

#include "planner/solve/parts.h"
#include "planner/solve/solve.h"
#include "test_util.h"

namespace ctb {
// A namespace of its own: the test executable's unity build puts files with same-named
// helpers side by side.
namespace soundness_test {
namespace {

struct Problem {
  Domain d;
  StatePlan sp;
};

Problem Load(const Json& domain, const Json& plan) {
  Diagnostics diags;
  auto d = LoadDomain(domain, diags);
  EXPECT_TRUE(d) << testing::AllErrors(diags);
  if (!d) return {};
  auto sp = LoadStatePlan(plan, *d, diags);
  EXPECT_TRUE(sp) << testing::AllErrors(diags);
  if (!sp) return {};
  return {std::move(*d), std::move(*sp)};
}

Json MustSolve(const Problem& p, SolveOptions o) {
  o.time_limit_ms = 120000;
  auto r = SolveDocument(p.d, p.sp, o);
  if (auto* e = std::get_if<Error>(&r)) {
    ADD_FAILURE() << e->ToString();
    return Json::object();
  }
  return std::get<Json>(r);
}

Json Switch(const std::string& n) {
  return {{"name", n}, {"locations", {"off", "on"}}, {"commands", {"turnOn"}},
          {"transitions", {{{"from", "off"}, {"to", "on"}, {"guard", n + "u[i]==turnOn"}}}}};
}

// Defect 1: three switches turned on at one event cost 3, more than max_cost * H = 1.
TEST(Soundness, SimultaneousTransitionsAreNotCutByTheCostBound) {
  Json dom = {{"name", "switches"}, {"automata", {Switch("s1"), Switch("s2"), Switch("s3")}}};
  Json plan = {
      {"initial_state", {{"s1", "off"}, {"s2", "off"}, {"s3", "off"}}},
      {"end_state",
       {{"maintenance_constraint", "not (s1l[i]==on /\\ s2l[i]==off /\\ s3l[i]==off)"},
        {"goal_constraint", "s1l[i+1]==on /\\ s2l[i+1]==on /\\ s3l[i+1]==on"}}},
      {"objective", "cost"}};
  Problem p = Load(dom, plan);
  SolveOptions fixed;
  fixed.horizon = 1;
  Json a = MustSolve(p, fixed);
  EXPECT_EQ(a["status"], "optimal");
  EXPECT_EQ(a["objective"]["value"], 3);
  SolveOptions grow;
  grow.max_horizon = 2;
  Json b = MustSolve(p, grow);
  EXPECT_EQ(b["status"], "optimal");
  EXPECT_EQ(b["objective"]["value"], 3);
}

// A lamp that warms up: off -(command)-> warm -(automatic, exactly w s)-> on.
Json WarmLamp(const std::string& n, int w) {
  return {{"name", n},
          {"locations", {"off", "warm", "on"}},
          {"commands", {"turnOn"}},
          {"transitions",
           {{{"from", "off"}, {"to", "warm"}, {"guard", n + "u[i]==turnOn"}},
            {{"from", "warm"}, {"to", "on"}, {"duration", {w, w}}}}}};
}

// A plain switch with both commands.
Json Toggle(const std::string& n) {
  return {{"name", n},
          {"locations", {"off", "on"}},
          {"commands", {"turnOn", "turnOff"}},
          {"transitions", {{{"from", "off"}, {"to", "on"}, {"guard", n + "u[i]==turnOn"}},
                           {{"from", "on"}, {"to", "off"}, {"guard", n + "u[i]==turnOff"}}}}};
}

// Defect 5: lamp2's episode can end on the event at which lamp1 finishes warming up (cost 3);
// solved apart, lamp2 must make an event of its own (off and on again: cost 5 in all).
TEST(Soundness, AnEpisodeMayEndOnAnotherPartsEvent) {
  Json dom = {{"name", "lamps"}, {"automata", {WarmLamp("lamp1", 10), Toggle("lamp2")}}};
  Json plan = {
      {"initial_state", {{"lamp1", "off"}, {"lamp2", "off"}}},
      {"end_state", {{"goal_constraint", "lamp1l[i+1]==on /\\ lamp2l[i+1]==on"}}},
      {"constraints",
       {{"episodes",
         {{"Lamp2On", {{"accepting_constraint", "lamp2l[i]==on"},
                       {"state_constraint", "lamp2l[i]==on"},
                       {"lower_bound", 10}, {"upper_bound", 10}}}}}}},
      {"objective", "cost"}};
  Problem p = Load(dom, plan);
  Json split = MustSolve(p, {});
  EXPECT_EQ(split["status"], "optimal");
  EXPECT_EQ(split["objective"]["value"], 3);
  SolveOptions mono;
  mono.decompose = false;
  EXPECT_EQ(MustSolve(p, mono)["objective"]["value"], 3);
}

// Defect 2: an episode whose accepting condition reads no automaton ("true", exactly 12 s) is
// met by any event at 12 s, here lamp1's; it must not force its own part to act later.
TEST(Soundness, AConstraintThatReadsNoAutomatonDoesNotStretchAPart) {
  Json dom = {{"name", "lamps"}, {"automata", {Toggle("lamp0"), WarmLamp("lamp1", 12)}}};
  Json plan = {
      {"initial_state", {{"lamp0", "off"}, {"lamp1", "off"}}},
      {"end_state", {{"goal_constraint", "lamp0l[i+1]==on /\\ lamp1l[i+1]==on"}}},
      {"constraints",
       {{"episodes", {{"Wait", {{"accepting_constraint", "true"},
                                {"lower_bound", 12}, {"upper_bound", 12}}}}}}},
      {"objective", "cost_then_makespan"}};
  Problem p = Load(dom, plan);
  Json split = MustSolve(p, {});
  SolveOptions mono;
  mono.decompose = false;
  Json whole = MustSolve(p, mono);
  EXPECT_EQ(whole["status"], "optimal");
  EXPECT_EQ(whole["objective"]["value"], Json({{"cost", 3}, {"makespan", 12}}));
  EXPECT_EQ(split["status"], "optimal");
  EXPECT_EQ(split["objective"]["value"], whole["objective"]["value"]);
}

// Defect 2, second half: a part that is infeasible on its own events but feasible with another
// part's events must not make the whole infeasible.
TEST(Soundness, APartInfeasibleAloneDoesNotMakeTheWholeInfeasible) {
  Json dom = {{"name", "lamps"}, {"automata", {WarmLamp("lamp1", 10), Toggle("lamp2")}}};
  Json plan = {
      {"initial_state", {{"lamp1", "off"}, {"lamp2", "off"}}},
      {"end_state", {{"goal_constraint", "lamp1l[i+1]==on /\\ lamp2l[i+1]==on"}}},
      {"constraints",
       {{"episodes",
         {{"Lamp2On", {{"accepting_constraint", "lamp2l[i]==on"},
                       {"state_constraint", "lamp2l[i]==on"},
                       {"lower_bound", 10}, {"upper_bound", 10}}}}}}},
      {"objective", "cost"}};
  Problem p = Load(dom, plan);
  SolveOptions o;
  o.max_horizon = 2;  // lamp2 alone would need 3 events
  Json a = MustSolve(p, o);
  EXPECT_EQ(a["status"], "optimal");
  EXPECT_EQ(a["objective"]["value"], 3);
}

// Defect 3: two parts that differ only in an upper bound are not "identical".
TEST(Soundness, PartsThatDifferInABoundAreNotReused) {
  auto episode = [](const std::string& n, int hi) {
    return Json{{"accepting_constraint", n + "l[i]==on"}, {"state_constraint", n + "l[i]==on"},
                {"lower_bound", 5}, {"upper_bound", hi}};
  };
  // lampA's episode may last up to 100 s, lampB's up to 50 s; both must end with an event while
  // on, and the goal asks for off: lampA's can end when it turns off at 60 s, lampB's cannot.
  Json dom = {{"name", "lamps"}, {"automata", {Toggle("lampA"), Toggle("lampB")}}};
  Json plan = {
      {"initial_state", {{"lampA", "off"}, {"lampB", "off"}}},
      {"end_state", {{"goal_constraint", "lampAl[i+1]==off /\\ lampBl[i+1]==off"}}},
      {"constraints",
       {{"episodes", {{"A", episode("lampA", 100)}, {"B", episode("lampB", 50)}}},
        {"temporal",
         {{"AOff", {{"accepting_event1_constraint", "lampAl[i]==off /\\ lampAl[i+1]==on"},
                    {"accepting_event2_constraint", "lampAl[i]==on /\\ lampAl[i+1]==off"},
                    {"lower_bound", 60}, {"upper_bound", 100}}},
          {"BOff", {{"accepting_event1_constraint", "lampBl[i]==off /\\ lampBl[i+1]==on"},
                    {"accepting_event2_constraint", "lampBl[i]==on /\\ lampBl[i+1]==off"},
                    {"lower_bound", 60}, {"upper_bound", 100}}}}}}},
      {"objective", "cost"}};
  Problem p = Load(dom, plan);
  Json reuse = MustSolve(p, {});
  SolveOptions apart;
  apart.reuse_identical_parts = false;
  Json no_reuse = MustSolve(p, apart);
  EXPECT_EQ(reuse["status"], no_reuse["status"]);
  EXPECT_EQ(reuse["objective"]["value"], no_reuse["objective"]["value"]);
  EXPECT_NE(reuse["stats"].value("parts_reused", 0), 1);
}

// The key under which parts are reused is horizon-independent and tells the bounds apart, while
// names do not count.
TEST(Soundness, TheCanonicalFormOfAPartIgnoresNamesButNotBounds) {
  auto problem = [](const std::string& n, int hi) {
    Json dom = {{"name", "one"}, {"automata", {Toggle(n)}}};
    Json plan = {{"initial_state", {{n, "off"}}},
                 {"end_state", {{"goal_constraint", n + "l[i+1]==off"}}},
                 {"constraints", {{"episodes", {{n + "Ep", {{"accepting_constraint", n + "l[i]==on"},
                                                            {"lower_bound", 5},
                                                            {"upper_bound", hi}}}}}}}};
    return Load(dom, plan);
  };
  Problem a = problem("lampA", 100), b = problem("lampB", 100), c = problem("lampC", 50);
  const std::string fa = solve::CanonicalForm(a.d, a.sp, Objective::kCost);
  EXPECT_EQ(fa, solve::CanonicalForm(b.d, b.sp, Objective::kCost));
  EXPECT_NE(fa, solve::CanonicalForm(c.d, c.sp, Objective::kCost));
  EXPECT_NE(fa, solve::CanonicalForm(a.d, a.sp, Objective::kMakespan));
  EXPECT_EQ(fa.find("lamp"), std::string::npos);
}

// Defect 4: costs that overflow the solver's integers are refused with a located error, not an
// internal failure.
TEST(Soundness, UnrepresentableCostsAreALocatedError) {
  Json big = Toggle("lamp");
  big["transitions"][0]["cost"] = 1000000;
  Json dom = {{"name", "big"}, {"automata", {big, WarmLamp("slow", 100000)}}};
  Json plan = {{"initial_state", {{"lamp", "off"}, {"slow", "off"}}},
               {"end_state", {{"goal_constraint", "lampl[i+1]==on /\\ slowl[i+1]==on"}}},
               {"objective", "cost_then_makespan"}};
  Problem p = Load(dom, plan);
  auto r = SolveDocument(p.d, p.sp, {});
  ASSERT_TRUE(std::holds_alternative<Error>(r));
  const Error& e = std::get<Error>(r);
  EXPECT_EQ(e.code, ErrorCode::kInvalidInput);
  ASSERT_FALSE(e.details.empty());
  EXPECT_EQ(e.details[0].pointer, "/automata/0/transitions/0/cost");
  EXPECT_NE(e.details[0].message.find("integer range"), std::string::npos);
  // The same costs with the cost objective fit.
  SolveOptions cost;
  cost.objective = Objective::kCost;
  EXPECT_TRUE(std::holds_alternative<Json>(SolveDocument(p.d, p.sp, cost)));
}


// Issue 14's loader cases: a fine resolution with long durations overflows the ticks (a located
// 400, not a solver failure); an absurdly fine resolution is refused at load.
TEST(Soundness, TicksBeyondTheIntegerRangeAreALocatedError) {
  Json slow = WarmLamp("slow", 10000000);
  Json dom = {{"name", "fine"}, {"time_resolution", 0.001}, {"automata", {slow}}};
  Json plan = {{"initial_state", {{"slow", "off"}}},
               {"end_state", {{"goal_constraint", "slowl[i+1]==on"}}}};
  Problem p = Load(dom, plan);
  auto r = SolveDocument(p.d, p.sp, {});
  ASSERT_TRUE(std::holds_alternative<Error>(r));
  const Error& e = std::get<Error>(r);
  EXPECT_EQ(e.code, ErrorCode::kInvalidInput);
  ASSERT_FALSE(e.details.empty());
  EXPECT_EQ(e.details[0].pointer, "/automata/0/transitions/1/duration");

  Diagnostics diags;
  Json tiny = {{"name", "tiny"}, {"time_resolution", 1e-300}, {"automata", {Toggle("lamp")}}};
  EXPECT_FALSE(LoadDomain(tiny, diags));
  EXPECT_TRUE(testing::HasError(diags, "/time_resolution", "[0.000001, 1]")) << testing::AllErrors(diags);
}

}  // namespace
}  // namespace soundness_test
}  // namespace ctb
