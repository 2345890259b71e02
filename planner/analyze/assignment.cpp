#include "planner/analyze/assignment.h"

#include <algorithm>
#include <map>

namespace ctb {

namespace {

// Clauses to automata at one time T: which automata can serve each clause, and how many clauses
// each automaton can serve at most.
class Flow {
 public:
  Flow(const Clauses& clauses, const std::vector<std::vector<long>>& arrival, long t) {
    std::map<int, int> index;  // automaton -> its slot in cap_
    std::map<LocationAtom, int> uses;
    for (const Clause& c : clauses) {
      std::vector<int> mine;
      for (const LocationAtom& f : c) {
        if (arrival[f.first][f.second] > t) continue;
        auto [it, fresh] = index.emplace(f.first, static_cast<int>(cap_.size()));
        if (fresh) cap_.push_back(0);
        if (std::find(mine.begin(), mine.end(), it->second) == mine.end())
          mine.push_back(it->second);
        cap_[it->second] = std::max(cap_[it->second], ++uses[f]);
      }
      serve_.push_back(std::move(mine));
    }
  }

  // True when every clause gets an automaton within the capacities (augmenting paths).
  bool Feasible() {
    load_.assign(cap_.size(), {});
    for (std::size_t c = 0; c < serve_.size(); ++c) {
      visited_.assign(cap_.size(), 0);
      if (!Augment(static_cast<int>(c))) return false;
    }
    return true;
  }

 private:
  bool Augment(int c) {
    for (int a : serve_[c]) {
      if (visited_[a]) continue;
      visited_[a] = 1;
      if (static_cast<int>(load_[a].size()) < cap_[a]) {
        load_[a].push_back(c);
        return true;
      }
      for (int& other : load_[a])
        if (Augment(other)) {
          other = c;
          return true;
        }
    }
    return false;
  }

  std::vector<std::vector<int>> serve_;  // clause -> automata (slots)
  std::vector<int> cap_;
  std::vector<std::vector<int>> load_;  // automaton -> the clauses it serves
  std::vector<char> visited_;
};

}  // namespace

long AssignmentBound(const Clauses& clauses, const std::vector<std::vector<long>>& arrival,
                     long never) {
  std::vector<long> times;
  for (const Clause& c : clauses)
    for (const LocationAtom& f : c)
      if (arrival[f.first][f.second] < never) times.push_back(arrival[f.first][f.second]);
  if (clauses.empty() || times.empty()) return 0;
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  if (!Flow(clauses, arrival, times.back()).Feasible()) return 0;
  std::size_t lo = 0, hi = times.size() - 1;  // feasible at times[hi]
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (Flow(clauses, arrival, times[mid]).Feasible())
      hi = mid;
    else
      lo = mid + 1;
  }
  return times[hi];
}

}  // namespace ctb
