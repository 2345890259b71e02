// Unsatisfiable cores with z3 (planner/smt/z3_core.h, issue 20), with real z3: the core of an
// infeasible plan leaves out the part that plays no role and is minimal, a feasible plan has
// none, sets known feasible need no check, and the time limit gives kUnknown.
#include "planner/smt/z3_core.h"

#include <gtest/gtest.h>

#include "planner/encode/encoder.h"
#include "test_util.h"

namespace ctb {
// A namespace of its own: the test executable's unity build puts files with same-named
// helpers side by side.
namespace z3_core_test {
namespace {

using Kind = smt::CorePart::Kind;

StatePlan Data(const std::string& name) {
  return testing::ShippedStatePlan("presentation", testing::SourceDir() + "/tests/data/" + name);
}

int TemporalIndex(const StatePlan& sp, const std::string& name) {
  for (std::size_t i = 0; i < sp.temporals.size(); ++i)
    if (sp.temporals[i].name == name) return static_cast<int>(i);
  ADD_FAILURE() << "no temporal constraint " << name;
  return 0;
}

// The maintenance constraint and every temporal constraint, switchable.
std::vector<smt::CorePart> AllParts(const StatePlan& sp) {
  std::vector<smt::CorePart> parts{{Kind::kMaintenance, 0}};
  for (std::size_t i = 0; i < sp.temporals.size(); ++i)
    parts.push_back({Kind::kTemporal, static_cast<int>(i)});
  return parts;
}

struct Spec {
  Spec(const Domain& d, const StatePlan& sp, int horizon) : info(Analyze(d, sp)) {
    spec = ModelSpec{&d, &sp, &info, {}};
    spec.opts.horizon = horizon;
  }
  ProblemInfo info;
  ModelSpec spec;
};

// three_together_60_extra: the computer on within 20 s, the projector on and connected within
// 60 s (75 s are needed), the connection only while the computer is off, and a connection
// within 1000 s that any plan of the others meets.
TEST(Z3Core, LeavesOutThePartThatPlaysNoRoleAndIsMinimal) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Data("explain/three_together_60_extra.json");
  Spec s(d, sp, 10);
  auto parts = AllParts(sp);
  smt::CoreOptions o;
  o.limits.time_limit_ms = 120000;
  smt::CoreResult r = smt::FindCoreWithZ3(s.spec, parts, o);
  ASSERT_EQ(r.status, smt::CoreResult::Status::kInfeasible) << r.error;
  EXPECT_TRUE(r.minimal);
  const int extra = 1 + TemporalIndex(sp, "ConnectedWithin1000");
  std::vector<int> expected;
  for (int i = 0; i < static_cast<int>(parts.size()); ++i)
    if (i != extra) expected.push_back(i);
  EXPECT_EQ(r.core, expected);
  EXPECT_GE(r.checks, 2);
  // Each part's removal was shown to leave a plan.
  for (int p : r.core) {
    std::vector<int> rest;
    for (int x : r.core)
      if (x != p) rest.push_back(x);
    bool shown = false;
    for (const auto& f : r.feasible)
      shown = shown || std::includes(f.begin(), f.end(), rest.begin(), rest.end());
    EXPECT_TRUE(shown) << "without part " << p;
  }
}

TEST(Z3Core, AFeasiblePlanHasNoCore) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Data("explain/three_together_60_extra.json");
  sp.temporals[TemporalIndex(sp, "ProjectorOnWithin40")].upper = 75;  // the least that works
  Spec s(d, sp, 10);
  smt::CoreOptions o;
  o.limits.time_limit_ms = 120000;
  smt::CoreResult r = smt::FindCoreWithZ3(s.spec, AllParts(sp), o);
  EXPECT_EQ(r.status, smt::CoreResult::Status::kFeasible) << r.error;
  EXPECT_TRUE(r.core.empty());
}

TEST(Z3Core, SetsKnownFeasibleOrInfeasibleNeedNoCheck) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Data("explain/three_together_60.json");
  Spec s(d, sp, 10);
  smt::CoreOptions o;
  o.limits.time_limit_ms = 120000;
  o.known_infeasible = true;
  o.feasible = {{0, 1}, {0, 2}, {1, 2}};  // every set without one part
  smt::CoreResult r = smt::FindCoreWithZ3(s.spec, AllParts(sp), o);
  ASSERT_EQ(r.status, smt::CoreResult::Status::kInfeasible) << r.error;
  EXPECT_EQ(r.checks, 0);
  EXPECT_TRUE(r.minimal);
  EXPECT_EQ(r.core, (std::vector<int>{0, 1, 2}));
  // A subset known infeasible (static analysis) is taken as the core without a check.
  o.feasible.clear();
  o.known_core = [](const std::vector<int>& on) -> std::optional<std::vector<int>> {
    if (on == std::vector<int>{0, 1}) return std::vector<int>{0, 1};
    return std::nullopt;
  };
  o.feasible = {{1, 2}, {0, 2}};
  r = smt::FindCoreWithZ3(s.spec, AllParts(sp), o);
  ASSERT_EQ(r.status, smt::CoreResult::Status::kInfeasible) << r.error;
  EXPECT_EQ(r.core, (std::vector<int>{0, 1}));
  EXPECT_TRUE(r.minimal);
  EXPECT_EQ(r.checks, 0);
}

TEST(Z3Core, TheTimeLimitGivesUnknown) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Data("explain/three_together_60.json");
  Spec s(d, sp, 40);
  smt::CoreOptions o;
  o.limits.time_limit_ms = 1;
  smt::CoreResult r = smt::FindCoreWithZ3(s.spec, AllParts(sp), o);
  EXPECT_EQ(r.status, smt::CoreResult::Status::kUnknown) << r.error;
  EXPECT_LT(r.elapsed_ms, 5000);
}

}  // namespace
}  // namespace z3_core_test
}  // namespace ctb
