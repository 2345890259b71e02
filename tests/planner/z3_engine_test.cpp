// The z3 engine (planner/smt) behind the backend interface, with real z3: a plan extracted and
// verified, a model proven infeasible, the time limit and cancellation honoured, and the engine
// named in the answer. The differential and brute-force suites compare it with Gecode.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "planner/encode/encoder.h"
#include "planner/encode/extract.h"
#include "planner/solve/backend.h"
#include "planner/solve/solve.h"
#include "planner/verify/verify.h"
#include "test_util.h"

namespace ctb {
namespace {

using Clock = std::chrono::steady_clock;

long MsSince(Clock::time_point t0) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count();
}

StatePlan ExamplePlan(const Domain& d, const std::string& file) {
  Diagnostics diags;
  auto j = ReadJsonFile(testing::ConfigDir() + "/examples/" + file, diags);
  EXPECT_TRUE(j) << testing::AllErrors(diags);
  auto sp = LoadStatePlan(*j, d, diags);
  EXPECT_TRUE(sp) << testing::AllErrors(diags);
  return *sp;
}

// One model for the backend: the problem as data, at a fixed horizon.
struct OneModel {
  OneModel(const Domain& d, const StatePlan& sp, int h, Objective objective)
      : info(Analyze(d, sp)) {
    spec.d = &d;
    spec.sp = &sp;
    spec.info = &info;
    spec.opts.horizon = h;
    spec.opts.objective = objective;
    req.spec = &spec;
  }
  ProblemInfo info;
  ModelSpec spec;
  RunRequest req;
};

TEST(Z3Backend, PlanIsExtractedAndVerified) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = ExamplePlan(d, "presentation/test1_cot.json");
  OneModel m(d, sp, 8, Objective::kMakespan);
  m.req.time_limit_ms = 60000;
  int seen = 0;
  m.req.on_solution = [&](const Json&) { ++seen; };
  RunResult r = Z3EngineBackend().Run(m.req);
  ASSERT_EQ(r.status, RunResult::Status::kOptimal) << r.error;
  ASSERT_TRUE(r.best);
  EXPECT_EQ(seen, r.solutions);
  EXPECT_GE(r.first_solution_ms, 0);
  std::string why;
  auto traj = ExtractTrajectory(*r.best, d, sp, 8, why);
  ASSERT_TRUE(traj) << why;
  EXPECT_TRUE(VerifyTrajectory(*traj, d, sp, 1).empty());
  EXPECT_EQ(traj->events.back(), 2430);  // the known optimum (bench/results/coupled.md)
}

TEST(Z3Backend, AnswerNamesTheEngineAndAgreesWithGecode) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = ExamplePlan(d, "presentation/test1_cot.json");
  SolveOptions o;
  o.max_horizon = 10;
  o.objective = Objective::kCost;
  o.search = "z3";
  o.first_plan_ms = 0;  // the engines themselves (the first-plan engine proves this one at once)
  auto z = SolveDocument(d, sp, o);
  ASSERT_TRUE(std::holds_alternative<Json>(z)) << std::get<Error>(z).ToString();
  o.search = "g_first";
  auto g = SolveDocument(d, sp, o);
  ASSERT_TRUE(std::holds_alternative<Json>(g)) << std::get<Error>(g).ToString();
  const Json &tz = std::get<Json>(z), &tg = std::get<Json>(g);
  EXPECT_EQ(tz["status"], "optimal");
  EXPECT_EQ(tz["verified"], true);
  EXPECT_EQ(tz["stats"]["solver"], "z3");
  EXPECT_EQ(tg["stats"]["solver"], "gecode");
  EXPECT_EQ(tz["status"], tg["status"]);
  EXPECT_EQ(tz["objective"], tg["objective"]);
}

TEST(Z3Backend, ProvesAModelInfeasible) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = ExamplePlan(d, "presentation/test1_cot.json");
  OneModel m(d, sp, 2, Objective::kCost);  // the plan needs more than two events
  m.req.time_limit_ms = 60000;
  RunResult r = Z3EngineBackend().Run(m.req);
  EXPECT_EQ(r.status, RunResult::Status::kInfeasible) << r.error;
  EXPECT_FALSE(r.best);
}

// search_rescue test 1 at a large horizon, makespan: z3 cannot finish in a second.
const StatePlan& RescuePlan() {
  static const StatePlan sp =
      ExamplePlan(testing::ShippedDomain("search_rescue"), "search_rescue/test1.json");
  return sp;
}

struct Hard : OneModel {
  Hard()
      : OneModel(testing::ShippedDomain("search_rescue"), RescuePlan(), 40, Objective::kMakespan) {}
};

TEST(Z3Backend, TimeLimitIsRespected) {
  Hard m;
  m.req.time_limit_ms = 500;
  auto t0 = Clock::now();
  RunResult r = Z3EngineBackend().Run(m.req);
  EXPECT_LT(MsSince(t0), 1500);
  EXPECT_TRUE(r.status == RunResult::Status::kUnknown || r.status == RunResult::Status::kFeasible)
      << RunStatusName(r.status) << " " << r.error;
}

TEST(Z3Backend, CancelStopsPromptly) {
  Hard m;
  m.req.time_limit_ms = 60000;
  std::atomic<bool> cancel{false};
  m.req.cancel = &cancel;
  std::thread t([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    cancel = true;
  });
  auto t0 = Clock::now();
  RunResult r = Z3EngineBackend().Run(m.req);
  t.join();
  EXPECT_LT(MsSince(t0), 1500);
  EXPECT_EQ(r.status, RunResult::Status::kCancelled) << r.error;
}

// search_rescue test 1 at horizon 20: a first plan within seconds, the proof later.
TEST(Z3Backend, CancelAfterAFirstPlanStopsPromptlyAndKeepsIt) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  OneModel m(d, RescuePlan(), 20, Objective::kMakespan);
  m.req.time_limit_ms = 60000;
  std::atomic<bool> cancel{false};
  std::atomic<long> first_at{-1};
  const auto t0 = Clock::now();
  m.req.cancel = &cancel;
  m.req.on_solution = [&](const Json&) {
    if (first_at < 0) first_at = MsSince(t0);
  };
  std::thread t([&] {
    while (first_at < 0 && MsSince(t0) < 30000)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    cancel = true;
  });
  RunResult r = Z3EngineBackend().Run(m.req);
  t.join();
  ASSERT_GE(first_at, 0) << "no plan in 30 s";
  if (r.status == RunResult::Status::kOptimal) GTEST_SKIP() << "proved before the cancel";
  EXPECT_EQ(r.status, RunResult::Status::kCancelled) << r.error;
  EXPECT_LT(MsSince(t0) - first_at, 1500);
  ASSERT_TRUE(r.best);
  std::string why;
  auto traj = ExtractTrajectory(*r.best, d, RescuePlan(), 20, why);
  ASSERT_TRUE(traj) << why;
  EXPECT_TRUE(VerifyTrajectory(*traj, d, RescuePlan(), 1).empty());
}

TEST(Z3Backend, WithoutTheProblemIsAnErrorNotACrash) {
  RunRequest req;
  req.model = "var 0..1: x; solve satisfy;";
  RunResult r = Z3EngineBackend().Run(req);
  EXPECT_EQ(r.status, RunResult::Status::kError);
  EXPECT_FALSE(r.error.empty());
}

}  // namespace
}  // namespace ctb
