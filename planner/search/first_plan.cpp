#include "planner/search/first_plan.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>
#include <unordered_map>
#include <unordered_set>

#include "planner/search/expand.h"
#include "planner/search/history_nodes.h"
#include "planner/search/relaxed_plan.h"
#include "planner/verify/verify.h"

namespace ctb {

namespace {

using search::Candidate;
using search::Expander;
using search::Node;
using search::RelaxedPlan;
using search::StageView;
using Clock = std::chrono::steady_clock;
using Value = std::pair<long, long>;  // the objective, compared lexicographically

struct KeyHash {
  std::size_t operator()(const std::vector<long>& k) const {
    std::size_t h = 1469598103934665603ull;
    for (long v : k) h = (h ^ static_cast<std::size_t>(v)) * 1099511628211ull;
    return h;
  }
};

// Successor kinds, in the order the search prefers them among children of one node: all the
// helpful transitions at once, one helpful transition, waiting for what is due, the node's
// other choices (generated only when the node comes up a second time).
enum Rank { kMacro = 0, kHelpful = 1, kWait = 2, kFull = 3, kOther = 4 };

struct Entry {
  double h;
  long then;  // the second objective so far (cost_then_makespan's time; 0 otherwise): ties on h
  int rank;
  long seq;
  int node;
  bool operator>(const Entry& o) const {
    if (h != o.h) return h > o.h;
    if (then != o.then) return then > o.then;
    if (rank != o.rank) return rank > o.rank;
    return seq > o.seq;
  }
};

class Search {
 public:
  Search(const Domain& d, const StatePlan& sp, const FirstPlanOptions& o)
      : d_(d), sp_(sp), o_(o), tps_(std::lround(1.0 / d.time_resolution)), ex_(d, sp, tps_),
        rp_(d, sp, o.objective, tps_), t0_(Clock::now()),
        scripted_(o.scripts.size() == d.automata.size() && !o.history) {
    if (o.history) ex_.SetEarliest(o.history->now);
  }

  FirstPlanResult Run() {
    if (!ex_.Declined().empty()) {
      r_.declined = ex_.Declined();
      return r_;
    }
    if (o_.history && sp_.HasActionRules()) {
      r_.declined = "replanning a state plan that orders or forbids actions";
      return r_;
    }
    if (o_.history && !o_.history->keep_next.empty()) {
      r_.declined = "keep: started (transitions in progress must go on)";
      return r_;
    }
    std::vector<Node> start = Start();
    if (start.empty()) return Finish(true);
    for (Node& n : start) {
      pool_.push_back(std::move(n));
      if (scripted_) progress_.emplace_back(d_.automata.size(), 0);
    }
    const int s = static_cast<int>(pool_.size()) - 1;
    auto root_key = ex_.Key(pool_[s]);
    if (scripted_) root_key.insert(root_key.end(), progress_[s].begin(), progress_[s].end());
    seen_[std::move(root_key)] = ValueOf(pool_[s]);
    if (pool_[s].done) {
      Offer(s);
      return Finish(true);
    }
    Push(s, 0, kMacro);
    while (!open_.empty()) {
      ++r_.expanded;
      if (OutOfTime()) return Finish(false);
      if (o_.max_expanded > 0 && r_.expanded > o_.max_expanded) return Finish(false);
      if (stop_) return Finish(false);
      Entry e = open_.top();
      open_.pop();
      if (!Improves(ValueOf(pool_[e.node]))) continue;  // cannot improve
      if (e.rank == kFull) {
        Expand(e.node, false);
        continue;
      }
      auto est = rp_.Evaluate(pool_[e.node]);
      if (est.dead) continue;
      helpful_[e.node] = est.helpful;
      h_[e.node] = est.h;
      Expand(e.node, true);
      if (!stop_) Push(e.node, est.h, kFull);
    }
    return Finish(true);
  }

 private:
  long ElapsedMs() const {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0_).count();
  }

  bool OutOfTime() const {
    if (o_.cancel && o_.cancel->load()) return true;
    return ElapsedMs() >= deadline_ms_;
  }

  // The nodes the run begins with: the initial state, or the history's stages 0..p (the search
  // goes on from the last one).
  std::vector<Node> Start() const {
    if (o_.history) return search::HistoryNodes(ex_, d_, *o_.history);
    std::vector<Node> out;
    if (auto root = ex_.Root()) out.push_back(std::move(*root));
    return out;
  }

  Value ValueOf(const Node& n) const { return ObjectiveKey(o_.objective, n.cost, n.time); }

  // Greedy on h until the first plan; then on g + h (the objective so far plus the estimate), so
  // that the improvement phase looks for better plans rather than other plans.
  // Improving under cost_then_makespan, of two nodes equal on g + h the earlier comes first: plans
  // of one cost differ in makespan only.
  void Push(int node, double h, Rank rank) {
    Entry e{h, 0, rank, seq_++, node};
    if (improving_) Rekey(e);
    open_.push(e);
  }

  // An entry of the improvement phase: on g + h, ties on the second objective so far.
  void Rekey(Entry& e) const {
    const Value g = ValueOf(pool_[e.node]);
    e.h += static_cast<double>(g.first);
    e.then = g.second;
  }

  // At the first plan: the open list again, ordered on g + h.
  void Reorder() {
    std::vector<Entry> all;
    for (; !open_.empty(); open_.pop()) all.push_back(open_.top());
    for (Entry e : all) {
      Rekey(e);
      open_.push(e);
    }
    improving_ = true;
  }

  // Adds a child unless an equal future was reached at least as well; a finished run is offered
  // as a plan instead.
  void Add(int parent, std::optional<Node> child, Rank rank) {
    ++r_.generated;
    if (!child || child->event > o_.max_events) return;
    child->parent = parent;
    if (!Improves(ValueOf(*child))) return;
    std::vector<int> progress;
    if (scripted_ && !Follows(parent, *child, progress)) return;
    auto key = ex_.Key(*child);
    key.insert(key.end(), progress.begin(), progress.end());
    const Value v = ValueOf(*child);
    auto it = seen_.find(key);
    if (it != seen_.end() && !(v < it->second)) return;
    seen_[std::move(key)] = v;
    pool_.push_back(std::move(*child));
    if (scripted_) progress_.push_back(std::move(progress));
    const int idx = static_cast<int>(pool_.size()) - 1;
    if (pool_[idx].done) {
      Offer(idx);
      return;
    }
    Push(idx, h_[parent], rank);
  }

  // Preferred successors first (the helpful transitions together, each alone at its earliest
  // time, at the monitors' target times and that transition's lead before them, waiting); the
  // others on the node's second turn.
  // When the helpful transitions fire together, each alone waits for the second turn too: with
  // a team of hundreds, generating every single one at every node was most of the search.
  void Expand(int idx, bool preferred) {
    const Node n = pool_[idx];  // a copy: pool_ grows below
    const StageView v = ex_.View(n);
    std::vector<Candidate> cands = OnScript(idx, ex_.Candidates(n, v));
    // Scripted automata go as soon as they can, all together: their own timings would make a
    // plateau of equal estimates that the few free automata's search is lost in.
    if (scripted_) {
      std::vector<Candidate> held = TakeHeld(idx, cands);
      if (preferred) HeldMacro(idx, n, v, held);
    }
    std::vector<long> targets = ex_.Targets(n);
    // In a round of the neighbourhood search, the free automata also aim at the times automatic
    // transitions are due (a device started its lead before another's warm-up ends takes its turn
    // without a gap).
    if (scripted_) {
      const std::vector<long> due = ex_.DueTimes(n, v);
      targets.insert(targets.end(), due.begin(), due.end());
      std::sort(targets.begin(), targets.end());
      targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
    }
    const auto& helpful = helpful_[idx];
    auto is_helpful = [&](const Candidate& c) {
      for (const auto& m : c.Members())
        if (std::find(helpful.begin(), helpful.end(), m) != helpful.end()) return true;
      return false;
    };
    auto singles = [&](const Candidate& c, Rank rank) {
      const std::vector<std::pair<int, int>> lead = {{c.automaton, c.transition}};
      Add(idx, ex_.Apply(n, v, lead, c.earliest, c.commands), rank);
      const long before = ex_.Lead(c.automaton, c.transition);
      for (long target : targets)
        for (long t : {target, target - before})
          if (t > c.earliest && t <= c.latest && (t == target || before > 0))
            Add(idx, ex_.Apply(n, v, lead, t, c.commands), rank);
    };
    if (!preferred) {
      if (deferred_.erase(idx))
        for (const Candidate& c : cands)
          if (is_helpful(c)) singles(c, kHelpful);
      for (const Candidate& c : cands)
        if (!is_helpful(c)) singles(c, kOther);
      return;
    }
    std::vector<const Candidate*> mine;
    for (const Candidate& c : cands)
      if (is_helpful(c)) mine.push_back(&c);
    std::optional<Node> macro;
    if (mine.size() > 1) macro = Macro(n, v, mine);
    if (macro) {
      Add(idx, std::move(macro), kMacro);
      deferred_.insert(idx);
    } else {
      for (const Candidate* c : mine) singles(*c, kHelpful);
    }
    const long due = ex_.DueTime(n, v);
    if (due < search::kInfinity) Add(idx, ex_.Apply(n, v, {}, due), kWait);
  }

  // Every helpful transition that can fire at the earliest time any of them can, one per
  // automaton, lower-indexed automata first: one that would break the guard of one already in
  // (a guard may read another automaton's command) or whose own guard fails is left out. When
  // all of them (one per automaton) fire together, that is the macro at once: a team of 1,000
  // robots otherwise paid 1,000 applications of growing sets (quadratic) at every node.
  std::optional<Node> Macro(const Node& n, const StageView& v,
                            const std::vector<const Candidate*>& mine, int least = 2,
                            long at = search::kInfinity) {
    if (at == search::kInfinity)
      for (const Candidate* c : mine) at = std::min(at, c->earliest);
    std::vector<std::pair<int, int>> chosen, given;
    std::vector<char> taken(d_.automata.size(), 0);
    // A candidate due at `at` whose automaton and commanded partners no chosen one holds.
    auto fits = [&](const Candidate* c) {
      if (c->earliest > at || c->latest < at || taken[c->automaton]) return false;
      for (auto [a, cmd] : c->commands)
        if (taken[a]) return false;
      return true;
    };
    auto choose = [&](const Candidate* c) {
      chosen.emplace_back(c->automaton, c->transition);
      given.insert(given.end(), c->commands.begin(), c->commands.end());
    };
    auto take = [&](const Candidate* c) {
      taken[c->automaton] = 1;
      for (auto [a, cmd] : c->commands) taken[a] = 1;
    };
    {
      int count = 0;
      for (const Candidate* c : mine) {
        if (!fits(c)) continue;
        choose(c);
        take(c);
        ++count;
      }
      if (count >= least)
        if (auto all = ex_.Apply(n, v, chosen, at, given)) return all;
      chosen.clear();
      given.clear();
      std::fill(taken.begin(), taken.end(), 0);
    }
    int picked = 0;
    for (const Candidate* c : mine) {
      if (!fits(c)) continue;
      choose(c);
      if (ex_.Apply(n, v, chosen, at, given)) {
        take(c);
        ++picked;
      } else {
        chosen.pop_back();
        given.resize(given.size() - c->commands.size());
      }
    }
    if (picked < least) return std::nullopt;
    return ex_.Apply(n, v, chosen, at, given);
  }

  // Strictly better than the best plan so far and than FirstPlanOptions::better_than.
  bool Improves(const Value& v) const {
    if (best_ && !(v < *best_)) return false;
    return !o_.better_than || v < *o_.better_than;
  }

  // Scripts (FirstPlanOptions::scripts): whether the child's transitions are each its scripted
  // automaton's next one; `progress` is then how far every script has gone.
  bool Follows(int parent, const Node& child, std::vector<int>& progress) const {
    progress = progress_[parent];
    for (auto [a, ti] : child.fired) {
      if (!o_.scripts[a]) continue;
      if (!Next(progress, a, ti)) return false;
      ++progress[a];
    }
    return true;
  }

  // Whether transition ti is scripted automaton a's next, its script gone as far as `at` says.
  bool Next(const std::vector<int>& at, int a, int ti) const {
    const std::vector<int>& script = *o_.scripts[a];
    return at[a] < static_cast<int>(script.size()) && script[at[a]] == ti;
  }

  // The candidates whose every scripted member is its automaton's next transition.
  std::vector<Candidate> OnScript(int idx, std::vector<Candidate> cands) const {
    if (!scripted_) return cands;
    const std::vector<int>& at = progress_[idx];
    auto off = [&](const Candidate& c) {
      for (auto [a, ti] : c.Members())
        if (o_.scripts[a] && !Next(at, a, ti)) return true;
      return false;
    };
    cands.erase(std::remove_if(cands.begin(), cands.end(), off), cands.end());
    return cands;
  }

  // Scripts: the held automata's transitions that can fire at the earliest time any of them can,
  // together; when the rules refuse every group there (one would break the maintenance
  // constraint), at the next such time, so that a held automaton may wait for another's.
  void HeldMacro(int idx, const Node& n, const StageView& v, const std::vector<Candidate>& held) {
    std::vector<const Candidate*> all;
    std::vector<long> times;
    for (const Candidate& c : held) {
      all.push_back(&c);
      times.push_back(c.earliest);
    }
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());
    for (long at : times)
      if (auto node = Macro(n, v, all, 1, at)) {
        Add(idx, std::move(node), kMacro);
        return;
      }
  }

  // Scripts: removes from `cands` and returns those whose members are all scripted, in the order
  // of their ranks (FirstPlanOptions::script_ranks) when given.
  std::vector<Candidate> TakeHeld(int idx, std::vector<Candidate>& cands) const {
    std::vector<Candidate> held, rest;
    for (Candidate& c : cands) {
      bool all = true;
      for (auto [a, ti] : c.Members()) all = all && o_.scripts[a].has_value();
      (all ? held : rest).push_back(std::move(c));
    }
    cands = std::move(rest);
    if (o_.script_ranks.size() == o_.scripts.size()) {
      const std::vector<int>& at = progress_[idx];
      auto rank = [&](const Candidate& c) {
        int r = std::numeric_limits<int>::max();
        for (auto [a, ti] : c.Members())
          if (at[a] < static_cast<int>(o_.script_ranks[a].size()))
            r = std::min(r, o_.script_ranks[a][at[a]]);
        return r;
      };
      std::stable_sort(held.begin(), held.end(),
                       [&](const Candidate& x, const Candidate& y) { return rank(x) < rank(y); });
    }
    return held;
  }

  Trajectory Build(int idx) const {
    std::vector<int> chain;
    for (int i = idx; i >= 0; i = pool_[i].parent) chain.push_back(i);
    std::reverse(chain.begin(), chain.end());
    const std::size_t na = d_.automata.size();
    const int g = static_cast<int>(chain.size()) - 1;
    Trajectory t;
    t.history = o_.history;
    t.goal_event = g;
    t.horizon = g;
    t.locations.assign(na, std::vector<int>(g + 1, 0));
    t.commands.assign(na, std::vector<int>(g + 1, 0));
    for (int k = 0; k <= g; ++k) {
      const Node& n = pool_[chain[k]];
      t.events.push_back(n.time);
      for (std::size_t a = 0; a < na; ++a) t.locations[a][k] = n.loc[a];
      for (auto [a, c] : n.cmds_before) t.commands[a][k - 1] = c;
      for (auto [a, ti] : n.fired) t.fired.push_back({k, a, ti});
    }
    const search::Monitors& m = pool_[idx].mon;
    for (std::size_t p = 0; p < sp_.episodes.size(); ++p)
      t.episodes.emplace_back(m.ep_start[p], m.ep_end[p]);
    for (std::size_t q = 0; q < sp_.temporals.size(); ++q)
      t.temporals.emplace_back(m.tc_k1[q], m.tc_k2[q]);
    // Orders: an `every` second end is its last firing, or the first end when none.
    for (std::size_t q = 0; q < sp_.orders.size(); ++q)
      t.orders.emplace_back(m.ord_k1[q], m.ord_k2[q] >= 0 ? m.ord_k2[q] : m.ord_k1[q]);
    return t;
  }

  // A finished run: kept when the verifier accepts it and it is strictly better.
  void Offer(int idx) {
    const Node& n = pool_[idx];
    const Value v = ValueOf(n);
    if (!Improves(v)) return;
    Trajectory t = Build(idx);
    if (!VerifyTrajectory(t, d_, sp_, tps_).empty()) {
      ++r_.rejected;
      return;
    }
    // The improvement window after the first plan; with a bound to reach (good_enough), the
    // whole budget: a plan that meets it spares the exact engines the proof.
    if (!best_ && !o_.good_enough) {
      const long now = ElapsedMs();
      deadline_ms_ = std::min(deadline_ms_, now + std::max(o_.improve_min_ms, now));
    }
    if (!best_) Reorder();
    best_ = v;
    r_.best = std::move(t);
    r_.cost = n.cost;
    r_.makespan = n.time;
    if (o_.on_plan) o_.on_plan(*r_.best, r_.cost, r_.makespan);
    if (o_.good_enough && o_.good_enough(r_.cost, r_.makespan)) stop_ = true;
  }

  FirstPlanResult Finish(bool exhausted) {
    r_.exhausted = exhausted && !stop_;
    r_.elapsed_ms =
        std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0_).count();
    return r_;
  }

  const Domain& d_;
  const StatePlan& sp_;
  const FirstPlanOptions& o_;
  long tps_;
  Expander ex_;
  RelaxedPlan rp_;
  Clock::time_point t0_;
  const bool scripted_;
  std::vector<Node> pool_;
  std::vector<std::vector<int>> progress_;  // scripted: per node, how far each script has gone
  std::unordered_map<int, std::vector<std::pair<int, int>>> helpful_;
  std::unordered_map<int, double> h_;
  std::unordered_set<int> deferred_;  // nodes whose helpful singles wait for the second turn
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open_;
  std::unordered_map<std::vector<long>, Value, KeyHash> seen_;
  std::optional<Value> best_;
  long seq_ = 0;
  long deadline_ms_ = o_.time_limit_ms;
  bool stop_ = false;
  bool improving_ = false;
  FirstPlanResult r_;
};

}  // namespace

std::pair<long, long> ObjectiveKey(Objective objective, long cost, long makespan) {
  switch (objective) {
    case Objective::kCost: return {cost, 0};
    case Objective::kMakespan: return {makespan, 0};
    case Objective::kCostThenMakespan: return {cost, makespan};
  }
  return {0, 0};
}

FirstPlanResult FindFirstPlan(const Domain& d, const StatePlan& sp, const FirstPlanOptions& o) {
  return Search(d, sp, o).Run();
}

}  // namespace ctb
