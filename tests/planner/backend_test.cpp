// The planner's logic around the solver (horizon growth, statuses, errors, cancellation) with
// fake backends: no minizinc, so these run in milliseconds.
#include <gtest/gtest.h>

#include <mutex>
#include <vector>

#include "planner/solve/backend.h"
#include "planner/solve/solve.h"
#include "test_util.h"

namespace ctb {
namespace {

// Answers every model with one status and records the horizon of each model it was given.
class ScriptedBackend : public SolverBackend {
 public:
  explicit ScriptedBackend(RunResult::Status status) : status_(status) {}
  const char* Name() const override { return "scripted"; }
  RunResult Run(const RunRequest& req) override {
    std::lock_guard<std::mutex> lock(mu_);
    horizons_.push_back(req.data.value("H", -1));
    RunResult r;
    r.status = status_;
    if (status_ == RunResult::Status::kError) r.error = "scripted failure";
    return r;
  }
  std::vector<int> horizons() {
    std::lock_guard<std::mutex> lock(mu_);
    return horizons_;
  }

 private:
  RunResult::Status status_;
  std::mutex mu_;
  std::vector<int> horizons_;
};

StatePlan Plan(const Domain& d) {
  Diagnostics diags;
  Json j = {{"initial_state", {{"comp", "compOff"}, {"conn", "disconnected"}, {"proj", "projOff"}}},
            {"end_state", {{"goal_constraint", "projl[i+1]==projOn /\\ compl[i+1]==compOn"}}}};
  auto sp = LoadStatePlan(j, d, diags);
  EXPECT_TRUE(sp) << testing::AllErrors(diags);
  return *sp;
}

TEST(Backend, InfeasibleAtEveryHorizonGrowsByDoublingToMaxHorizon) {
  const Domain& d = testing::ShippedDomain("presentation");
  ScriptedBackend b(RunResult::Status::kInfeasible);
  SolveOptions o;
  o.backend = &b;
  o.max_horizon = 12;
  o.portfolio = 1;
  o.first_plan_ms = 0;  // the exact path alone (the first-plan engine would solve these)
  auto r = SolveDocument(d, Plan(d), o);
  ASSERT_TRUE(std::holds_alternative<Json>(r));
  const Json& t = std::get<Json>(r);
  EXPECT_EQ(t["status"], "infeasible");
  EXPECT_EQ(t["verified"], false);
  EXPECT_EQ(t["stats"]["solver"], "scripted");
  // The goal needs the projector two transitions away, and its first one waits for the
  // connection (a guard), an event earlier: start at 3 (analyze/earliest.h, in events).
  EXPECT_EQ(b.horizons(), (std::vector<int>{3, 6, 12}));
}

TEST(Backend, AFixedHorizonIsOneModel) {
  const Domain& d = testing::ShippedDomain("presentation");
  ScriptedBackend b(RunResult::Status::kInfeasible);
  SolveOptions o;
  o.backend = &b;
  o.horizon = 7;
  o.portfolio = 1;
  o.first_plan_ms = 0;  // the exact path alone (the first-plan engine would solve these)
  auto r = SolveDocument(d, Plan(d), o);
  ASSERT_TRUE(std::holds_alternative<Json>(r));
  EXPECT_EQ(std::get<Json>(r)["status"], "infeasible");
  EXPECT_EQ(b.horizons(), (std::vector<int>{7}));
}

TEST(Backend, NoAnswerInTimeIsUnknownNotInfeasible) {
  const Domain& d = testing::ShippedDomain("presentation");
  ScriptedBackend b(RunResult::Status::kUnknown);
  SolveOptions o;
  o.backend = &b;
  o.portfolio = 1;
  o.first_plan_ms = 0;  // the exact path alone (the first-plan engine would solve these)
  auto r = SolveDocument(d, Plan(d), o);
  ASSERT_TRUE(std::holds_alternative<Json>(r));
  EXPECT_EQ(std::get<Json>(r)["status"], "unknown");
  EXPECT_EQ(b.horizons().size(), 1u);  // an undecided horizon is not grown past
}

TEST(Backend, ASolverFailureIsAnError) {
  const Domain& d = testing::ShippedDomain("presentation");
  ScriptedBackend b(RunResult::Status::kError);
  SolveOptions o;
  o.backend = &b;
  o.portfolio = 1;
  o.first_plan_ms = 0;  // the exact path alone (the first-plan engine would solve these)
  auto r = SolveDocument(d, Plan(d), o);
  ASSERT_TRUE(std::holds_alternative<Error>(r));
  EXPECT_EQ(std::get<Error>(r).code, ErrorCode::kInternal);
  EXPECT_NE(std::get<Error>(r).message.find("scripted failure"), std::string::npos);
}

// A "plan" that does not reach the goal must never be returned: the verifier catches it.
class LyingBackend : public SolverBackend {
 public:
  const char* Name() const override { return "lying"; }
  RunResult Run(const RunRequest& req) override {
    const int H = req.data.value("H", 0), na = req.data.value("NA", 0);
    Json rows = Json::array(), zeros = Json::array(), times = Json::array();
    for (int k = 0; k <= H; ++k) times.push_back(0);
    for (int a = 0; a < na; ++a) {
      Json r = Json::array(), z = Json::array();
      for (int k = 0; k <= H; ++k) r.push_back(req.data["INIT"][a]), z.push_back(0);
      rows.push_back(r);
      zeros.push_back(z);
    }
    Json x = Json::array();
    for (int a = 0; a < na; ++a) x.push_back(Json::array());
    for (int a = 0; a < na; ++a)
      for (int k = 0; k < H; ++k) x[a].push_back(0);
    RunResult res;
    res.status = RunResult::Status::kOptimal;
    res.best = Json{{"e", times}, {"L", rows}, {"U", zeros}, {"X", x}, {"N", zeros}, {"g", 0},
                    {"EP_S", Json::array()}, {"EP_E", Json::array()}, {"TC_1", Json::array()},
                    {"TC_2", Json::array()}};
    return res;
  }
};

TEST(Backend, AWrongPlanFromTheSolverIsAnInternalErrorNeverAnAnswer) {
  const Domain& d = testing::ShippedDomain("presentation");
  LyingBackend b;
  SolveOptions o;
  o.backend = &b;
  o.portfolio = 1;
  o.first_plan_ms = 0;  // the exact path alone (the first-plan engine would solve these)
  auto r = SolveDocument(d, Plan(d), o);
  ASSERT_TRUE(std::holds_alternative<Error>(r));
  EXPECT_EQ(std::get<Error>(r).code, ErrorCode::kInternal);
}

// The first-plan engine's plan is the incumbent: an engine that finds nothing better at every
// horizon up to max_horizon proves it optimal (issue 18). "C on A" from A on B on C: the makespan
// bound (5 s: C is clear at 2 s at the earliest, then its pick and place) is below the optimum
// (6 s: both arms are busy with A and B until 3 s), so the exact path runs. (The shipped
// example's bound now meets its optimum.)
TEST(Backend, AnIncumbentWithNothingBetterAtAnyHorizonIsOptimal) {
  const Domain& d = testing::ShippedDomain("assembly");
  Diagnostics diags;
  auto loaded = LoadStatePlan(testing::MustParse(R"({
    "initial_state": {"arm1": "home", "arm2": "home", "blockA": "onB", "blockB": "onC",
                      "blockC": "onFloor"},
    "end_state": {"maintenance_constraint": "true",
      "goal_constraint": "arm1[i+1]==home /\\ arm2[i+1]==home /\\ blockC[i+1]==onA"},
    "objective": "makespan"})"), d, diags);
  ASSERT_TRUE(loaded) << testing::AllErrors(diags);
  const StatePlan& sp = *loaded;
  ScriptedBackend b(RunResult::Status::kInfeasible);
  SolveOptions o;
  o.backend = &b;
  o.max_horizon = 16;  // the engine's plan has about a dozen events
  o.portfolio = 1;
  o.objective = Objective::kMakespan;
  o.zone_proof_ms = 0;  // the zone search with a deadline proves it too (below): the engine's turn
  auto r = SolveDocument(d, sp, o);
  ASSERT_TRUE(std::holds_alternative<Json>(r));
  const Json& t = std::get<Json>(r);
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["verified"], true);
  EXPECT_GE(t["objective"]["value"].get<long>(), 6);
  EXPECT_EQ(t["stats"]["found_by"], "heuristic");
  EXPECT_EQ(t["stats"]["proved_by"], "scripted");
  ASSERT_FALSE(b.horizons().empty());
  EXPECT_EQ(b.horizons().back(), 16);  // refuted up to max_horizon (makespan)
  EXPECT_GE(t["stats"]["first_solution_ms"].get<long>(), 0);
  // With the zone search (analyze/bounds.h, RaiseMakespanBound) the engine is not asked: no run
  // ends before the plan does.
  ScriptedBackend unused(RunResult::Status::kInfeasible);
  o.backend = &unused;
  o.zone_proof_ms = 600000;  // ends by its states
  auto z = SolveDocument(d, sp, o);
  ASSERT_TRUE(std::holds_alternative<Json>(z));
  const Json& u = std::get<Json>(z);
  EXPECT_EQ(u["status"], "optimal");
  EXPECT_EQ(u["objective"], t["objective"]);
  EXPECT_EQ(u["stats"]["proved_by"], "zone search");
  EXPECT_TRUE(unused.horizons().empty());
}

// Off, the same problem is infeasible by the same script: the status came from the incumbent.
TEST(Backend, WithoutTheFirstPlanEngineTheScriptIsFollowed) {
  const Domain& d = testing::ShippedDomain("assembly");
  StatePlan sp = testing::ShippedStatePlan(
      "assembly", testing::ConfigDir() + "/examples/assembly/test.json");
  ScriptedBackend b(RunResult::Status::kInfeasible);
  SolveOptions o;
  o.backend = &b;
  o.max_horizon = 16;
  o.portfolio = 1;
  o.first_plan_ms = 0;
  auto r = SolveDocument(d, sp, o);
  ASSERT_TRUE(std::holds_alternative<Json>(r));
  EXPECT_EQ(std::get<Json>(r)["status"], "infeasible");
  EXPECT_EQ(std::get<Json>(r)["stats"]["found_by"], nullptr);
}

}  // namespace
}  // namespace ctb
