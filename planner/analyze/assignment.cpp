#include "planner/analyze/assignment.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <map>
#include <queue>

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

std::optional<long> MinCostAssignment(int columns, const std::vector<AssignmentRow>& rows) {
  constexpr long kFar = std::numeric_limits<long>::max() / 4;
  const int nr = static_cast<int>(rows.size());
  // Each row's choices with one (the least) cost per column. Nodes: rows 0..nr-1, then columns.
  std::vector<AssignmentRow> choice(rows.size());
  for (int r = 0; r < nr; ++r) {
    std::map<int, long> least;
    for (auto [c, w] : rows[r]) {
      auto [it, fresh] = least.emplace(c, w);
      if (!fresh) it->second = std::min(it->second, w);
    }
    choice[r].assign(least.begin(), least.end());
  }
  auto cost_of = [&](int r, int c) {
    return std::lower_bound(choice[r].begin(), choice[r].end(), std::make_pair(c, 0L))->second;
  };
  std::vector<long> pot(nr + columns, 0), dist(nr + columns, kFar);
  std::vector<int> row_of(columns, -1), column_of(nr, -1), via(columns, -1);
  std::vector<char> done(nr + columns, 0);
  std::vector<int> touched;
  using Item = std::pair<long, int>;  // (distance, node)
  for (int s = 0; s < nr; ++s) {
    if (choice[s].empty()) return std::nullopt;
    // Every reduced cost w + pot[row] - pot[column] stays >= 0, the new row's too.
    pot[s] = std::numeric_limits<long>::min();
    for (auto [c, w] : choice[s]) pot[s] = std::max(pot[s], pot[nr + c] - w);
    for (int v : touched) {
      dist[v] = kFar;
      done[v] = 0;
    }
    touched.assign(1, s);
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    dist[s] = 0;
    heap.push({0, s});
    int free_column = -1;
    while (!heap.empty()) {
      auto [du, u] = heap.top();
      heap.pop();
      if (done[u] || du > dist[u]) continue;
      done[u] = 1;
      auto reach = [&](int v, long dv) {
        if (dv >= dist[v]) return;
        if (dist[v] == kFar) touched.push_back(v);
        dist[v] = dv;
        heap.push({dv, v});
      };
      if (u < nr) {  // a row: to its other columns
        for (auto [c, w] : choice[u]) {
          if (c == column_of[u]) continue;
          const long dv = du + w + pot[u] - pot[nr + c];
          if (dv < dist[nr + c]) via[c] = u;
          reach(nr + c, dv);
        }
      } else {  // a column: free ends the search; taken leads back to its row
        const int c = u - nr;
        if (row_of[c] < 0) {
          free_column = c;
          break;
        }
        const int r = row_of[c];
        reach(r, du - cost_of(r, c) + pot[u] - pot[r]);
      }
    }
    if (free_column < 0) return std::nullopt;
    const long far = dist[nr + free_column];
    for (int v : touched)
      if (done[v] && dist[v] < far) pot[v] -= far - dist[v];
    for (int c = free_column;;) {  // flip the path
      const int r = via[c];
      const int next = column_of[r];
      column_of[r] = c;
      row_of[c] = r;
      if (r == s) break;
      c = next;
    }
  }
  long total = 0;
  for (int r = 0; r < nr; ++r) total += cost_of(r, column_of[r]);
  return total;
}

}  // namespace ctb
