#include "planner/network/stn.h"

#include <algorithm>

namespace ctb::network::internal {

std::vector<StnEdge> DistanceEdges(const Network& net) {
  std::vector<StnEdge> edges;
  edges.reserve(net.links.size() * 2);
  for (std::size_t i = 0; i < net.links.size(); ++i) {
    const Link& l = net.links[i];
    const int li = static_cast<int>(i);
    if (l.ub) edges.push_back({l.from, l.to, *l.ub, li});
    edges.push_back({l.to, l.from, -l.lb, li});
  }
  return edges;
}

namespace {

// Goldberg & Radzik (1993), "A heuristic improvement of the Bellman-Ford algorithm": each pass
// sorts the nodes reachable from the changed ones over arcs of non-positive reduced cost
// topologically (a depth-first search), then scans them in that order. A plan's chain of lower
// bounds, which costs FIFO Bellman-Ford (SPFA) n^2/2 relaxations, settles in one pass. A cycle of
// such arcs with a negative arc is a negative cycle, which the search reports.
class GoldbergRadzik {
 public:
  GoldbergRadzik(int n, const std::vector<StnEdge>& edges)
      : n_(static_cast<std::size_t>(n)),
        edges_(edges),
        out_(n_),
        dist_(n_, 0),
        pos_(n_, 0),
        pred_(n_, -1) {
    for (std::size_t i = 0; i < edges.size(); ++i) {
      out_[static_cast<std::size_t>(edges[i].from)].push_back(static_cast<int>(i));
    }
  }

  // False with the cycle's edges when there is a negative cycle.
  bool Run(std::vector<int>* cycle) {
    std::vector<int> changed(n_);
    for (std::size_t v = 0; v < n_; ++v) changed[v] = static_cast<int>(v);
    std::vector<int> state(n_, 0);  // per pass: 0 unseen, 1 on the DFS stack, 2 done
    std::vector<int> order;
    for (std::size_t pass = 0; !changed.empty(); ++pass) {
      if (pass > n_ + 1) return Fail(cycle, {});  // beyond Bellman-Ford's bound
      std::fill(state.begin(), state.end(), 0);
      order.clear();
      for (int s : changed) {
        if (state[static_cast<std::size_t>(s)] == 0 && HasNegativeArc(s) &&
            !Dfs(s, state, order, cycle)) {
          return false;
        }
      }
      changed.clear();
      for (auto it = order.rbegin(); it != order.rend(); ++it) Scan(*it, changed);
      // A zero-cost cycle can hide a negative one from the search (a node is entered once); a cycle
      // of the predecessor graph is always negative.
      if (!changed.empty()) {
        std::vector<int> c = PredecessorCycle();
        if (!c.empty()) return Fail(cycle, std::move(c));
      }
    }
    return true;
  }

  std::vector<Ticks>& dist() { return dist_; }

 private:
  Ticks Reduced(const StnEdge& e) const {
    return dist_[static_cast<std::size_t>(e.from)] + e.w - dist_[static_cast<std::size_t>(e.to)];
  }

  bool HasNegativeArc(int u) const {
    for (int ei : out_[static_cast<std::size_t>(u)]) {
      if (Reduced(edges_[static_cast<std::size_t>(ei)]) < 0) return true;
    }
    return false;
  }

  // Iterative depth-first search over arcs of non-positive reduced cost; post-order into `order`. A
  // cycle of such arcs is negative unless all its arcs cost 0 (then it is skipped): each frame
  // keeps the reduced cost from the root, so the cycle's cost is a difference.
  bool Dfs(int root, std::vector<int>& state, std::vector<int>& order, std::vector<int>* cycle) {
    struct Frame {
      int node;
      std::size_t next;
      int via;     // the edge that reached the node, -1 at the root
      Ticks cost;  // reduced cost from the root
    };
    std::vector<Frame> stack{{root, 0, -1, 0}};
    state[static_cast<std::size_t>(root)] = 1;
    pos_[static_cast<std::size_t>(root)] = 0;
    while (!stack.empty()) {
      Frame& f = stack.back();
      const std::vector<int>& out = out_[static_cast<std::size_t>(f.node)];
      if (f.next == out.size()) {
        state[static_cast<std::size_t>(f.node)] = 2;
        order.push_back(f.node);
        stack.pop_back();
        continue;
      }
      const int ei = out[f.next++];
      const StnEdge& e = edges_[static_cast<std::size_t>(ei)];
      const Ticks r = Reduced(e);
      if (r > 0) continue;
      const std::size_t to = static_cast<std::size_t>(e.to);
      if (state[to] == 0) {
        state[to] = 1;
        pos_[to] = stack.size();
        stack.push_back({e.to, 0, ei, f.cost + r});
      } else if (state[to] == 1 && f.cost + r - stack[pos_[to]].cost < 0) {
        std::vector<int> c;  // a negative cycle: from e.to on the stack, then e
        for (std::size_t i = pos_[to] + 1; i < stack.size(); ++i) c.push_back(stack[i].via);
        c.push_back(ei);
        return Fail(cycle, std::move(c));
      }
    }
    return true;
  }

  void Scan(int u, std::vector<int>& changed) {
    const Ticks du = dist_[static_cast<std::size_t>(u)];
    for (int ei : out_[static_cast<std::size_t>(u)]) {
      const StnEdge& e = edges_[static_cast<std::size_t>(ei)];
      Ticks& dv = dist_[static_cast<std::size_t>(e.to)];
      if (du + e.w < dv) {
        dv = du + e.w;
        pred_[static_cast<std::size_t>(e.to)] = ei;
        changed.push_back(e.to);
      }
    }
  }

  // A cycle of the predecessor graph (edge indices in order), or empty.
  std::vector<int> PredecessorCycle() const {
    std::vector<int> mark(n_, -1);  // the walk that visited the node
    for (std::size_t s = 0; s < n_; ++s) {
      std::size_t v = s;
      while (mark[v] < 0) {
        mark[v] = static_cast<int>(s);
        const int e = pred_[v];
        if (e < 0) break;
        v = static_cast<std::size_t>(edges_[static_cast<std::size_t>(e)].from);
      }
      if (mark[v] != static_cast<int>(s) || pred_[v] < 0) continue;
      std::vector<int> c;  // v is on a cycle met by this walk
      std::size_t u = v;
      do {
        c.push_back(pred_[u]);
        u = static_cast<std::size_t>(edges_[static_cast<std::size_t>(pred_[u])].from);
      } while (u != v);
      std::reverse(c.begin(), c.end());
      return c;
    }
    return {};
  }

  static bool Fail(std::vector<int>* cycle, std::vector<int> c) {
    if (cycle) *cycle = std::move(c);
    return false;
  }

  std::size_t n_;
  const std::vector<StnEdge>& edges_;
  std::vector<std::vector<int>> out_;
  std::vector<Ticks> dist_;
  std::vector<std::size_t> pos_;  // a node's index on the DFS stack while it is there
  std::vector<int> pred_;         // the edge that last lowered a node's distance, or -1
};

}  // namespace

bool BellmanFord(int n, const std::vector<StnEdge>& edges, std::vector<Ticks>* potential,
                 std::vector<int>* cycle) {
  if (n <= 0) return true;
  GoldbergRadzik gr(n, edges);
  if (!gr.Run(cycle)) return false;
  if (potential) *potential = std::move(gr.dist());
  return true;
}

}  // namespace ctb::network::internal
