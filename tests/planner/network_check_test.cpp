// Textbook cases of the temporal-network checker, each answer derived by hand below.
#include <gtest/gtest.h>

#include "planner/network/check.h"
#include "tests/planner/network_oracle.h"

namespace ctb::network {
namespace {

struct L {
  int from, to;
  Ticks lb;
  std::optional<Ticks> ub;
  bool contingent = false;
};

Network Make(int n, const std::vector<L>& links) {
  Network net;
  for (int i = 0; i < n; ++i)
    net.points.push_back({i, std::string(1, char('A' + i)), PointKind::kControllable, {}});
  for (const L& l : links) {
    net.links.push_back({l.from, l.to, l.lb, l.ub, l.contingent, ""});
    if (l.contingent) net.points[static_cast<std::size_t>(l.to)].kind = PointKind::kContingent;
  }
  Diagnostics d;
  EXPECT_TRUE(Validate(net, d)) << (d.ok() ? "" : d.errors()[0].ToString());
  return net;
}

constexpr int A = 0, B = 1, C = 2;

// A -[1,5]-> B -[2,4]-> C, A -[0,10]-> C: A=0, B=1, C=3 is a schedule; no contingent link, so
// strong and dynamic are the consistency.
TEST(NetworkCheck, ConsistentStnIsControllable) {
  const CheckResult r = CheckNetwork(Make(3, {{A, B, 1, 5}, {B, C, 2, 4}, {A, C, 0, 10}}));
  EXPECT_TRUE(r.consistent);
  EXPECT_TRUE(r.strong);
  EXPECT_TRUE(r.dynamic);
  EXPECT_TRUE(r.conflict.empty());
}

// A -[5,10]-> B -[5,10]-> C forces C - A >= 10, but A -[0,8]-> C says C - A <= 8: the cycle A->C
// (8), C->B (-5), B->A (-5) has length -2; the conflict is all three links.
TEST(NetworkCheck, InconsistentStnNamesItsCycle) {
  const CheckResult r =
      CheckNetwork(Make(3, {{A, B, 5, 10}, {B, C, 5, 10}, {A, C, 0, 8}, {A, B, 0, {}}}));
  EXPECT_FALSE(r.consistent);
  EXPECT_FALSE(r.strong);
  EXPECT_FALSE(r.dynamic);
  EXPECT_EQ(r.conflict, (std::vector<int>{0, 1, 2}));
}

// A ==[1,3]==> C contingent, C -[0,1]-> B. Dynamic: execute B the moment C is seen (B - C = 0,
// instantaneous reaction). Strong: B - A would have to lie in [d, d+1] for every d in [1,3],
// so at least 3 and at most 2: impossible. Dynamic but not strong.
TEST(NetworkCheck, DynamicButNotStrong) {
  const Network net = Make(3, {{A, C, 1, 3, true}, {C, B, 0, 1}});
  const CheckResult r = CheckNetwork(net);
  EXPECT_TRUE(r.consistent);
  EXPECT_FALSE(r.strong);
  EXPECT_TRUE(r.dynamic);
  EXPECT_TRUE(testing::OracleDynamic(net));
  EXPECT_FALSE(testing::OracleStrong(net));
}

// A ==[1,3]==> C, C -[-2,-1]-> B: B must come 1 to 2 before C, before C is seen. B at A + s: s = 0
// fails when C comes at 3 (B - C = -3); s >= 1 fails when C comes at 1 (B - C >= 0). Consistent (C
// at 2, B at 0), neither strong nor dynamic; the conflict is both links.
TEST(NetworkCheck, NeitherStrongNorDynamic) {
  const Network net = Make(3, {{A, C, 1, 3, true}, {C, B, -2, -1}});
  const CheckResult r = CheckNetwork(net);
  EXPECT_TRUE(r.consistent);
  EXPECT_FALSE(r.strong);
  EXPECT_FALSE(r.dynamic);
  EXPECT_EQ(r.conflict, (std::vector<int>{0, 1}));
  EXPECT_FALSE(testing::OracleDynamic(net));
}

// A ==[1,3]==> C, A -[0,10]-> B, C -[0,10]-> B: B = A + 3 is after C for every outcome and
// B - C <= 2 <= 10. Strong, hence dynamic.
TEST(NetworkCheck, StrongAndDynamic) {
  const CheckResult r = CheckNetwork(Make(3, {{A, C, 1, 3, true}, {A, B, 0, 10}, {C, B, 0, 10}}));
  EXPECT_TRUE(r.consistent);
  EXPECT_TRUE(r.strong);
  EXPECT_TRUE(r.dynamic);
}

// Waiting (Morris's wait edges): A ==[2,5]==> C, A -[0,inf]-> B, B -[0,3]-> C... read as C - B in
// [0,3]: B must come no more than 3 before C and not after it. Strategy: wait until A + 2; if C
// came at 2, B at 2; otherwise B at 2 gives C - B in (0,3]. Dynamic. Strong: B - A in [d-3, d] for
// d in {2, 5} needs B - A in [2, 2]: B = A + 2 works for all d in [2,5]. So both; with C - B in
// [0, 2] instead, B - A in [3, 2]: not strong, but the dispatcher waits until A + 3 or C, whichever
// first: C at d <= 3 -> B = d; else B at 3, C - B in (0, 2]. Dynamic.
TEST(NetworkCheck, WaitMakesItDynamic) {
  const Network both = Make(3, {{A, C, 2, 5, true}, {A, B, 0, {}}, {B, C, 0, 3}});
  EXPECT_TRUE(CheckNetwork(both).strong);
  const Network dc = Make(3, {{A, C, 2, 5, true}, {A, B, 0, {}}, {B, C, 0, 2}});
  const CheckResult r = CheckNetwork(dc);
  EXPECT_FALSE(r.strong);
  EXPECT_TRUE(r.dynamic);
  EXPECT_TRUE(testing::OracleDynamic(dc));
}

// A chain of contingent links A ==[1,2]==> C1 ==[1,2]==> C2 with C2 - A <= 3 as a requirement:
// nature can make it 4. Not dynamic, not strong; consistent.
TEST(NetworkCheck, ContingentChain) {
  const Network net = Make(3, {{A, 1, 1, 2, true}, {1, 2, 1, 2, true}, {A, 2, 0, 3}});
  const CheckResult r = CheckNetwork(net);
  EXPECT_TRUE(r.consistent);
  EXPECT_FALSE(r.dynamic);
  EXPECT_EQ(r.conflict, (std::vector<int>{0, 1, 2}));
  EXPECT_FALSE(testing::OracleDynamic(net));
}

TEST(NetworkCheck, EmptyNetwork) {
  const CheckResult r = CheckNetwork(Network{});
  EXPECT_TRUE(r.consistent && r.strong && r.dynamic);
}

// A 10,000-point chain, every point a negative node: Bellman-Ford settles it in one pass and
// DCbackprop's searches, which Morris nests as deep as the chain, do not nest here.
TEST(NetworkCheck, LongChainDoesNotOverflowTheStack) {
  std::vector<L> links;
  const int n = 10000;
  for (int i = 0; i + 1 < n; ++i) links.push_back({i, i + 1, 1, 5, i % 3 == 0});
  const Network net = Make(n, links);
  const CheckResult r = CheckNetwork(net);
  EXPECT_TRUE(r.consistent);
  EXPECT_TRUE(r.dynamic);
  EXPECT_TRUE(r.strong);
  EXPECT_TRUE(IsDynamicallyControllable(net));  // CheckNetwork skips it when strong
}

}  // namespace
}  // namespace ctb::network
