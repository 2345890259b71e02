// Symmetry detection (issue 18, lever 4): interchangeable automata found from the checked trees,
// and their ordering in the encoding. Soundness against the solver is checked in
// symmetry_differential_test.cpp.
#include "planner/analyze/symmetry.h"

#include <gtest/gtest.h>

#include "planner/encode/encoder.h"
#include "test_util.h"

namespace ctb {
namespace {

// Robots r1..rn: home -> going (command go, when the gate is open) -> there after `dur` s. The
// gate opens (1 s) when some robot is going, read as one disjunction over every robot.
Json Robots(int n, const std::vector<int>& durations = {}, const std::string& odd_guard = "") {
  Json automata = Json::array();
  std::string someone;
  for (int k = 1; k <= n; ++k) {
    const std::string r = "r" + std::to_string(k);
    const int dur = k - 1 < static_cast<int>(durations.size()) ? durations[k - 1] : 3;
    std::string guard = r + "u[i]==go /\\ gatel[i]==open";
    if (k == n && !odd_guard.empty()) guard = odd_guard;
    automata.push_back({{"name", r},
                        {"locations", {"home", "going", "there"}},
                        {"commands", {"go"}},
                        {"transitions",
                         {{{"from", "home"}, {"to", "going"}, {"guard", guard}},
                          {{"from", "going"}, {"to", "there"}, {"duration", {dur, dur}}}}}});
    someone += (k > 1 ? " \\/ " : "") + r + "l[i]==going";
  }
  automata.push_back({{"name", "gate"},
                      {"locations", {"closed", "opening", "open"}},
                      {"commands", Json::array()},
                      {"transitions",
                       {{{"from", "closed"}, {"to", "opening"}, {"guard", someone}},
                        {{"from", "opening"}, {"to", "open"}, {"duration", {1, 1}}}}}});
  return {{"name", "robots"}, {"description", "test"}, {"automata", automata}};
}

// Units k = 1..n of a computer compK and a projector projK whose switch-on reads its computer.
Json Units(int n) {
  Json automata = Json::array();
  for (int k = 1; k <= n; ++k) {
    const std::string c = "comp" + std::to_string(k), p = "proj" + std::to_string(k);
    automata.push_back(
        {{"name", c},
         {"locations", {"off", "on"}},
         {"commands", {"turnOn"}},
         {"transitions", {{{"from", "off"}, {"to", "on"}, {"guard", c + "u[i]==turnOn"}}}}});
    automata.push_back(
        {{"name", p},
         {"locations", {"off", "warm", "on"}},
         {"commands", {"turnOn"}},
         {"transitions",
          {{{"from", "off"}, {"to", "warm"}, {"guard", p + "u[i]==turnOn /\\ " + c + "l[i]==on"}},
           {{"from", "warm"}, {"to", "on"}, {"duration", {2, 2}}}}}});
  }
  return {{"name", "units"}, {"description", "test"}, {"automata", automata}};
}

Json Plan(const Json& initial, const std::string& goal, Json episodes = Json::object(),
          Json temporal = Json::object(), Json events = Json::object(),
          const std::string& maintenance = "true") {
  return {{"initial_state", initial},
          {"end_state", {{"maintenance_constraint", maintenance}, {"goal_constraint", goal}}},
          {"constraints", {{"episodes", episodes}, {"temporal", temporal}, {"event", events}}}};
}

Json RobotsHome(int n) {
  Json init = {{"gate", "closed"}};
  for (int k = 1; k <= n; ++k) init["r" + std::to_string(k)] = "home";
  return init;
}

struct Problem {
  Domain d;
  StatePlan sp;
};

Problem Load(const Json& domain, const Json& plan) {
  Diagnostics diags;
  auto d = LoadDomain(domain, diags);
  if (!d) {
    ADD_FAILURE() << testing::AllErrors(diags);
    return {};
  }
  auto sp = LoadStatePlan(plan, *d, diags);
  if (!sp) {
    ADD_FAILURE() << testing::AllErrors(diags);
    return {};
  }
  return {*d, *sp};
}

std::vector<std::vector<std::vector<int>>> Orbits(const Json& domain, const Json& plan) {
  Problem p = Load(domain, plan);
  std::vector<std::vector<std::vector<int>>> out;
  for (const auto& o : FindSymmetries(p.d, p.sp)) out.push_back(o.units);
  return out;
}

using Units_ = std::vector<std::vector<std::vector<int>>>;

const char* kAnyThere = "r1l[i+1]==there \\/ r2l[i+1]==there";

TEST(Symmetry, FreeAssignmentIsOneOrbit) {
  // Three robots, each one must arrive: the goal is invariant, the gate reads all three.
  EXPECT_EQ(Orbits(Robots(3), Plan(RobotsHome(3),
                                   "r1l[i+1]==there /\\ r3l[i+1]==there /\\ "
                                   "r2l[i+1]==there")),
            (Units_{{{0}, {1}, {2}}}));
  EXPECT_EQ(Orbits(Robots(2), Plan(RobotsHome(2), kAnyThere)), (Units_{{{0}, {1}}}));
  // Operands of \/ and <-> in another order are the same condition.
  EXPECT_EQ(Orbits(Robots(2), Plan(RobotsHome(2),
                                   "(r2l[i+1]==there <-> r1l[i+1]==home) \\/ "
                                   "(r2l[i+1]==home <-> r1l[i+1]==there)")),
            (Units_{{{0}, {1}}}));
}

TEST(Symmetry, DifferentDurationIsNotSymmetric) {
  EXPECT_TRUE(Orbits(Robots(2, {3, 4}), Plan(RobotsHome(2), kAnyThere)).empty());
  // Two of three alike: only those two.
  EXPECT_EQ(Orbits(Robots(3, {3, 4, 3}), Plan(RobotsHome(3),
                                              "r1l[i+1]==there /\\ "
                                              "r2l[i+1]==there /\\ r3l[i+1]==there")),
            (Units_{{{0}, {2}}}));
}

TEST(Symmetry, DifferentGuardIsNotSymmetric) {
  EXPECT_TRUE(
      Orbits(Robots(2, {}, "r2u[i]==go /\\ gatel[i]==closed"), Plan(RobotsHome(2), kAnyThere))
          .empty());
  // A guard that reads the other robot is symmetric only when the other one reads back.
  EXPECT_TRUE(Orbits(Robots(2, {}, "r2u[i]==go /\\ r1l[i]==there"), Plan(RobotsHome(2), kAnyThere))
                  .empty());
}

TEST(Symmetry, AsymmetricStatePlanIsNotSymmetric) {
  EXPECT_TRUE(Orbits(Robots(2), Plan(RobotsHome(2), "r1l[i+1]==there")).empty());
  EXPECT_TRUE(
      Orbits(Robots(2), Plan(RobotsHome(2), "r1l[i+1]==there /\\ r2l[i+1]==going")).empty());
  Json init = RobotsHome(2);
  init["r2"] = "going";
  EXPECT_TRUE(Orbits(Robots(2), Plan(init, kAnyThere)).empty());
  EXPECT_TRUE(Orbits(Robots(2), Plan(RobotsHome(2), kAnyThere, Json::object(), Json::object(),
                                     Json::object(), "r1l[i]!=going"))
                  .empty());
}

Json Stay(const std::string& robot, double lo, double hi) {
  return {{"accepting_constraint", robot + "l[i]==going"},
          {"state_constraint", robot + "l[i]==going"},
          {"lower_bound", lo},
          {"upper_bound", hi}};
}

TEST(Symmetry, NamedConstraintsMustMapOntoEachOther) {
  // An episode on one robot only.
  EXPECT_TRUE(
      Orbits(Robots(2), Plan(RobotsHome(2), kAnyThere, {{"Slow1", Stay("r1", 0, 10)}})).empty());
  // One on each, the same bounds: the exchange exchanges them.
  EXPECT_EQ(Orbits(Robots(2), Plan(RobotsHome(2), kAnyThere,
                                   {{"Slow1", Stay("r1", 0, 10)}, {"Slow2", Stay("r2", 0, 10)}})),
            (Units_{{{0}, {1}}}));
  // Different bounds.
  EXPECT_TRUE(Orbits(Robots(2), Plan(RobotsHome(2), kAnyThere,
                                     {{"Slow1", Stay("r1", 0, 10)}, {"Slow2", Stay("r2", 0, 11)}}))
                  .empty());
  // A goal that reads one of the two episodes' states.
  EXPECT_TRUE(
      Orbits(Robots(2), Plan(RobotsHome(2),
                             std::string(kAnyThere) + " /\\ "
                                                      "epAcceptAutomatonTraj_Slow1[i]==epAccepted",
                             {{"Slow1", Stay("r1", 0, 10)}, {"Slow2", Stay("r2", 0, 10)}}))
          .empty());
  // ... or both.
  EXPECT_EQ(Orbits(Robots(2), Plan(RobotsHome(2),
                                   "(" + std::string(kAnyThere) +
                                       ") /\\ epAcceptAutomatonTraj_Slow2[i]==epAccepted /\\ "
                                       "epAcceptAutomatonTraj_Slow1[i]==epAccepted",
                                   {{"Slow1", Stay("r1", 0, 10)}, {"Slow2", Stay("r2", 0, 10)}})),
            (Units_{{{0}, {1}}}));
  // Shared events: each episode tied to its robot's temporal constraint maps onto itself; one
  // of them tied alone does not.
  auto leave = [](const std::string& r) {
    return Json{{"accepting_event1_constraint", r + "l[i]==home /\\ " + r + "l[i+1]==going"},
                {"accepting_event2_constraint", r + "l[i+1]==there"},
                {"lower_bound", 0},
                {"upper_bound", 9}};
  };
  Json tcs = {{"Leave1", leave("r1")}, {"Leave2", leave("r2")}};
  Json eps = {{"Slow1", Stay("r1", 0, 10)}, {"Slow2", Stay("r2", 0, 10)}};
  EXPECT_EQ(Orbits(Robots(2), Plan(RobotsHome(2), kAnyThere, eps, tcs,
                                   {{"Tied1", {"Slow1.start", "Leave1.event1"}},
                                    {"Tied2", {"Leave2.event1", "Slow2.start"}}})),
            (Units_{{{0}, {1}}}));
  EXPECT_TRUE(Orbits(Robots(2), Plan(RobotsHome(2), kAnyThere, eps, tcs,
                                     {{"Tied", {"Slow1.start", "Leave1.event1"}}}))
                  .empty());
  EXPECT_TRUE(Orbits(Robots(2), Plan(RobotsHome(2), kAnyThere, eps, tcs,
                                     {{"Tied1", {"Slow1.start", "Leave1.event1"}},
                                      {"Tied2", {"Leave2.event1", "Slow2.end"}}}))
                  .empty());
}

TEST(Symmetry, TemporalConstraintsThatReadTheirOwnState) {
  auto tc = [](const std::string& r, const std::string& self) {
    return Json{{"accepting_event1_constraint", r + "l[i]==home /\\ " + r + "l[i+1]==going"},
                {"accepting_event2_constraint",
                 r + "l[i+1]==there /\\ temporalAcceptConstraint_Traj_" + self + "[i]==tempActive"},
                {"lower_bound", 0},
                {"upper_bound", 20}};
  };
  EXPECT_EQ(Orbits(Robots(2), Plan(RobotsHome(2), kAnyThere, Json::object(),
                                   {{"A", tc("r1", "A")}, {"B", tc("r2", "B")}})),
            (Units_{{{0}, {1}}}));
  // Each reading the other's state is no longer the image of the exchange of its own.
  EXPECT_TRUE(Orbits(Robots(2), Plan(RobotsHome(2), kAnyThere, Json::object(),
                                     {{"A", tc("r1", "A")}, {"B", tc("r2", "A")}}))
                  .empty());
}

Json UnitsInit(int n) {
  Json init = Json::object();
  for (int k = 1; k <= n; ++k) {
    init["comp" + std::to_string(k)] = "off";
    init["proj" + std::to_string(k)] = "off";
  }
  return init;
}

TEST(Symmetry, UnitsOfSeveralAutomata) {
  // Every projector on together: units (projK, compK) exchange as a whole.
  std::string all;
  for (int k = 1; k <= 3; ++k)
    all += (k > 1 ? " /\\ " : "") + ("proj" + std::to_string(k)) + "l[i+1]==on";
  EXPECT_EQ(Orbits(Units(3), Plan(UnitsInit(3), all)), (Units_{{{1, 0}, {3, 2}, {5, 4}}}));
  // Exchanging the computers alone is no symmetry: each projector reads its own computer.
  Problem p = Load(Units(2), Plan(UnitsInit(2), "proj1l[i+1]==on /\\ proj2l[i+1]==on"));
  EXPECT_FALSE(IsSymmetry(p.d, p.sp, {2, 1, 0, 3}));
  EXPECT_TRUE(IsSymmetry(p.d, p.sp, {2, 3, 0, 1}));
  EXPECT_TRUE(IsSymmetry(p.d, p.sp, {0, 1, 2, 3}));
  EXPECT_FALSE(IsSymmetry(p.d, p.sp, {1, 2, 3, 0}));  // not an involution
  EXPECT_FALSE(IsSymmetry(p.d, p.sp, {0, 1}));        // the wrong size
  // A goal on the first unit's computer only.
  EXPECT_TRUE(Orbits(Units(2), Plan(UnitsInit(2), "comp1l[i+1]==on")).empty());
}

TEST(Symmetry, ShippedSearchRescueTestPrompts) {
  // Test prompt 1: person 1 and person 2 rescued, by either robot; the doors read both robots.
  const Domain& d = testing::ShippedDomain("search_rescue");
  const std::string dir = testing::ConfigDir() + "/examples/search_rescue/";
  StatePlan sp = testing::ShippedStatePlan("search_rescue", dir + "test1.json");
  auto orbits = FindSymmetries(d, sp);
  ASSERT_EQ(orbits.size(), 1u);
  EXPECT_EQ(orbits[0].units, (std::vector<std::vector<int>>{{0}, {1}}));
  // Test prompt 2: robot 1 rescues person 1, which tells the robots apart.
  EXPECT_TRUE(
      FindSymmetries(d, testing::ShippedStatePlan("search_rescue", dir + "test2.json")).empty());
}

std::string Model(const Problem& p, EncodeOptions o) {
  o.horizon = 4;
  ProblemInfo info = Analyze(p.d, p.sp);
  info.symmetries = FindSymmetries(p.d, p.sp);
  return Encode(p.d, p.sp, info, o).model;
}

TEST(Symmetry, EncoderOrdersTheUnitsUnlessTurnedOffOrReplanning) {
  Problem p = Load(Robots(3), Plan(RobotsHome(3),
                                   "r1l[i+1]==there /\\ r2l[i+1]==there /\\ "
                                   "r3l[i+1]==there"));
  EncodeOptions o;
  std::string m = Model(p, o);
  EXPECT_NE(m.find("lex_lesseq"), std::string::npos);
  EXPECT_NE(m.find("array2d(1..3, 1..1, [1, 2, 3])"), std::string::npos) << m;
  o.symmetry = false;
  EXPECT_EQ(Model(p, o).find("lex_lesseq"), std::string::npos);
  History h;
  h.times = {0};
  h.locations = {{0}, {0}, {0}, {0}};
  h.entry = {{0}, {0}, {0}, {0}};
  o.symmetry = true;
  o.history = &h;
  EXPECT_EQ(Model(p, o).find("lex_lesseq"), std::string::npos);
}

}  // namespace
}  // namespace ctb
