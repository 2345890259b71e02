#include "planner/analyze/workload.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace ctb {

namespace {

constexpr long kNever = EarliestTimes::kNever;

long Add(long a, long b) { return std::min(kNever, a + b); }

using Weight = std::function<long(const Transition&)>;

struct Support {
  int helper = -1;  // -1: not supported
  int at = -1;      // the helper's location the guard needs
};

// One helped automaton's share: at least `runs` runs of at least `run` each, `total` in all,
// none starting before `release`.
struct Job {
  long runs = 0, run = 0, total = 0, release = 0;
};

class WorkloadBound {
 public:
  WorkloadBound(const Domain& d, const StatePlan& sp)
      : d_(d), sp_(sp), tps_(std::max(1L, std::lround(1.0 / d.time_resolution))) {}

  Workload Run(const EarliestTimes* ticks, const EarliestTimes* events) {
    Workload w;
    w.helper.assign(d_.automata.size(), false);
    if (sp_.goal.info.IsChange()) return w;
    pinned_.assign(d_.automata.size(), -1);
    std::vector<std::pair<int, int>> goal;
    RequiredLocations(sp_.goal.expr, goal);
    for (auto [a, l] : goal) pinned_[a] = l;
    FindSupports();
    for (std::size_t k = 0; k < d_.automata.size(); ++k) w.helper[k] = !supporting_[k].empty();
    const int helpers = static_cast<int>(std::count(w.helper.begin(), w.helper.end(), true));
    if (helpers == 0) return w;
    const Weight by_time = [this](const Transition& t) {
      return std::lround(t.duration.lo * static_cast<double>(tps_));
    };
    const Weight by_event = [](const Transition&) { return 1L; };
    const Weight by_cost = [](const Transition& t) { return t.cost; };
    w.makespan_ticks = Spread(Jobs(by_time, ticks), helpers);
    w.events = Spread(Jobs(by_event, events), helpers);
    for (const Job& j : Jobs(by_cost, nullptr)) w.helper_cost += j.total;
    return w;
  }

 private:
  // The required locations of every transition's guard, and which automata need each (k, v).
  void FindSupports() {
    const std::size_t na = d_.automata.size();
    needs_.resize(na);
    std::map<std::pair<int, int>, std::set<int>> users;
    for (std::size_t a = 0; a < na; ++a)
      for (const Transition& t : d_.automata[a].transitions) {
        needs_[a].emplace_back();
        RequiredLocations(t.guard, needs_[a].back());
        for (auto kv : needs_[a].back())
          if (kv.first != static_cast<int>(a)) users[kv].insert(static_cast<int>(a));
      }
    support_.resize(na);
    supporting_.assign(na, {});
    for (std::size_t b = 0; b < na; ++b) {
      const auto& ts = d_.automata[b].transitions;
      support_[b].assign(ts.size(), Support{});
      if (pinned_[b] < 0 || pinned_[b] == sp_.initial[b]) continue;
      for (std::size_t x = 0; x < ts.size(); ++x) {
        if (ts[x].from == ts[x].to) continue;
        for (auto [k, v] : needs_[b][x]) {
          if (k == static_cast<int>(b) || users[{k, v}] != std::set<int>{static_cast<int>(b)}) continue;
          if (!OneUsePerVisit(static_cast<int>(b), ts[x].to, k, v)) continue;
          support_[b][x] = {k, v};
          supporting_[k].insert(v);
          break;
        }
      }
    }
  }

  // True when b, having entered `to` while k is in v, cannot take a transition that needs k in v
  // before k leaves v: no such transition leaves a location b reaches from `to` by transitions
  // that do not need k elsewhere.
  bool OneUsePerVisit(int b, int to, int k, int v) const {
    const auto& ts = d_.automata[b].transitions;
    std::vector<bool> seen(d_.automata[b].locations.size(), false);
    std::vector<int> stack{to};
    seen[to] = true;
    auto needs_k_elsewhere = [&](std::size_t x) {
      for (auto [c, w] : needs_[b][x])
        if (c == k && w != v) return true;
      return false;
    };
    auto needs_k_in_v = [&](std::size_t x) {
      for (auto kw : needs_[b][x])
        if (kw == std::make_pair(k, v)) return true;
      return false;
    };
    while (!stack.empty()) {
      const int l = stack.back();
      stack.pop_back();
      for (std::size_t x = 0; x < ts.size(); ++x) {
        if (ts[x].from != l) continue;
        if (needs_k_in_v(x)) return false;
        if (needs_k_elsewhere(x) || seen[ts[x].to]) continue;
        seen[ts[x].to] = true;
        stack.push_back(ts[x].to);
      }
    }
    return true;
  }

  // What one visit by k to supporting location v is charged (see the header).
  long Charge(int k, int v, const Weight& w) const {
    const Automaton& au = d_.automata[k];
    long own = 0, before = 0;
    if (pinned_[k] >= 0 && pinned_[k] != v) {
      own = kNever;
      for (const Transition& t : au.transitions)
        if (t.from == v && t.to != v) own = std::min(own, w(t));
      if (own >= kNever) own = 0;
    }
    if (v != sp_.initial[k]) {
      before = kNever;
      for (const Transition& t : au.transitions)
        if (t.to == v && t.from != v) before = std::min(before, supporting_[k].count(t.from) ? 0 : w(t));
      if (before >= kNever) before = 0;
    }
    return own + before;
  }

  // No charge of a visit to v starts before k can first enter v or a location it comes from.
  long Release(int k, int v, const EarliestTimes* arrivals) const {
    if (!arrivals) return 0;
    const auto& arr = arrivals->arrival[k];
    long r = arr[v];
    for (const Transition& t : d_.automata[k].transitions)
      if (t.to == v && t.from != v && !supporting_[k].count(t.from)) r = std::min(r, arr[t.from]);
    return r;
  }

  // Each helped automaton's runs, charges and release under weight w.
  std::vector<Job> Jobs(const Weight& w, const EarliestTimes* arrivals) const {
    std::vector<Job> out;
    for (std::size_t b = 0; b < d_.automata.size(); ++b) {
      if (pinned_[b] < 0 || pinned_[b] == sp_.initial[b]) continue;
      if (auto j = JobOf(static_cast<int>(b), w, arrivals)) out.push_back(*j);
    }
    return out;
  }

  std::optional<Job> JobOf(int b, const Weight& w, const EarliestTimes* arrivals) const {
    const Automaton& au = d_.automata[b];
    const auto& ts = au.transitions;
    const auto& sup = support_[b];
    std::vector<long> charge(ts.size(), 0);
    for (std::size_t x = 0; x < ts.size(); ++x)
      if (sup[x].helper >= 0) charge[x] = Charge(sup[x].helper, sup[x].at, w);
    const std::vector<int> held = Held(b);
    auto starts_run = [&](std::size_t x) { return sup[x].helper >= 0 && held[ts[x].from] < 0; };
    Job j;
    j.runs = ShortestFrom(au, sp_.initial[b], [&](const Transition& t) {
      return starts_run(&t - ts.data()) ? 1L : 0L;
    })[pinned_[b]];
    j.total = ShortestFrom(au, sp_.initial[b], [&](const Transition& t) {
      return charge[&t - ts.data()];
    })[pinned_[b]];
    if (j.runs >= kNever || j.total >= kNever) return std::nullopt;  // the goal is out of reach
    if (j.runs == 0) return j;
    const std::vector<long> rest = LeaveHeld(b, held, charge);
    j.run = kNever;
    j.release = kNever;
    for (std::size_t x = 0; x < ts.size(); ++x) {
      if (!starts_run(x)) continue;
      j.run = std::min(j.run, Add(charge[x], held[ts[x].to] >= 0 ? rest[ts[x].to] : 0));
      j.release = std::min(j.release, Release(sup[x].helper, sup[x].at, arrivals));
    }
    if (j.run >= kNever || j.release >= kNever) return std::nullopt;
    return j;
  }

  // For each location of b, the helper every transition in and out of it (loops aside) is
  // supported by, or -1.
  std::vector<int> Held(int b) const {
    const Automaton& au = d_.automata[b];
    std::vector<int> held(au.locations.size(), -2);  // -2: nothing seen yet
    for (std::size_t x = 0; x < au.transitions.size(); ++x) {
      const Transition& t = au.transitions[x];
      if (t.from == t.to) continue;
      const int k = support_[b][x].helper;
      for (int l : {t.from, t.to}) held[l] = (held[l] == -2 || held[l] == k) ? k : -1;
    }
    for (int& h : held) h = std::max(h, -1);
    return held;
  }

  // For each location b's helper holds it in, the least charge of the rest of a run from there:
  // out of the held locations, or to b's goal location.
  std::vector<long> LeaveHeld(int b, const std::vector<int>& held,
                              const std::vector<long>& charge) const {
    const auto& ts = d_.automata[b].transitions;
    std::vector<long> rest(held.size(), kNever);
    rest[pinned_[b]] = 0;
    for (std::size_t round = 0; round <= held.size(); ++round) {
      bool changed = false;
      for (std::size_t x = 0; x < ts.size(); ++x) {
        const Transition& t = ts[x];
        if (held[t.from] < 0 || t.from == t.to) continue;
        const long r = Add(charge[x], held[t.to] >= 0 ? rest[t.to] : 0);
        if (r < rest[t.from]) rest[t.from] = r, changed = true;
      }
      if (!changed) break;
    }
    return rest;
  }

  // The least goal time (event) the jobs allow on `helpers` helpers.
  static long Spread(const std::vector<Job>& jobs, int helpers) {
    std::set<long> releases;
    for (const Job& j : jobs) releases.insert(j.release);
    long best = 0;
    for (long r : releases) {
      long total = 0;
      std::vector<long> runs;
      for (const Job& j : jobs) {
        if (j.release < r) continue;
        total += j.total;
        for (long n = 0; n < j.runs && runs.size() < 4096; ++n) runs.push_back(j.run);
      }
      std::sort(runs.rbegin(), runs.rend());
      long load = (total + helpers - 1) / helpers;
      // The jK+1 largest runs on K helpers: one helper has j+1 of them, at least the j+1
      // smallest of those.
      for (std::size_t top = helpers + 1, per = 2; top <= runs.size(); top += helpers, ++per) {
        long sum = 0;
        for (std::size_t i = top - per; i < top; ++i) sum += runs[i];
        load = std::max(load, sum);
      }
      if (!runs.empty()) load = std::max(load, runs.front());
      best = std::max(best, Add(r, load));
    }
    return best;
  }

  const Domain& d_;
  const StatePlan& sp_;
  const long tps_;
  std::vector<int> pinned_;
  std::vector<std::vector<std::vector<std::pair<int, int>>>> needs_;  // [a][transition]
  std::vector<std::vector<Support>> support_;                         // [b][transition]
  std::vector<std::set<int>> supporting_;                             // [k]: supporting locations
};

}  // namespace

Workload ComputeWorkload(const Domain& d, const StatePlan& sp, const EarliestTimes* ticks,
                         const EarliestTimes* events) {
  return WorkloadBound(d, sp).Run(ticks, events);
}

}  // namespace ctb
