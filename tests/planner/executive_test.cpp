// The executive's decisions (executive/run.h) driven by the built-in simulated team on a virtual
// clock, on the plans the real minizinc finds for every shipped example and the contingent
// variants: each run reaches the goal with no replan and the realized schedule, rebuilt as a
// trajectory, passes the independent verifier; a report later than the plan's own time but
// inside its slack moves nothing; one outside it asks for a replan; bad reports are refused at
// their pointer; the stored form round-trips.
#include "executive/run.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "executive/sim.h"
#include "planner/flexible/flexible.h"
#include "planner/solve/solve.h"
#include "planner/verify/verify.h"
#include "test_util.h"

namespace ctb {
// A namespace of its own: the test executable's unity build puts files with same-named
// helpers side by side.
namespace executive_test {
namespace {

namespace fs = std::filesystem;
using network::Ticks;

struct Case {
  Domain domain;
  StatePlan sp;
  std::string name;
};

std::vector<Case> Cases() {
  std::vector<Case> out;
  for (const char* d : {"presentation", "search_rescue", "assembly"})
    for (const auto& e : fs::directory_iterator(testing::ConfigDir() + "/examples/" + d))
      out.push_back({testing::ShippedDomain(d), testing::ShippedStatePlan(d, e.path().string()), e.path().string()});
  for (const auto& [dom, files] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"presentation", {"on_within_60", "on_ten_then_off"}}, {"search_rescue", {"rescue_at_door1", "rescue_open_on_arrival"}}}) {
    Diagnostics diags;
    auto d = LoadDomainFile(testing::ConfigDir() + "/uncertain/" + dom + ".json", diags);
    EXPECT_TRUE(d) << testing::AllErrors(diags);
    for (const auto& f : files) {
      auto j = ReadJsonFile(testing::ConfigDir() + "/uncertain/" + f + ".json", diags);
      auto sp = j ? LoadStatePlan(*j, *d, diags) : std::nullopt;
      EXPECT_TRUE(sp) << f << testing::AllErrors(diags);
      if (sp) out.push_back({*d, *sp, f});
    }
  }
  return out;
}

struct Solved {
  Json answer;
  Trajectory plan;
};

std::optional<Solved> SolveCase(const Case& c) {
  Solved s;
  SolveOptions o;
  o.time_limit_ms = 60000;
  o.plan_out = &s.plan;
  auto r = SolveDocument(c.domain, c.sp, o);
  if (auto* e = std::get_if<Error>(&r)) {
    ADD_FAILURE() << e->ToString();
    return std::nullopt;
  }
  s.answer = std::get<Json>(r);
  const std::string status = s.answer["status"];
  if (status != "optimal" && status != "feasible") return std::nullopt;
  return s;
}

// True when `r` (a device's own move) may come `by` seconds later than it says, given what happened.
bool RoomFor(const exec::Run& run, const exec::Report& r, double now, double by) {
  const auto points = run.Points();
  const auto w = run.WindowsAt(now);
  for (std::size_t q = 1; w && q < points.size(); ++q)
    if (!points[q].at && points[q].automaton == r.automaton && points[q].to == *r.location)
      return points[q].command.empty() && (!(*w)[q].latest || *(*w)[q].latest >= r.time + by);
  return false;
}

// Runs the plan against the simulated team on a virtual clock: the realized time of every point
// (ticks), or a test failure. `hold`: (automaton, location) whose report comes `by` s late.
// With `late`, the first report of a transition the devices make on their own whose window,
// given what happened, still allows it comes a whole second late (counted in *held).
std::optional<std::vector<Ticks>> Drive(exec::Run& run, exec::SimTeam& sim, double resolution,
                                        bool late = false, int* held_count = nullptr) {
  const double by = 1;
  double now = 0;
  std::optional<exec::Report> held;
  bool was_held = false;
  for (int step = 0; step < 10000; ++step) {
    for (auto due = sim.Due(run, now); !due.empty(); due = sim.Due(run, now))  // what one report frees, too
    for (const auto& r : due) {
      if (late && !was_held && r.location && RoomFor(run, r, now, by)) {
        if (held_count) ++*held_count;
        held = r;
        held->time += by;
        was_held = true;
        continue;
      }
      auto a = run.Apply(r, now);
      if (auto* e = std::get_if<Error>(&a)) return ADD_FAILURE() << e->ToString(), std::nullopt;
      if (std::get<exec::Applied>(a).replan) return ADD_FAILURE() << *std::get<exec::Applied>(a).replan, std::nullopt;
    }
    if (held && held->time <= now) {
      auto a = run.Apply(*held, now);
      if (auto* e = std::get_if<Error>(&a)) return ADD_FAILURE() << e->ToString(), std::nullopt;
      if (std::get<exec::Applied>(a).replan)
        return ADD_FAILURE() << "a late report inside the slack replans: " << *std::get<exec::Applied>(a).replan,
               std::nullopt;
      held.reset();
    }
    exec::Decision d = run.Advance(now);
    if (d.replan) {
      std::string pts;
      for (const auto& p : run.Points())
        pts += p.automaton + " " + p.from + "->" + p.to + " at=" + (p.at ? std::to_string(*p.at) : "-") +
               " sent=" + (p.sent ? std::to_string(*p.sent) : "-") + " ready=" + std::to_string(p.ready) + "\n";
      return ADD_FAILURE() << "replan at " << now << ": " << *d.replan << "\n" << pts, std::nullopt;
    }
    if (d.finished) {
      std::vector<Ticks> times;
      for (const auto& p : run.Points()) times.push_back(std::llround(p.at.value_or(-1) * 1000));
      return times;
    }
    if (!d.dispatch.empty()) continue;
    std::optional<double> wake = run.NextWake(now);
    if (auto s = sim.NextDue(run, now)) wake = wake ? std::min(*wake, *s) : *s;
    if (held) wake = wake ? std::min(*wake, held->time) : held->time;
    if (!wake) return ADD_FAILURE() << "stuck at " << now, std::nullopt;
    now = std::max(now + resolution / 1000, *wake);
  }
  ADD_FAILURE() << "no end";
  return std::nullopt;
}

TEST(Executive, EveryShippedPlanRunsToItsGoalAndItsRealizedScheduleVerifies) {
  int runs = 0, contingent = 0;
  for (const Case& c : Cases()) {
    SCOPED_TRACE(c.name);
    auto s = SolveCase(c);
    if (!s) continue;  // the impossible examples, and plans not of the asked kind
    const long tps = std::lround(1.0 / c.domain.time_resolution);
    auto f = flexible::DeriveNetwork(s->plan, c.domain, c.sp, tps);
    ASSERT_TRUE(f);
    for (unsigned seed = 1; seed <= 3; ++seed) {
      exec::Run run(c.domain);
      run.SetGrace(0);
      ASSERT_EQ(run.Adopt(s->answer, 0), std::nullopt);
      exec::SimTeam sim({0, 0, 0, seed}, c.domain.time_resolution);
      auto times = Drive(run, sim, c.domain.time_resolution);
      ASSERT_TRUE(times);
      std::string why;
      auto t = flexible::ScheduleToTrajectory(*f, s->plan, *times, &why);
      ASSERT_TRUE(t) << why;
      EXPECT_EQ(VerifyTrajectory(*t, c.domain, c.sp, tps), std::vector<std::string>{}) << "seed " << seed;
      EXPECT_EQ(run.history().size(), s->answer["transitions"].size());
      ++runs;
      contingent += c.domain.HasContingent();
    }
  }
  EXPECT_GE(runs, 30);
  EXPECT_GE(contingent, 6);
}

// A device-driven transition reported a second later than the plan's own time, where its slack
// allows it: nothing replans and the run still verifies. Reported beyond its slack: a replan.
TEST(Executive, ALateReportInsideTheSlackMovesNothingAndOneOutsideReplans) {
  int held = 0;
  for (const Case& c : Cases()) {
    auto s = SolveCase(c);
    if (!s) continue;
    SCOPED_TRACE(c.name);
    exec::Run run(c.domain);
    run.SetGrace(0);
    ASSERT_EQ(run.Adopt(s->answer, 0), std::nullopt);
    exec::SimTeam sim({0, 0, 0, 1}, c.domain.time_resolution);
    ASSERT_TRUE(Drive(run, sim, c.domain.time_resolution, /*late=*/true, &held));
  }
  EXPECT_GE(held, 3) << "devices' moves with room to be late";

  // Beyond the slack: the uncertain rescue, robot 1 at door 1 after [1, 3] s, reported at 5 s.
  Case c = Cases().back();
  for (const Case& x : Cases())
    if (x.name == "rescue_at_door1") c = x;
  auto s = SolveCase(c);
  ASSERT_TRUE(s);
  exec::Run run(c.domain);
  run.SetGrace(0);
  ASSERT_EQ(run.Adopt(s->answer, 0), std::nullopt);
  exec::Decision d = run.Advance(0);
  ASSERT_EQ(d.dispatch.size(), 1u);
  EXPECT_EQ(d.dispatch[0].command, "goToDoor1");
  auto a = run.Apply({"robot1", "goingToDoor1", std::nullopt, 0}, 0);
  ASSERT_TRUE(std::holds_alternative<exec::Applied>(a));
  EXPECT_FALSE(std::get<exec::Applied>(a).replan);
  EXPECT_FALSE(run.Advance(3).replan) << "due by 3 s: not yet overdue";
  auto overdue = run.Advance(4);
  ASSERT_TRUE(overdue.replan);
  EXPECT_NE(overdue.replan->find("overdue"), std::string::npos) << *overdue.replan;
  a = run.Apply({"robot1", "atDoor1", std::nullopt, 5}, 5);
  ASSERT_TRUE(std::holds_alternative<exec::Applied>(a));
  ASSERT_TRUE(std::get<exec::Applied>(a).replan);
  EXPECT_NE(std::get<exec::Applied>(a).replan->find("outside its window [1.0, 3.0]"), std::string::npos)
      << *std::get<exec::Applied>(a).replan;
  const Json req = run.ReplanRequest(5);
  EXPECT_EQ(req["now"], 5);
  EXPECT_EQ(req["executed"].size(), 2u);
}

TEST(Executive, BadReportsAreRefusedAtTheirPointerAndTheStoredFormRoundTrips) {
  Case c = Cases().front();
  for (const Case& x : Cases())
    if (x.name == "rescue_at_door1") c = x;
  auto s = SolveCase(c);
  ASSERT_TRUE(s);
  exec::Run run(c.domain);
  ASSERT_EQ(run.Adopt(s->answer, 0), std::nullopt);
  ASSERT_EQ(run.Advance(0).dispatch.size(), 1u);
  struct Bad {
    exec::Report r;
    std::string pointer;
  };
  const std::vector<Bad> bad = {
      {{"robot7", "atDoor1", std::nullopt, 0}, "/r/automaton"},
      {{"robot1", "onTheMoon", std::nullopt, 0}, "/r/location"},
      {{"robot1", "atDoor1", std::nullopt, 0}, "/r/location"},  // not from outside
      {{"robot1", "goingToDoor1", std::nullopt, 9}, "/r/time"},  // after now
      {{"robot1", std::nullopt, "teleport", 0}, "/r/failed"},
  };
  for (const auto& b : bad) {
    auto a = run.Apply(b.r, 1, "/r");
    ASSERT_TRUE(std::holds_alternative<Error>(a)) << b.pointer;
    EXPECT_EQ(std::get<Error>(a).details.at(0).pointer, b.pointer) << std::get<Error>(a).ToString();
  }
  EXPECT_TRUE(run.history().empty());
  const exec::Report ok{"robot1", "goingToDoor1", std::nullopt, 0};
  EXPECT_FALSE(std::get<exec::Applied>(run.Apply(ok, 1)).duplicate);
  EXPECT_TRUE(std::get<exec::Applied>(run.Apply(ok, 1)).duplicate);
  EXPECT_EQ(run.history().size(), 1u);

  exec::Run back(c.domain);
  ASSERT_EQ(back.FromJson(run.ToJson()), std::nullopt);
  EXPECT_EQ(back.ToJson(), run.ToJson());
  EXPECT_EQ(back.NextWake(1), run.NextWake(1));

  // A move that fails: blocked, and the replan request says so.
  exec::Run fail(c.domain);
  ASSERT_EQ(fail.Adopt(s->answer, 0), std::nullopt);
  fail.Advance(0);
  auto a = fail.Apply({"robot1", std::nullopt, "goToDoor1", 0}, 0);
  ASSERT_TRUE(std::get<exec::Applied>(a).replan);
  const Json req = fail.ReplanRequest(0);
  ASSERT_EQ(req["blocked"].size(), 1u);
  EXPECT_EQ(req["blocked"][0], (Json{{"automaton", "robot1"}, {"from", "outside"}, {"to", "goingToDoor1"}}));

  Diagnostics diags;
  EXPECT_FALSE(exec::ParseReport(Json{{"automaton", "robot1"}, {"location", "a"}, {"failed", "b"}, {"time", 0}}, "", diags));
  EXPECT_TRUE(testing::HasError(diags, "/location", "either"));
}

}  // namespace
}  // namespace executive_test
}  // namespace ctb
