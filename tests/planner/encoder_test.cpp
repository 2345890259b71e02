#include "planner/encode/encoder.h"

#include <gtest/gtest.h>

#include "planner/solve/runner.h"
#include "test_util.h"

namespace ctb {
namespace {

StatePlan Load(const std::string& domain, const std::string& file) {
  Diagnostics d;
  auto j = ReadJsonFile(testing::ConfigDir() + "/examples/" + file, d);
  return *LoadStatePlan(*j, testing::ShippedDomain(domain), d);
}

TEST(Analyze, DerivesTicksBoundsAndCommandVisibility) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Load("presentation", "presentation/test1_cot.json");
  ProblemInfo info = Analyze(d, sp);
  EXPECT_EQ(info.ticks_per_second, 1);
  EXPECT_EQ(info.max_lo, 60);          // projCoolDown -> projOff
  EXPECT_EQ(info.bound_sum, 1800 + 600 + 0);
  EXPECT_EQ(info.TimeBound(10), 2400 + 600);
  EXPECT_EQ(info.min_cost, 1);
  EXPECT_EQ(info.owner.size(), 14u);   // 13 transitions + the unused 0
  for (bool pub : info.command_public) EXPECT_FALSE(pub);
}

TEST(Encode, ModelHoldsNoNameFromTheInput) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Load("presentation", "presentation/test1_cot.json");
  EncodeOptions o;
  o.horizon = 9;
  Encoding enc = Encode(d, sp, Analyze(d, sp), o);
  for (const char* name : {"projOn", "compOff", "connected", "Shutdown", "ProjectorOn", "proj",
                           "temporalAccept", "include \"/"})
    EXPECT_EQ(enc.model.find(name), std::string::npos) << name;
  EXPECT_EQ(enc.data["H"], 9);
  EXPECT_EQ(enc.data["T"], enc.time_bound);
  EXPECT_EQ(enc.time_bound, 2400 + 9 * 60);
}

TEST(Encode, ChangeConditionsAreFalseAtTheFirstEvent) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Load("presentation", "presentation/test1_cot.json");
  EncodeOptions o;
  Encoding enc = Encode(d, sp, Analyze(d, sp), o);
  // ShutdownWithin600 event 1 is "projl[i]==projOn /\ projl[i+1]==projConfirm".
  EXPECT_NE(enc.model.find("(if k = 0 then false else ((L[3,k-1] = 2) /\\ (L[3,k] = 3)) endif)"),
            std::string::npos);
  // A state condition reads the stage after the event: "projl[i+1]==projOn".
  EXPECT_NE(enc.model.find("array1d(0..H, [(L[3,k] = 2) | k in 0..H])"), std::string::npos);
}

TEST(Encode, DistanceTablesAreShortestPaths) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Load("presentation", "presentation/test1_cot.json");
  Encoding enc = Encode(d, sp, Analyze(d, sp), EncodeOptions{});
  const Json& proj = enc.data["DIST"][2];
  EXPECT_EQ(proj[0][0], 0);
  EXPECT_EQ(proj[1][2], 30);    // warm-up to on
  EXPECT_EQ(proj[1][0], 30 + 0 + 60);  // warm-up, on, (disconnect) cool-down, off
  const Json& cost = enc.data["CDIST"][2];
  EXPECT_EQ(cost[0][2], 2);
  EXPECT_EQ(cost[2][0], 2);  // on -> cool-down (automatic) -> off
}

TEST(Encode, ObjectiveFactorsAndBound) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Load("presentation", "presentation/test1_cot.json");
  EncodeOptions o;
  o.objective = Objective::kCostThenMakespan;
  o.better_than = 12345;
  Encoding enc = Encode(d, sp, Analyze(d, sp), o);
  EXPECT_EQ(enc.objective_cost_factor, enc.time_bound + 1);
  EXPECT_EQ(enc.objective_makespan_factor, 1);
  EXPECT_NE(enc.model.find("constraint objective < 12345;"), std::string::npos);
}

TEST(Encode, EveryExampleModelFlattensWithMiniZinc) {
  for (auto [domain, file] : {std::pair{"presentation", "presentation/test2_cot.json"},
                              {"search_rescue", "search_rescue/test1.json"},
                              {"assembly", "assembly/test.json"}}) {
    const Domain& d = testing::ShippedDomain(domain);
    StatePlan sp = Load(domain, file);
    EncodeOptions o;
    o.horizon = 2;
    Encoding enc = Encode(d, sp, Analyze(d, sp), o);
    RunRequest req;
    req.model = enc.model;
    req.data = enc.data;
    req.time_limit_ms = 20000;
    RunResult r = RunMiniZinc(req);
    EXPECT_TRUE(r.status == RunResult::Status::kInfeasible || r.status == RunResult::Status::kOptimal)
        << file << ": " << RunStatusName(r.status) << " " << r.error << "\n" << r.solver_stderr;
  }
}

}  // namespace
}  // namespace ctb
