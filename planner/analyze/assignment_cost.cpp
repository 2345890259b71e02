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

}  // namespace

long AssignmentCostBound(const Domain& d, const StatePlan& sp,
                         const std::vector<std::vector<int>>& visits,
                         const std::vector<long>& own_cost, long known) {
  if (sp.goal.info.IsChange()) return 0;
  const Clauses clauses = DistinctClauses(ToClauses(sp.goal.expr));
  // Without a choice (every clause one fact: robot k rescues person k) the graph bound and the
  // relaxation already count each automaton's own way and the help, shared once.
  if (std::all_of(clauses.begin(), clauses.end(), [](const Clause& c) { return c.size() == 1; }))
    return 0;
  const int na = static_cast<int>(d.automata.size());
  std::map<int, CostWays> ways;  // the automata of S
  for (const Clause& c : clauses)
    for (auto [a, l] : c)
      if (!ways.count(a)) ways.emplace(a, CostWays(d.automata[a], sp.initial[a], visits[a]));
  std::vector<char> in_s(na, 0);
  long base = 0;  // what S costs with nothing asked of it
  for (const auto& [a, w] : ways) {
    in_s[a] = 1;
    base += w.Need(-1);
  }
  // The assignment; with j >= 0, automaton j's costs those through location v.
  auto assign = [&](int j, int v) -> std::optional<long> {
    std::vector<AssignmentRow> rows;
    std::vector<long> from_v;
    long extra = 0, j_none = 0;
    if (j >= 0) {
      from_v = ways.at(j).From(v);
      auto none = ways.at(j).NeedVia(v, from_v, -1);
      if (!none) return std::nullopt;
      j_none = *none;
      extra = j_none - ways.at(j).Need(-1);
    }
    for (const Clause& c : clauses) {
      AssignmentRow row;
      for (auto [a, l] : c) {
        const CostWays& w = ways.at(a);
        if (!w.Reaches(l)) continue;
        if (a != j) {
          row.emplace_back(a, w.Need(l) - w.Need(-1));
        } else if (auto via = w.NeedVia(v, from_v, l)) {
          row.emplace_back(a, *via - j_none);
        }
      }
      rows.push_back(std::move(row));
    }
    auto m = MinCostAssignment(na, rows);
    if (!m) return std::nullopt;
    return base + extra + *m;
  };
  const auto plain = assign(-1, -1);
  if (!plain) return 0;
  long s_part = *plain;
  long others = 0;
  for (int a = 0; a < na; ++a)
    if (!in_s[a]) others += own_cost[a];
  if (auto relaxed = RelaxedCostOfOthers(d, sp, in_s)) others = std::max(others, *relaxed);
  long edges = 0;
  for (const Clause& c : clauses) edges += static_cast<long>(c.size());
  // Help: facts of S that the other automata's guards read; their union, and each automaton's.
  std::set<LocationAtom> all_help;
  std::vector<std::vector<LocationAtom>> landmarks(1);
  for (int b = 0; b < na; ++b) {
    if (in_s[b]) continue;
    std::set<LocationAtom> facts;
    for (const Transition& t : d.automata[b].transitions)
      for (const Clause& c : ToClauses(t.guard))
        for (const LocationAtom& f : c)
          if (in_s[f.first]) facts.insert(f);
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
        const CostWays& w = ways.at(j);
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
        if (auto x = assign(j, v)) least = least ? std::min(*least, *x) : *x;
      if (least) s_part = std::max(s_part, *least);
    }
  }
  return s_part + others;
}

}  // namespace ctb
