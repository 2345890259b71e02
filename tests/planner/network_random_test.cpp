// The checker against the slow oracles (tests/planner/network_oracle.h) on random networks with
// fixed seeds: consistency against Floyd-Warshall, strong controllability against the enumeration
// of contingent extremes, dynamic controllability against the discrete-time game, and every
// conflict checked to be not dynamically controllable itself.
#include <gtest/gtest.h>

#include <cstdio>

#include "planner/network/check.h"
#include "planner/network/dynamic_internal.h"
#include "tests/planner/network_oracle.h"

namespace ctb::network {
namespace {

std::string Describe(const Network& net) {
  std::string s;
  for (const Link& l : net.links) {
    s += "  " + std::to_string(l.from) + (l.contingent ? " ==[" : " -[") + std::to_string(l.lb) +
         "," + (l.ub ? std::to_string(*l.ub) : "inf") + (l.contingent ? "]==> " : "]-> ") +
         std::to_string(l.to) + "\n";
  }
  return s;
}

struct Counts {
  int consistent = 0, strong = 0, dynamic = 0, total = 0;
  ~Counts() {
    std::printf(
        "%d networks: %d inconsistent, %d consistent not dynamic, %d "
        "dynamic not strong, "
        "%d strong\n",
        total, total - consistent, consistent - dynamic, dynamic - strong, strong);
  }
};

void CheckOne(const Network& net, bool with_game, Counts& counts) {
  const CheckResult r = CheckNetwork(net);
  ++counts.total;
  counts.consistent += r.consistent;
  counts.strong += r.strong;
  counts.dynamic += r.dynamic;
  ASSERT_EQ(r.consistent, testing::OracleConsistent(net)) << Describe(net);
  ASSERT_EQ(r.strong, testing::OracleStrong(net)) << Describe(net);
  ASSERT_TRUE(!r.strong || r.dynamic) << Describe(net);
  ASSERT_TRUE(!r.dynamic || r.consistent) << Describe(net);
  ASSERT_EQ(r.dynamic, internal::MoatDynamicControllability(net, nullptr)) << Describe(net);
  ASSERT_EQ(r.dynamic, IsDynamicallyControllable(net)) << Describe(net);  // even when strong
  if (with_game) {
    ASSERT_EQ(r.dynamic, testing::OracleDynamic(net)) << Describe(net);
  }
  if (r.dynamic) {
    ASSERT_TRUE(r.conflict.empty());
    return;
  }
  ASSERT_FALSE(r.conflict.empty()) << Describe(net);
  const Network sub = testing::Restrict(net, r.conflict);
  Diagnostics d;
  ASSERT_TRUE(Validate(sub, d));
  ASSERT_FALSE(IsDynamicallyControllable(sub)) << "conflict is controllable:\n" << Describe(sub);
  ASSERT_FALSE(internal::MoatDynamicControllability(sub, nullptr)) << Describe(sub);
  if (with_game) {
    ASSERT_FALSE(testing::OracleDynamic(sub)) << Describe(sub);
  }
}

// Tiny networks: every answer against every oracle, the game included.
TEST(NetworkRandom, TinyNetworksAgreeWithTheGame) {
  std::mt19937 rng(20261127);
  Counts c;
  for (int i = 0; i < 4000; ++i) {
    const int n = 2 + static_cast<int>(rng() % 3);  // 2..4 points
    const int k = 1 + static_cast<int>(rng() % 2);  // 1 or 2 contingent links
    const int m = 1 + static_cast<int>(rng() % 4);  // 1..4 requirement links
    CheckOne(testing::RandomNetwork(rng, n, k, m, 4), true, c);
    if (HasFatalFailure()) return;
  }
  // The sample covers every answer.
  EXPECT_GT(c.dynamic - c.strong, 50);
  EXPECT_GT(c.consistent - c.dynamic, 50);
  EXPECT_GT(c.strong, 50);
  EXPECT_GT(c.total - c.consistent, 50);
}

// Five points and three contingent links: the game still answers in milliseconds.
TEST(NetworkRandom, SmallNetworksAgreeWithTheGame) {
  std::mt19937 rng(7);
  Counts c;
  for (int i = 0; i < 1000; ++i) {
    const int k = 1 + static_cast<int>(rng() % 3);
    const int m = 2 + static_cast<int>(rng() % 4);
    CheckOne(testing::RandomNetwork(rng, 5, k, m, 3), true, c);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(c.dynamic - c.strong, 20);
}

// Larger networks (no game): strong against enumeration, consistency, conflicts.
TEST(NetworkRandom, LargerNetworksAgreeWithEnumeration) {
  std::mt19937 rng(99);
  Counts c;
  for (int i = 0; i < 1000; ++i) {
    const int n = 6 + static_cast<int>(rng() % 10);
    const int k = static_cast<int>(rng() % 5);
    const int m = n + static_cast<int>(rng() % n);
    CheckOne(testing::RandomNetwork(rng, n, k, m, 20), false, c);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(c.strong, 20);
  EXPECT_GT(c.consistent - c.dynamic, 20);
}

}  // namespace
}  // namespace ctb::network
