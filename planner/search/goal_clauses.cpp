#include "planner/search/goal_clauses.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <unordered_map>

namespace ctb::search {

bool ChooseFacts(const Clauses& clauses, bool one_stage,
                 const std::function<double(const LocationAtom&)>& cost,
                 std::vector<LocationAtom>& out) {
  const bool plain = std::all_of(clauses.begin(), clauses.end(),
                                 [](const Clause& c) { return c.size() == 1; });
  if (plain) {  // a conjunction of atoms: nothing to choose
    for (const Clause& c : clauses)
      if (std::isinf(cost(c[0]))) return false;
    const auto start = static_cast<std::ptrdiff_t>(out.size());
    for (const Clause& c : clauses)
      if (std::find(out.begin() + start, out.end(), c[0]) == out.end()) out.push_back(c[0]);
    return true;
  }
  struct Pair {
    double cost;
    int clause;
    LocationAtom atom;
  };
  std::vector<Pair> pairs;
  std::map<LocationAtom, std::vector<int>> clauses_of;
  for (std::size_t i = 0; i < clauses.size(); ++i) {
    bool reachable = false;
    for (const LocationAtom& t : clauses[i]) {
      const double c = cost(t);
      if (std::isinf(c)) continue;
      reachable = true;
      pairs.push_back({c, static_cast<int>(i), t});
      clauses_of[t].push_back(static_cast<int>(i));
    }
    if (!reachable) return false;
  }
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const Pair& a, const Pair& b) { return a.cost < b.cost; });
  // The fact each clause gets, emitted in clause order: for a plain conjunction the relaxed plan
  // then sums its costs in the same order as the conjunction's atoms (ties in the search's open
  // list compare sums exactly).
  std::vector<const LocationAtom*> got(clauses.size(), nullptr);
  std::unordered_map<int, int> at;  // automaton -> the location chosen for it
  for (const Pair& p : pairs) {
    if (got[p.clause]) continue;
    auto it = at.find(p.atom.first);
    if (one_stage && it != at.end() && it->second != p.atom.second) continue;
    at[p.atom.first] = p.atom.second;
    for (int c : clauses_of[p.atom])  // what this fact already achieves
      if (!got[c]) got[c] = &p.atom;
  }
  for (const Pair& p : pairs)  // nothing consistent left: the cheapest fact
    if (!got[p.clause]) got[p.clause] = &p.atom;
  std::set<LocationAtom> emitted;
  for (const LocationAtom* t : got)
    if (emitted.insert(*t).second) out.push_back(*t);
  return true;
}

}  // namespace ctb::search
