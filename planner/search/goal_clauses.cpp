#include "planner/search/goal_clauses.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace ctb::search {

bool ChooseFacts(const Clauses& clauses, bool one_stage,
                 const std::function<double(const LocationAtom&)>& cost,
                 std::vector<LocationAtom>& out) {
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
  std::vector<char> done(clauses.size(), 0);
  std::unordered_map<int, int> at;  // automaton -> the location chosen for it
  for (const Pair& p : pairs) {
    if (done[p.clause]) continue;
    auto it = at.find(p.atom.first);
    if (one_stage && it != at.end() && it->second != p.atom.second) continue;
    at[p.atom.first] = p.atom.second;
    out.push_back(p.atom);
    for (int c : clauses_of[p.atom]) done[c] = 1;  // what this fact already achieves
  }
  for (const Pair& p : pairs)  // nothing consistent left: the cheapest fact
    if (!done[p.clause]) {
      done[p.clause] = 1;
      out.push_back(p.atom);
    }
  return true;
}

}  // namespace ctb::search
