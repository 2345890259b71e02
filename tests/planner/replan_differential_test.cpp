// The replanning differential check (issue 21): random problems, a random `now` along the optimal
// plan, random departures (a blocked transition, an observation, a transition that did not
// happen). Every answer's history + future, rebuilt from the answer's JSON alone, must pass the
// independent verifier against the state plan with the blocked transitions removed; the
// prechecks and the first-plan engine (both on by default) must agree with the exact engines
// alone; and for tiny cases an enumeration of every future with at most 2 events confirms the
// future's optimum.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <random>

#include "planner/expr/expr_print.h"
#include "planner/replan/replan.h"
#include "planner/verify/verify.h"
#include "random_problem.h"
#include "test_util.h"

namespace ctb {
namespace {

constexpr int kFutureEvents = 2;

Domain WithoutBlocked(const Domain& d, const Json& blocked) {
  Domain out = d;
  for (const auto& b : blocked) {
    Automaton& a = out.automata[d.AutomatonIndex(b["automaton"])];
    for (auto& t : a.transitions)
      if (a.locations[t.from] == b["from"] && a.locations[t.to] == b["to"]) {
        t.guard = Expr{};
        t.guard.op = Expr::Op::kFalse;
        t.guard_info = ExprInfo{};
      }
  }
  return out;
}

// The run the answer describes, with its history (the transitions marked executed or observed),
// rebuilt without planner/replan. `since` holds the observations' since times.
std::optional<Trajectory> FromAnswer(const Json& ans, const Domain& d, const StatePlan& sp,
                                     const std::map<int, long>& since, long now) {
  Trajectory t;
  for (const auto& e : ans["events"]) t.events.push_back(e.get<long>());
  const int g = static_cast<int>(t.events.size()) - 1;
  const std::size_t na = d.automata.size();
  t.goal_event = g;
  t.horizon = ans["horizon"].get<int>();
  t.locations.assign(na, std::vector<int>(g + 1));
  t.commands.assign(na, std::vector<int>(g + 1, 0));
  auto h = std::make_shared<History>();
  std::vector<int> loc = sp.initial;
  std::vector<long> entry(na, 0);
  int p = 0;
  for (const auto& tr : ans["transitions"])
    if (tr.value("executed", false) || tr.value("observed", false)) p = std::max(p, tr["event"].get<int>());
  std::size_t next = 0;
  const Json& trs = ans["transitions"];
  for (int k = 0; k <= g; ++k) {
    for (; next < trs.size() && trs[next]["event"].get<int>() == k; ++next) {
      const Json& tr = trs[next];
      const int a = d.AutomatonIndex(tr["automaton"]);
      const Automaton& au = d.automata[a];
      const int from = au.LocationIndex(tr["from"]), to = au.LocationIndex(tr["to"]);
      if (tr.value("observed", false)) {
        h->jumps.push_back({k, a, from, to});
        // An observation with `since` sets the clock, also where the automaton already was.
        if (from != to || since.count(a)) entry[a] = since.count(a) ? since.at(a) : now;
        loc[a] = to;
        continue;
      }
      int idx = -1;
      for (std::size_t x = 0; x < au.transitions.size() && idx < 0; ++x) {
        const Transition& c = au.transitions[x];
        if (c.from != from || c.to != to) continue;
        const bool named = tr["command"].is_string();
        if (named != (c.commanded && c.command > 0)) continue;
        if (named && au.commands[c.command - 1] != tr["command"]) continue;
        const bool holds = Evaluate(c.guard, [&](const Expr& atom) {
          if (atom.var_kind == VarKind::kLocation) return t.locations[atom.target][k - 1];
          if (atom.target == a) return c.commanded ? c.command : 0;  // its own command
          return t.commands[atom.target][k - 1];
        });
        if (holds || k <= p) idx = static_cast<int>(x);
      }
      if (idx < 0) return std::nullopt;
      const Transition& c = au.transitions[idx];
      if (c.commanded) t.commands[a][k - 1] = c.command;
      t.fired.push_back({k, a, idx});
      if (k <= p) h->fired.push_back({k, a, idx});
      loc[a] = to;
      entry[a] = t.events[k];
    }
    for (std::size_t a = 0; a < na; ++a) t.locations[a][k] = loc[a];
    if (k <= p) {
      h->times.push_back(t.events[k]);
      if (h->locations.empty()) h->locations.assign(na, {}), h->entry.assign(na, {});
      for (std::size_t a = 0; a < na; ++a) {
        h->locations[a].push_back(loc[a]);
        h->entry[a].push_back(entry[a]);
      }
    }
  }
  h->now = now;
  t.history = h;
  for (const auto& ep : sp.episodes)
    t.episodes.emplace_back(ans["episodes"][ep.name]["start_event"].get<int>(),
                            ans["episodes"][ep.name]["end_event"].get<int>());
  for (const auto& q : sp.temporals)
    t.temporals.emplace_back(ans["temporal"][q.name]["event1_event"].get<int>(),
                             ans["temporal"][q.name]["event2_event"].get<int>());
  return t;
}

struct Best {
  long cost = 0, makespan = 0;
};

// Every future with at most kFutureEvents events after the history (integer times from now to
// the bound, every transition choice and every placement of the state plan's events), checked by
// the verifier alone.
class FutureEnumerator {
 public:
  FutureEnumerator(const Domain& d, const StatePlan& sp, const Trajectory& base, long bound)
      : d_(d), sp_(sp), base_(base), tb_(bound) {}

  std::optional<Best> Run() {
    const int p = base_.history->events();
    for (int g = p; g <= p + kFutureEvents; ++g) {
      Trajectory t;
      t.history = base_.history;
      t.goal_event = g;
      t.horizon = g;
      t.events.assign(base_.history->times.begin(), base_.history->times.end());
      t.events.resize(g + 1, 0);
      t.locations.assign(d_.automata.size(), std::vector<int>(g + 1, 0));
      t.commands.assign(d_.automata.size(), std::vector<int>(g + 1, 0));
      for (std::size_t a = 0; a < d_.automata.size(); ++a)
        for (int k = 0; k <= p; ++k) {
          t.locations[a][k] = base_.history->locations[a][k];
          if (k < p) t.commands[a][k] = base_.commands[a][k];
        }
      t.fired = base_.history->fired;
      Times(t, p + 1);
    }
    return best_;
  }

 private:
  void Times(Trajectory& t, int k) {
    if (k > t.goal_event) return Transitions(t, t.history->events() + 1);
    for (long time = std::max(t.history->now, t.events[k - 1]); time <= tb_; ++time) {
      t.events[k] = time;
      Times(t, k + 1);
    }
  }
  void Transitions(Trajectory& t, int k) {
    if (k > t.goal_event) return Placements(t, 0);
    const int na = static_cast<int>(d_.automata.size());
    std::function<void(int, bool)> each = [&](int a, bool any) {
      if (a == na) {
        if (any) Transitions(t, k + 1);
        return;
      }
      const Automaton& au = d_.automata[a];
      const int loc = t.locations[a][k - 1];
      t.locations[a][k] = loc;
      t.commands[a][k - 1] = 0;
      each(a + 1, any);
      for (std::size_t x = 0; x < au.transitions.size(); ++x) {
        if (au.transitions[x].from != loc) continue;
        t.locations[a][k] = au.transitions[x].to;
        t.commands[a][k - 1] = au.transitions[x].commanded ? au.transitions[x].command : 0;
        t.fired.push_back({k, a, static_cast<int>(x)});
        each(a + 1, true);
        t.fired.pop_back();
      }
      t.locations[a][k] = loc;
      t.commands[a][k - 1] = 0;
    };
    each(0, false);
  }
  void Placements(Trajectory& t, std::size_t i) {
    const std::size_t ne = sp_.episodes.size(), nq = sp_.temporals.size();
    if (i == 0) {
      t.episodes.assign(ne, {0, 0});
      t.temporals.assign(nq, {0, 0});
    }
    if (i == ne + nq) {
      std::vector<FiredTransition> sorted = t.fired;
      std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) {
        return a.event != b.event ? a.event < b.event : a.automaton < b.automaton;
      });
      std::swap(t.fired, sorted);
      if (TrajectoryIsPlan(t, d_, sp_, 1)) {
        Best b{TrajectoryCost(t, d_), t.events[t.goal_event]};
        const Objective o = sp_.objective;
        bool better = !best_ || (o == Objective::kCost ? b.cost < best_->cost
                                 : o == Objective::kMakespan
                                     ? b.makespan < best_->makespan
                                     : b.cost < best_->cost ||
                                           (b.cost == best_->cost && b.makespan < best_->makespan));
        if (better) best_ = b;
      }
      std::swap(t.fired, sorted);
      return;
    }
    for (int x = 0; x <= t.goal_event; ++x)
      for (int y = 0; y <= t.goal_event; ++y) {
        if (i < ne && y <= x) continue;
        if (i < ne) t.episodes[i] = {x, y};
        else t.temporals[i - ne] = {x, y};
        Placements(t, i + 1);
      }
  }

  const Domain& d_;
  const StatePlan& sp_;
  const Trajectory& base_;
  long tb_;
  std::optional<Best> best_;
};

Json Value(Objective o, const Best& b) {
  if (o == Objective::kCost) return b.cost;
  if (o == Objective::kMakespan) return b.makespan;
  return {{"cost", b.cost}, {"makespan", b.makespan}};
}

TEST(ReplanDifferential, HistoryPlusFutureVerifiesAndTinyOptimaAreTrue) {
  testing::RandomShape shape;
  shape.max_automata = 2;
  shape.max_locations = 3;
  shape.max_duration = 2;
  shape.max_bound = 3;
  int checked = 0, plans = 0, infeasible = 0, brute = 0, heuristic = 0;
  for (unsigned seed = 2100; seed < 2160; ++seed) {
    testing::ProblemGenerator gen(seed, shape);
    testing::RandomProblem prob = gen.Next();
    Diagnostics diags;
    auto d = LoadDomain(prob.domain, diags);
    ASSERT_TRUE(d) << testing::AllErrors(diags);
    auto sp = LoadStatePlan(prob.state_plan, *d, diags);
    ASSERT_TRUE(sp) << testing::AllErrors(diags);
    SolveOptions so;
    so.max_horizon = 6;
    so.time_limit_ms = 60000;
    auto solved = SolveDocument(*d, *sp, so);
    ASSERT_TRUE(std::holds_alternative<Json>(solved));
    const Json plan = std::get<Json>(solved);
    if (plan["status"] != "optimal") continue;
    std::mt19937 rng(seed);
    auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    const long now = pick(0, plan["goal_reached_at"].get<int>());
    Json body = {{"now", now}, {"trajectory", plan}};
    std::map<int, long> since;
    const int kind = pick(0, 3);
    const int a = pick(0, static_cast<int>(d->automata.size()) - 1);
    const Automaton& au = d->automata[a];
    if (kind == 1 && !au.transitions.empty()) {
      const Transition& t = au.transitions[pick(0, static_cast<int>(au.transitions.size()) - 1)];
      body["blocked"] = {{{"automaton", au.name}, {"from", au.locations[t.from]}, {"to", au.locations[t.to]}}};
    } else if (kind == 2) {
      const long s = pick(0, static_cast<int>(now));
      body["observed"] = {{au.name, {{"location", au.locations[pick(0, static_cast<int>(au.locations.size()) - 1)]}, {"since", s}}}};
      since[a] = s;
    } else if (kind == 3) {
      Json executed = Json::array();
      for (const auto& t : plan["transitions"])
        if (t["time"].get<long>() < now) executed.push_back(t);
      if (!executed.empty()) executed.erase(executed.end() - 1);  // the last one did not happen
      body["executed"] = executed;
    }
    const std::string what = "seed " + std::to_string(seed) + " request " + body.dump() + "\n" + prob.Describe();
    ReplanRequest req;
    ASSERT_FALSE(ReadReplanRequest(body, req, nullptr));
    ReplanOptions o;
    o.solve.max_horizon = 6;
    o.solve.time_limit_ms = 60000;
    auto r = ReplanDocument(*d, *sp, req, o);
    ASSERT_TRUE(std::holds_alternative<Json>(r)) << std::get<Error>(r).ToString() << what;
    const Json ans = std::get<Json>(r);
    ++checked;
    // The prechecks and the first-plan engine agree with the exact engines alone.
    o.precheck = false;
    o.solve.first_plan_ms = 0;
    auto r2 = ReplanDocument(*d, *sp, req, o);
    o.solve.first_plan_ms = -1;
    ASSERT_TRUE(std::holds_alternative<Json>(r2)) << what;
    EXPECT_EQ(std::get<Json>(r2)["status"], ans["status"]) << what;
    EXPECT_EQ(std::get<Json>(r2)["objective"]["value"], ans["objective"]["value"]) << what;
    if (ans["status"] == "infeasible") {
      ++infeasible;
      EXPECT_FALSE(ans["explanation"]["conflicts"].empty()) << what;
      continue;
    }
    ASSERT_EQ(ans["status"], "optimal") << ans.dump() << what;
    ++plans;
    heuristic += ans["stats"]["found_by"] == "heuristic" ? 1 : 0;
    const Domain model = WithoutBlocked(*d, body.value("blocked", Json::array()));
    auto traj = FromAnswer(ans, model, *sp, since, now);
    ASSERT_TRUE(traj) << "cannot rebuild the run: " << ans.dump() << what;
    auto problems = VerifyTrajectory(*traj, model, *sp, 1);
    EXPECT_TRUE(problems.empty()) << problems[0] << "\n" << ans.dump() << what;
    // Tiny cases: the enumeration of every future with at most 2 events.
    if (sp->episodes.size() + sp->temporals.size() <= 1 && d->automata.size() <= 2) {
      long lower = 0, max_lo = 0;
      for (const auto& e : sp->episodes) lower += static_cast<long>(e.lower);
      for (const auto& q : sp->temporals) lower += static_cast<long>(q.lower);
      for (const auto& au2 : d->automata)
        for (const auto& t : au2.transitions) max_lo = std::max(max_lo, static_cast<long>(t.duration.lo));
      FutureEnumerator en(model, *sp, *traj, now + lower + kFutureEvents * max_lo + 1);
      auto truth = en.Run();
      o.precheck = true;
      o.solve.max_horizon = kFutureEvents;
      auto small = ReplanDocument(*d, *sp, req, o);
      ASSERT_TRUE(std::holds_alternative<Json>(small)) << what;
      const Json& s = std::get<Json>(small);
      if (truth) {
        EXPECT_EQ(s["status"], "optimal") << s.dump() << what;
        EXPECT_EQ(s["objective"]["value"], Value(sp->objective, *truth)) << s.dump() << what;
      } else {
        EXPECT_EQ(s["status"], "infeasible") << s.dump() << what;
      }
      ++brute;
    }
  }
  EXPECT_GE(checked, 30);
  EXPECT_GE(plans, 15);
  EXPECT_GE(brute, 5);
  EXPECT_GE(heuristic, plans / 3);  // the first-plan engine answers from the history
  std::printf("replanned %d problems: %d plans (%d found by the first-plan engine), %d infeasible, "
              "%d checked by enumeration\n", checked, plans, heuristic, infeasible, brute);
}

}  // namespace
}  // namespace ctb
