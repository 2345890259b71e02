// The zone search (issue 20, planner/analyze/zone_reach.h): difference-bound matrices, proofs
// for any number of events that need the automata's runs themselves, and runs found for every
// feasible shipped example. Soundness against the solvers: explain_test.cpp (the deadline grid)
// and the near misses of differential_test.cpp and brute_force_test.cpp.
#include "planner/analyze/zone_reach.h"

#include <gtest/gtest.h>

#include <chrono>
#include <set>

#include "planner/analyze/dbm.h"
#include "test_util.h"

namespace ctb {
// A namespace of its own: the test executable's unity build puts files with same-named
// helpers side by side.
namespace zone_reach_test {
namespace {

using analysis::Dbm;
using analysis::FindZoneConflict;
using analysis::Reach;

TEST(Dbm, DelayResetAndConstraintsKeepTheDifferences) {
  Dbm z(2);  // x1 = x2 = 0
  z.Up();
  ASSERT_TRUE(z.AtMost(1, 10));
  z.Reset(2);  // x2 = 0, x1 in [0, 10]
  z.Up();
  ASSERT_TRUE(z.AtLeast(2, 5));  // x1 - x2 in [0, 10], so x1 >= 5
  EXPECT_EQ(z.At(0, 1), Dbm::Le(-5));
  EXPECT_FALSE(z.Empty());
  Dbm tight = z;
  EXPECT_FALSE(tight.Below(1, 5));  // x1 < 5 contradicts x1 >= 5
  EXPECT_TRUE(tight.Empty());
  Dbm part = z;
  ASSERT_TRUE(part.AtMost(1, 7));
  EXPECT_TRUE(z.Includes(part));
  EXPECT_FALSE(part.Includes(z));
}

TEST(Dbm, ExtrapolationForgetsOnlyBeyondTheLargestConstant) {
  Dbm z(1);
  z.Up();
  ASSERT_TRUE(z.AtLeast(1, 100));
  Dbm kept = z, cut = z;
  kept.Extrapolate({0, 200});
  EXPECT_EQ(kept.At(0, 1), Dbm::Le(-100));
  cut.Extrapolate({0, 30});  // beyond 30 the automata cannot tell: x1 > 30
  EXPECT_EQ(cut.At(0, 1), Dbm::Lt(-30));
  EXPECT_TRUE(cut.Includes(z));
  Dbm freed = z;
  freed.Extrapolate({0, -1});
  EXPECT_EQ(freed.At(0, 1), Dbm::Le(0));
  EXPECT_GE(freed.At(1, 0), Dbm::kInfinity);
}

StatePlan Data(const std::string& domain, const std::string& name) {
  return testing::ShippedStatePlan(domain, testing::SourceDir() + "/tests/data/" + name);
}

std::optional<double> HintFor(const analysis::ZoneConflict& c, const std::string& pointer) {
  for (const auto& h : c.hints)
    if (h.pointer == pointer) return h.value;
  return std::nullopt;
}

StatePlan WithUpper(const Domain& d, const StatePlan& sp, const std::string& name, double upper) {
  Json j = StatePlanToJson(sp, d);
  j["constraints"]["temporal"][name]["upper_bound"] = upper;
  Diagnostics diags;
  auto out = LoadStatePlan(j, d, diags);
  EXPECT_TRUE(out) << testing::AllErrors(diags);
  return out ? *out : sp;
}

// The projector on and connected within 60 s, the computer on within 20 s, connected only while
// the computer is off. Computer first: on at 15 s, shut down by 45 s, then the connection and
// the 30 s warm-up: 75 s. Projector first: the computer cannot boot while connected, and a
// projector left on without the connection cools down at once (an automatic transition). The
// time network sees 45 s (it has no node for the connection); the runs show 75 s.
TEST(ZoneSearch, TheWarmUpAfterTheConnectionIsCounted) {
  const Domain& d = testing::ShippedDomain("presentation");
  const StatePlan sp = Data("presentation", "explain/three_together_60.json");
  auto c = FindZoneConflict(d, sp, true);
  ASSERT_TRUE(c);
  EXPECT_EQ(std::set<std::string>(c->parts.begin(), c->parts.end()),
            (std::set<std::string>{"/end_state/maintenance_constraint",
                                   "/constraints/temporal/ComputerOnWithin20",
                                   "/constraints/temporal/ProjectorOnWithin40"}));
  EXPECT_EQ(HintFor(*c, "/constraints/temporal/ProjectorOnWithin40/upper_bound"), 75);
  EXPECT_EQ(HintFor(*c, "/constraints/temporal/ComputerOnWithin20/upper_bound"), 45);
  EXPECT_NE(c->text.find("at least 75 s"), std::string::npos) << c->text;
  EXPECT_TRUE(FindZoneConflict(d, WithUpper(d, sp, "ProjectorOnWithin40", 74), true));
  EXPECT_FALSE(FindZoneConflict(d, WithUpper(d, sp, "ProjectorOnWithin40", 75), true));
  // Without the maintenance constraint the computer boots while connected: nothing to prove.
  Json j = StatePlanToJson(sp, d);
  j["end_state"]["maintenance_constraint"] = "true";
  Diagnostics diags;
  auto loose = LoadStatePlan(j, d, diags);
  ASSERT_TRUE(loose);
  EXPECT_FALSE(FindZoneConflict(d, *loose, true));
}

// Every impossible request of the benchmark (bench/impossible.py) is proven by the search alone
// too: it follows the runs, so what the part checks and the time network prove it proves.
TEST(ZoneSearch, ProvesEveryImpossibleExampleAlone) {
  const char* cases[][2] = {
      {"presentation", "config/examples/presentation/impossible_off_within59.json"},
      {"presentation", "config/examples/presentation/impossible_on1800_off1500.json"},
      {"search_rescue", "config/examples/search_rescue/impossible_door_shut_deadline.json"},
      {"presentation", "tests/data/deadline_infeasible.json"},
      {"presentation", "config/examples/presentation/test2_direct.json"},
      {"presentation", "tests/data/explain/deadline_boot.json"},
      {"presentation", "tests/data/explain/change_not_allowed.json"},
      {"search_rescue", "tests/data/explain/unreachable.json"},
      {"presentation", "tests/data/explain/overlap.json"},
      {"presentation", "tests/data/explain/maintenance_blocks.json"},
      {"presentation", "tests/data/explain/three_together.json"}};
  for (auto& [dom, file] : cases) {
    SCOPED_TRACE(file);
    const Domain& d = testing::ShippedDomain(dom);
    StatePlan sp = testing::ShippedStatePlan(dom, testing::SourceDir() + "/" + file);
    auto q = analysis::WholePlan(d, sp, true);
    analysis::ZoneBudget b{200000, std::chrono::steady_clock::now() + std::chrono::seconds(10)};
    EXPECT_EQ(analysis::SearchZones(d, sp, q, b), Reach::kNoRun);
  }
}

// A run is found for every feasible shipped example, quickly: the search runs before every
// solve that the other checks leave undecided.
TEST(ZoneSearch, FindsARunForEveryFeasibleExample) {
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
    auto q = analysis::WholePlan(d, sp, true);
    const auto t0 = std::chrono::steady_clock::now();
    analysis::ZoneBudget b{200000, t0 + std::chrono::seconds(10)};
    EXPECT_EQ(analysis::SearchZones(d, sp, q, b), Reach::kRun);
    const auto ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0);
    EXPECT_LT(ms.count(), 100);
  }
}

// A run under way (replanning) has clocks the state plan does not give: the computer booting
// since some time may be on in 14 s. With every clock at 0 it cannot.
TEST(ZoneSearch, UnknownClocksClaimNothingAboutTimeAlreadySpent) {
  const Domain& d = testing::ShippedDomain("presentation");
  Json j = testing::MustParse(R"({"initial_state": {"comp": "compBooting", "conn": "disconnected",
      "proj": "projOff"}, "end_state": {"goal_constraint": "true"},
      "constraints": {"temporal": {"OnWithin14": {
        "accepting_event1_constraint": "compl[i]==compBooting",
        "accepting_event2_constraint": "compl[i+1]==compOn",
        "lower_bound": 0, "upper_bound": 14}}}})");
  Diagnostics diags;
  auto sp = LoadStatePlan(j, d, diags);
  ASSERT_TRUE(sp) << testing::AllErrors(diags);
  EXPECT_TRUE(FindZoneConflict(d, *sp, true));
  EXPECT_FALSE(FindZoneConflict(d, *sp, false));
}

// Untrusted state plans may have many parts (a clock each) whose conditions read commands (either
// value at every event): the search keeps to its budget (time, states, and memory for zones).
TEST(ZoneSearch, ManyPartsStayWithinTheBudget) {
  const Domain& d = testing::ShippedDomain("presentation");
  Json temporal = Json::object();
  for (int k = 0; k < 40; ++k)
    temporal["T" + std::to_string(k)] = {
        {"accepting_event1_constraint", "proju[i]==projTurnOn \\/ compu[i]==compTurnOff"},
        {"accepting_event2_constraint", "compl[i+1]==compOn"},
        {"lower_bound", k},
        {"upper_bound", 1000 + k}};
  Json j = {{"initial_state", {{"comp", "compOff"}, {"conn", "disconnected"}, {"proj", "projOff"}}},
            {"end_state", {{"goal_constraint", "projl[i+1]==projOn"}}},
            {"constraints", {{"temporal", temporal}}}};
  Diagnostics diags;
  auto sp = LoadStatePlan(j, d, diags);
  ASSERT_TRUE(sp) << testing::AllErrors(diags);
  const auto t0 = std::chrono::steady_clock::now();
  FindZoneConflict(d, *sp, true);
  const auto ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0);
  EXPECT_LT(ms.count(), 1000);
}

}  // namespace
}  // namespace zone_reach_test
}  // namespace ctb
