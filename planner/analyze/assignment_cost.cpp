#include "planner/analyze/assignment_cost.h"

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <utility>

#include "planner/analyze/assignment.h"
#include "planner/analyze/clauses.h"
#include "planner/analyze/earliest.h"  // ShortestFrom
#include "planner/analyze/relaxed_cost.h"

namespace ctb {

namespace {

constexpr long kNoWay = EarliestTimes::kNever;
// The help landmark costs one assignment per fact of it: beyond this many (facts x edges) it is
// not tried (about 20 robots when every robot may rescue every person, 100 when each has its
// own; the assignment without it still holds).
constexpr long kMaxLandmarkWork = 20'000;
// Landmarks tried: the union of the facts the other automata's guards read, and those of each of
// the first few other automata alone.
constexpr std::size_t kMaxLandmarkTries = 8;

// One automaton of S: its cheapest ways by cost (guards ignored) from its initial location and
// from each location it must visit, and from the locations of the landmark tried.
class CostWays {
 public:
  CostWays(const Automaton& au, int init, const std::vector<int>& visits)
      : au_(au), visits_(visits), from_init_(From(init)) {
    for (int v : visits_) from_visit_.push_back(From(v));
  }

  bool Reaches(int l) const { return from_init_[l] < kNoWay; }

  // need(l): the cheapest way through every visit to l (l < 0: ending anywhere). A visit it
  // cannot reach is not this bound's business (the static checks): it adds nothing.
  long Need(int l) const {
    long need = l >= 0 && Reaches(l) ? from_init_[l] : 0;
    for (std::size_t i = 0; i < visits_.size(); ++i) {
      const long first = from_init_[visits_[i]];
      if (first >= kNoWay) continue;
      const long second = l >= 0 ? from_visit_[i][l] : 0;
      need = std::max(need, second < kNoWay ? first + second : first);
    }
    return need;
  }

  // The same with v visited too (`from_v`: From(v)): nullopt when no way enters v and then
  // reaches l.
  std::optional<long> NeedVia(int v, const std::vector<long>& from_v, int l) const {
    const long first = from_init_[v];
    if (first >= kNoWay) return std::nullopt;
    if (l < 0) return std::max(Need(-1), first);
    if (from_v[l] >= kNoWay) return std::nullopt;
    return std::max(Need(l), first + from_v[l]);
  }

  std::vector<long> From(int l) const {
    return ShortestFrom(au_, l, [](const Transition& t) { return t.cost; });
  }

 private:
  const Automaton& au_;
  const std::vector<int>& visits_;
  std::vector<long> from_init_;
  std::vector<std::vector<long>> from_visit_;
};

// Clauses no two of which share a fact, the shorter first (each clause then needs an automaton of
// its own). Empty when some clause is false (no plan: nothing claimed).
Clauses DistinctClauses(Clauses all) {
  std::stable_sort(all.begin(), all.end(),
                   [](const Clause& x, const Clause& y) { return x.size() < y.size(); });
  Clauses kept;
  std::set<LocationAtom> used;
  for (Clause& c : all) {
    if (c.empty()) return {};
    if (std::any_of(c.begin(), c.end(), [&](const LocationAtom& f) { return used.count(f) > 0; }))
      continue;
    used.insert(c.begin(), c.end());
    kept.push_back(std::move(c));
  }
  return kept;
}

// The goal's distinct clauses served by the automata of S (the automata they name), at their own
// costs: what AssignmentCostBound and ReachWithinBudget share.
class ServedClauses {
 public:
  ServedClauses(const Domain& d, const StatePlan& sp, const std::vector<std::vector<int>>& visits,
                const std::vector<long>& own_cost)
      : na_(static_cast<int>(d.automata.size())), in_s_(na_, 0) {
    if (sp.goal.info.IsChange()) return;
    clauses_ = DistinctClauses(ToClauses(sp.goal.expr));
    // Without a choice (every clause one fact: robot k rescues person k) the graph bound and the
    // relaxation already count each automaton's own way and the help, shared once.
    if (std::all_of(clauses_.begin(), clauses_.end(), [](const Clause& c) { return c.size() == 1; })) {
      clauses_.clear();
      return;
    }
    for (const Clause& c : clauses_)
      for (auto [a, l] : c)
        if (!ways_.count(a)) ways_.emplace(a, CostWays(d.automata[a], sp.initial[a], visits[a]));
    for (const auto& [a, w] : ways_) {
      in_s_[a] = 1;
      base_ += w.Need(-1);
    }
    for (int a = 0; a < na_; ++a)
      if (!in_s_[a]) others_ += own_cost[a];
    if (auto relaxed = RelaxedCostOfOthers(d, sp, in_s_)) others_ = std::max(others_, *relaxed);
  }

  bool Claims() const { return !clauses_.empty(); }
  const Clauses& clauses() const { return clauses_; }
  const std::map<int, CostWays>& ways() const { return ways_; }
  bool InS(int a) const { return in_s_[a] != 0; }
  // A bound on what the automata outside S cost in every plan.
  long Others() const { return others_; }

  // What S costs at least; with j >= 0, in plans where automaton j enters location v; with
  // `arrival`, in plans whose goal stage comes by time t (an automaton serves a clause in a
  // location only if it can arrive there by then). nullopt: no assignment (then no such plan).
  std::optional<long> Assign(int j, int v, const std::vector<std::vector<long>>* arrival = nullptr,
                             long t = 0) const {
    std::vector<AssignmentRow> rows;
    std::vector<long> from_v;
    long extra = 0, j_none = 0;
    if (j >= 0) {
      from_v = ways_.at(j).From(v);
      auto none = ways_.at(j).NeedVia(v, from_v, -1);
      if (!none) return std::nullopt;
      j_none = *none;
      extra = j_none - ways_.at(j).Need(-1);
    }
    for (const Clause& c : clauses_) {
      AssignmentRow row;
      for (auto [a, l] : c) {
        const CostWays& w = ways_.at(a);
        if (!w.Reaches(l) || (arrival && (*arrival)[a][l] > t)) continue;
        if (a != j) {
          row.emplace_back(a, w.Need(l) - w.Need(-1));
        } else if (auto via = w.NeedVia(v, from_v, l)) {
          row.emplace_back(a, *via - j_none);
        }
      }
      rows.push_back(std::move(row));
    }
    auto m = MinCostAssignment(na_, rows);
    if (!m) return std::nullopt;
    return base_ + extra + *m;
  }

 private:
  int na_;
  Clauses clauses_;
  std::map<int, CostWays> ways_;
  std::vector<char> in_s_;
  long base_ = 0;    // what S costs with nothing asked of it
  long others_ = 0;
};

}  // namespace

long AssignmentCostBound(const Domain& d, const StatePlan& sp,
                         const std::vector<std::vector<int>>& visits,
                         const std::vector<long>& own_cost, long known) {
  const ServedClauses served(d, sp, visits, own_cost);
  if (!served.Claims()) return 0;
  const Clauses& clauses = served.clauses();
  const int na = static_cast<int>(d.automata.size());
  const auto plain = served.Assign(-1, -1);
  if (!plain) return 0;
  long s_part = *plain;
  const long others = served.Others();
  long edges = 0;
  for (const Clause& c : clauses) edges += static_cast<long>(c.size());
  // Help: facts of S that the other automata's guards read; their union, and each automaton's.
  std::set<LocationAtom> all_help;
  std::vector<std::vector<LocationAtom>> landmarks(1);
  for (int b = 0; b < na; ++b) {
    if (served.InS(b)) continue;
    std::set<LocationAtom> facts;
    for (const Transition& t : d.automata[b].transitions)
      for (const Clause& c : ToClauses(t.guard))
        for (const LocationAtom& f : c)
          if (served.InS(f.first)) facts.insert(f);
    if (facts.empty()) continue;
    all_help.insert(facts.begin(), facts.end());
    if (landmarks.size() < kMaxLandmarkTries) landmarks.emplace_back(facts.begin(), facts.end());
  }
  landmarks.front().assign(all_help.begin(), all_help.end());
  if (landmarks.size() == 2) landmarks.pop_back();  // one automaton's facts: the union itself
  // One that an automaton starts in is met at no cost: then the union is no help.
  const bool starts_in_one = std::any_of(all_help.begin(), all_help.end(), [&](const LocationAtom& f) {
    return sp.initial[f.first] == f.second;
  });
  if (!starts_in_one && !all_help.empty()) {
    for (const auto& facts : landmarks) {
      if (static_cast<long>(facts.size()) * (edges + 1) > kMaxLandmarkWork) continue;
      // The most a fact can add: its automaton's detour, asked for nothing or at its dearest
      // location. When even that stays within `known`, the landmark cannot raise the bound.
      long most = 0;
      for (auto [j, v] : facts) {
        const CostWays& w = served.ways().at(j);
        const std::vector<long> from_v = w.From(v);
        if (auto x = w.NeedVia(v, from_v, -1)) most = std::max(most, *x - w.Need(-1));
        for (const Clause& c : clauses)
          for (auto [a, l] : c)
            if (a == j && w.Reaches(l))
              if (auto x = w.NeedVia(v, from_v, l)) most = std::max(most, *x - w.Need(l));
      }
      if (*plain + most + others <= known) continue;
      if (RelaxedReachableAvoiding(d, sp, facts)) continue;
      std::optional<long> least;
      for (auto [j, v] : facts)
        if (auto x = served.Assign(j, v)) least = least ? std::min(*least, *x) : *x;
      if (least) s_part = std::max(s_part, *least);
    }
  }
  return s_part + others;
}

namespace {

// Each automaton alone: locations where its cheapest way through them plus the others' own ways
// exceed the budget. False when the work cap stopped it (the list so far still holds).
bool AddCostlyAlone(const Domain& d, const StatePlan& sp, const std::vector<std::vector<int>>& visits,
                    const std::vector<long>& own_cost, const std::vector<int>& final_loc, long budget,
                    long& work, std::vector<std::pair<int, int>>& out) {
  long all_own = 0;
  for (long c : own_cost) all_own += c;
  for (int a = 0; a < static_cast<int>(d.automata.size()); ++a) {
    const CostWays w(d.automata[a], sp.initial[a], visits[a]);
    const int nl = static_cast<int>(d.automata[a].locations.size());
    work += nl;
    if (work > kMaxLandmarkWork) return false;
    for (int v = 0; v < nl; ++v) {
      if (v == sp.initial[a] || !w.Reaches(v)) continue;
      const auto via = w.NeedVia(v, w.From(v), final_loc[a]);
      if (!via || all_own - own_cost[a] + std::max(own_cost[a], *via) > budget) out.emplace_back(a, v);
    }
  }
  return true;
}

// The automata of S under the assignment: locations where the assignment with that automaton's
// costs through them, plus the others' part, exceeds the budget.
void AddCostlyServed(const Domain& d, const StatePlan& sp, const ServedClauses& served, long budget,
                     long& work, std::vector<std::pair<int, int>>& out) {
  for (const auto& [j, w] : served.ways()) {
    const int nl = static_cast<int>(d.automata[j].locations.size());
    work += nl * static_cast<long>(served.clauses().size() + 1);
    if (work > kMaxLandmarkWork) return;
    for (int v = 0; v < nl; ++v) {
      if (v == sp.initial[j] || !w.Reaches(v)) continue;
      const auto via = served.Assign(j, v);
      if (!via || *via + served.Others() > budget) out.emplace_back(j, v);
    }
  }
}

// The least time by which automata that can arrive serve the clauses within the budget; 0 when
// none does (or the work cap).
long Bottleneck(const ServedClauses& served, const std::vector<std::vector<long>>& arrival, long budget) {
  std::vector<long> times;
  for (const Clause& c : served.clauses())
    for (auto [a, l] : c)
      if (served.ways().at(a).Reaches(l) && arrival[a][l] < EarliestTimes::kNever)
        times.push_back(arrival[a][l]);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  if (static_cast<long>(times.size() * served.clauses().size()) > kMaxLandmarkWork) return 0;
  for (long t : times) {
    const auto s_part = served.Assign(-1, -1, &arrival, t);
    if (s_part && *s_part + served.Others() <= budget) return t;
  }
  return 0;
}

}  // namespace

WithinBudget ReachWithinBudget(const Domain& d, const StatePlan& sp,
                               const std::vector<std::vector<int>>& visits,
                               const std::vector<long>& own_cost, const std::vector<int>& final_loc,
                               const std::vector<std::vector<long>>* arrival, long budget) {
  WithinBudget r;
  long work = 0;
  const bool alone_done = AddCostlyAlone(d, sp, visits, own_cost, final_loc, budget, work, r.costly);
  const ServedClauses served(d, sp, visits, own_cost);  // the others' LM-cut: built once
  if (served.Claims()) {
    if (alone_done) AddCostlyServed(d, sp, served, budget, work, r.costly);
    if (arrival) r.bottleneck = Bottleneck(served, *arrival, budget);
  }
  std::sort(r.costly.begin(), r.costly.end());
  r.costly.erase(std::unique(r.costly.begin(), r.costly.end()), r.costly.end());
  return r;
}

}  // namespace ctb
