// The verifier on a hand-built trajectory for the thesis' test prompt 1 (chain of thought), and
// on hand-corrupted copies of it. Independent of the encoder and the solver.
#include "planner/verify/verify.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "test_util.h"

namespace ctb {
namespace {

struct Fixture {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp;
  Trajectory t;

  Fixture() {
    Diagnostics diags;
    auto j = ReadJsonFile(testing::ConfigDir() + "/examples/presentation/test1_cot.json", diags);
    sp = *LoadStatePlan(*j, d, diags);
    // comp(0) stays off; conn(1): connect at e1, disconnect at e5; proj(2): on at e2, warm-up
    // 30 s, on until 1830, first press, then the disconnect cools it down, off at 2430.
    t.events = {0, 0, 0, 30, 1830, 2370, 2370, 2430};
    t.goal_event = 7;
    t.horizon = 7;
    t.locations = {{0, 0, 0, 0, 0, 0, 0, 0}, {0, 1, 1, 1, 1, 0, 0, 0}, {0, 0, 1, 2, 3, 3, 4, 0}};
    t.commands = {{0, 0, 0, 0, 0, 0, 0, 0}, {1, 0, 0, 0, 2, 0, 0, 0}, {0, 1, 0, 2, 0, 0, 0, 0}};
    t.fired = {{1, 1, 0}, {2, 2, 0}, {3, 2, 1}, {4, 2, 2}, {5, 1, 1}, {6, 2, 6}, {7, 2, 4}};
    t.episodes = {{3, 4}};
    t.temporals.resize(2);
    t.temporals[Temporal("ProjectorOnWithin60")] = {2, 3};
    t.temporals[Temporal("ShutdownWithin600")] = {4, 7};
  }
  std::size_t Temporal(const std::string& name) const {
    for (std::size_t q = 0; q < sp.temporals.size(); ++q)
      if (sp.temporals[q].name == name) return q;
    abort();
  }
  std::vector<std::string> Verify() const { return VerifyTrajectory(t, d, sp, 1); }
};

bool Mentions(const std::vector<std::string>& problems, const std::string& part) {
  for (const auto& p : problems)
    if (p.find(part) != std::string::npos) return true;
  return false;
}

std::string Join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += x + "\n";
  return s;
}

TEST(VerifyTrajectory, AcceptsTheHandBuiltPlan) {
  Fixture f;
  auto problems = f.Verify();
  EXPECT_TRUE(problems.empty()) << Join(problems);
  EXPECT_EQ(TrajectoryCost(f.t, f.d), 7);
}

TEST(VerifyTrajectory, RejectsAShortenedWarmUp) {
  Fixture f;
  f.t.events[3] = 20;
  auto problems = f.Verify();
  EXPECT_TRUE(Mentions(problems, "'proj' at event 3 (t=20 ticks): time in 'projWarmUp' is outside"))
      << Join(problems);
}

TEST(VerifyTrajectory, RejectsACommandIssuedWhileItsGuardIsFalse) {
  Fixture f;  // the projector is turned on before the connection is made
  f.t.locations[1] = {0, 0, 1, 1, 1, 0, 0, 0};
  f.t.locations[2] = {0, 1, 1, 2, 3, 3, 4, 0};
  f.t.commands[1] = {0, 1, 0, 0, 2, 0, 0, 0};
  f.t.commands[2] = {1, 0, 0, 2, 0, 0, 0, 0};
  f.t.fired[0] = {1, 2, 0};
  f.t.fired[1] = {2, 1, 0};
  auto problems = f.Verify();
  EXPECT_TRUE(Mentions(problems, "'proj' at event 1 (t=0 ticks): guard 'proju[i]==projTurnOn /\\ "
                                 "connl[i]==connected' is false")) << Join(problems);
}

TEST(VerifyTrajectory, RejectsAnEpisodeCutShort) {
  Fixture f;
  f.t.events[4] = 1500;
  auto problems = f.Verify();
  EXPECT_TRUE(Mentions(problems, "episode 'ProjectorOnDuration': lasts outside its bounds"))
      << Join(problems);
}

TEST(VerifyTrajectory, RejectsAnOverstayedAutomaticTransition) {
  Fixture f;
  f.t.events[7] = 2500;
  auto problems = f.Verify();
  EXPECT_TRUE(Mentions(problems, "was due at clock 60")) << Join(problems);
}

TEST(VerifyTrajectory, RejectsAnEnabledAutomaticTransitionThatDoesNotFire) {
  Fixture f;  // after the disconnect the projector must cool down at once; here it waits
  f.t.events[6] = 2380;
  auto problems = f.Verify();
  EXPECT_TRUE(Mentions(problems, "was due at clock 0")) << Join(problems);
}

TEST(VerifyTrajectory, RejectsAWrongEpisodeStart) {
  Fixture f;
  f.t.episodes[0] = {2, 4};
  auto problems = f.Verify();
  EXPECT_TRUE(Mentions(problems, "not at the first event its accepting constraint holds"))
      << Join(problems);
}

TEST(VerifyTrajectory, RejectsATemporalBoundViolation) {
  Fixture f;  // shutdown 100 s late
  f.t.events[5] = 2470;
  f.t.events[6] = 2470;
  f.t.events[7] = 2530;
  auto problems = f.Verify();
  EXPECT_TRUE(Mentions(problems, "'ShutdownWithin600': time between its events is outside"))
      << Join(problems);
}

TEST(VerifyTrajectory, RejectsAGoalNotReached) {
  Fixture f;
  f.t.locations[0][7] = 2;  // computer on at the end, with no transition
  auto problems = f.Verify();
  EXPECT_TRUE(Mentions(problems, "location changed without a transition")) << Join(problems);
  EXPECT_TRUE(Mentions(problems, "the end state is not accepted")) << Join(problems);
}

TEST(VerifyTrajectory, RejectsAnEventWithoutTransition) {
  Fixture f;
  f.t.fired.erase(f.t.fired.begin() + 4);  // the disconnect at event 5 vanishes
  f.t.locations[1] = {0, 1, 1, 1, 1, 1, 1, 1};
  auto problems = f.Verify();
  EXPECT_TRUE(Mentions(problems, "event 5 carries no transition")) << Join(problems);
}

TEST(VerifyTrajectory, RejectsMalformedShapes) {
  Fixture f;
  f.t.locations.pop_back();
  EXPECT_TRUE(Mentions(f.Verify(), "one timeline per automaton"));
}

// The yes-or-no replay that stops at the first violation (brute force) agrees with the full one
// on the hand-built plan and on 300 random corruptions of it: event times, locations, commands,
// constraint placements.
TEST(TrajectoryIsPlan, AgreesWithTheFullReplay) {
  Fixture base;
  EXPECT_TRUE(TrajectoryIsPlan(base.t, base.d, base.sp, 1));
  std::mt19937 rng(7);
  int rejected = 0;
  for (int i = 0; i < 300; ++i) {
    Fixture f;
    auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
    for (int changes = 1 + pick(2); changes > 0; --changes) {
      const int k = pick(8), a = pick(3);
      switch (pick(4)) {
        case 0: f.t.events[k] = std::max(0L, f.t.events[k] + pick(121) - 60); break;
        case 1: f.t.locations[a][k] = pick(5) % (a == 2 ? 5 : (a == 1 ? 2 : 3)); break;
        case 2: f.t.commands[a][k] = pick(3); break;
        default: f.t.temporals[pick(2)].second = pick(8); break;
      }
    }
    const auto problems = f.Verify();
    EXPECT_EQ(TrajectoryIsPlan(f.t, f.d, f.sp, 1), problems.empty()) << "case " << i << "\n" << Join(problems);
    rejected += !problems.empty();
  }
  EXPECT_GT(rejected, 200);  // the corruptions mostly break the plan
}

}  // namespace
}  // namespace ctb
