// Dynamic controllability by iterated moat reductions (Morris 2006, "A structural characterization
// of temporal dynamic controllability", CP 2006), with instantaneous reaction. A lower-case edge A
// --c:x--> C is usable in a path only when a *moat* follows it: a path Q from C of negative length
// whose proper prefixes are non-negative, made of ordinary edges and at most one upper-case edge
// (the last, with a label other than C). The pair reduces to A --x+|Q|--> W (ordinary; upper-case
// labelled B when Q ends with B's edge, unless x+|Q| >= -lb(B): label removal). The network is
// dynamically controllable iff, once no reduction adds or tightens an edge, the AllMax graph
// (ordinary and upper-case edges, labels ignored) has no negative cycle.
//
// Each round: Bellman-Ford (Goldberg-Radzik) on the AllMax graph gives a potential, or a negative
// cycle (not controllable); then one Dijkstra per contingent link, forward from C over reduced
// costs, settles every node whose prefix is non-negative and stops at the first negative one (the
// moat's end). Derived edges join the graph after the round. Morris shows K + 1 rounds suffice (K
// contingent links); in practice two or three. O(rounds * (BF + K (m + n log n))).
//
// Conflicts: every derived edge keeps its lower-case edge and moat (path nodes shared within a
// search), so a negative cycle expands to the input links it came from (as Bhargava et al. do for
// Morris 2014's edges).
#include <algorithm>
#include <functional>
#include <map>
#include <queue>
#include <set>
#include <tuple>

#include "planner/network/dynamic_internal.h"
#include "planner/network/stn.h"

namespace ctb::network::internal {
namespace {

enum class Kind { kOrdinary, kLower, kUpper };

struct Edge {
  int from = 0;
  int to = 0;
  Ticks w = 0;
  Kind kind = Kind::kOrdinary;
  int label = -1;  // lower/upper: the contingent link
  int link = -1;   // input edges: the link; derived: -1
  int lower = -1;  // derived: the lower-case edge reduced
  int path = -1;   // derived: the moat (path node of its first edge)
  bool dead = false;
};

struct PathNode {
  int edge = 0;
  int next = -1;  // towards the moat's end
};

// Per node of a moat search: the shortest path from C that ends there with an ordinary edge (paths
// that end with a wait are moat ends, derived at once).
struct Slot {
  Ticks dist = 0;
  int edge = -1;  // the last edge of the path
  int prev = -1;  // the node before it, -1 at C
  unsigned stamp = 0;
  bool settled = false;
};

class Moats {
 public:
  explicit Moats(const Network& net)
      : net_(net), n_(static_cast<int>(net.points.size())), out_(Size(n_)), slots_(Size(n_)) {
    for (std::size_t i = 0; i < net.links.size(); ++i) AddLink(net.links[i], static_cast<int>(i));
  }

  bool Run(std::vector<int>* conflict) {
    const std::size_t max_rounds = 4 * contingent_.size() + 8;
    for (std::size_t round = 0; round < max_rounds; ++round) {
      if (!Potential(conflict)) return false;
      for (int lower : contingent_) {
        if (!Search(lower, conflict)) return false;
      }
      if (!Commit()) return Potential(conflict);
    }
    return Potential(conflict);
  }

 private:
  static std::size_t Size(int n) { return static_cast<std::size_t>(n); }
  const Edge& E(int i) const { return edges_[static_cast<std::size_t>(i)]; }

  int AddEdge(const Edge& e) {
    out_[Size(e.from)].push_back(static_cast<int>(edges_.size()));
    edges_.push_back(e);
    return static_cast<int>(edges_.size()) - 1;
  }

  void AddLink(const Link& l, int li) {
    if (l.ub) AddEdge({l.from, l.to, *l.ub, Kind::kOrdinary, -1, li});
    AddEdge({l.to, l.from, -l.lb, Kind::kOrdinary, -1, li});
    if (l.contingent) {
      contingent_.push_back(AddEdge({l.from, l.to, l.lb, Kind::kLower, li, li}));
      AddEdge({l.to, l.from, -*l.ub, Kind::kUpper, li, li});
    }
  }

  // Bellman-Ford on the AllMax graph; false (with the conflict) on a negative cycle.
  bool Potential(std::vector<int>* conflict) {
    std::vector<StnEdge> stn;
    std::vector<int> ids;
    for (std::size_t i = 0; i < edges_.size(); ++i) {
      const Edge& e = edges_[i];
      if (e.dead || e.kind == Kind::kLower) continue;
      stn.push_back({e.from, e.to, e.w, static_cast<int>(i)});
    }
    std::vector<int> cycle;
    if (BellmanFord(n_, stn, &f_, &cycle)) return true;
    for (int c : cycle) ids.push_back(stn[static_cast<std::size_t>(c)].link);
    Explain(ids, conflict);
    return false;
  }

  // The input links behind a set of edges.
  void Explain(std::vector<int> stack, std::vector<int>* conflict) const {
    if (!conflict) return;
    std::set<int> links;
    std::vector<char> seen(edges_.size(), 0);
    while (!stack.empty()) {
      const int ei = stack.back();
      stack.pop_back();
      if (ei < 0 || seen[static_cast<std::size_t>(ei)]) continue;
      seen[static_cast<std::size_t>(ei)] = 1;
      const Edge& e = E(ei);
      if (e.link >= 0) {
        links.insert(e.link);
        continue;
      }
      stack.push_back(e.lower);
      for (int p = e.path; p >= 0; p = paths_[static_cast<std::size_t>(p)].next) {
        stack.push_back(paths_[static_cast<std::size_t>(p)].edge);
      }
    }
    conflict->assign(links.begin(), links.end());
  }

  bool Search(int lower, std::vector<int>* conflict);
  bool Visit(int u, int lower_edge, std::vector<int>* conflict);
  bool Derive(int lower_edge, int node, int last, Ticks dist, std::vector<int>* conflict);
  int Materialise(int node, int last);
  bool Commit();

  const Network& net_;
  int n_;
  std::vector<std::vector<int>> out_;
  std::vector<Edge> edges_;
  std::vector<int> contingent_;  // the lower-case edges
  std::vector<PathNode> paths_;
  std::vector<Ticks> f_;
  std::vector<Slot> slots_;
  unsigned stamp_ = 0;
  std::priority_queue<std::pair<Ticks, int>, std::vector<std::pair<Ticks, int>>, std::greater<>>
      queue_;
  std::vector<Edge> pending_;
  std::map<std::tuple<int, int, int>, std::size_t> pending_index_;
  // The live derived edge per (from, to, label + 1).
  std::map<std::tuple<int, int, int>, int> derived_;
};

// Materialises a moat as path nodes from C's first edge: the slot chain of `node`, then `last` (an
// upper-case edge) when given; returns the first node's id.
int Moats::Materialise(int node, int last) {
  int next = -1;
  if (last >= 0) {
    paths_.push_back({last, -1});
    next = static_cast<int>(paths_.size()) - 1;
  }
  for (int k = node; k >= 0 && slots_[Size(k)].edge >= 0; k = slots_[Size(k)].prev) {
    paths_.push_back({slots_[Size(k)].edge, next});
    next = static_cast<int>(paths_.size()) - 1;
  }
  return next;
}

bool Moats::Search(int lower, std::vector<int>* conflict) {
  const int c = E(lower).to;
  ++stamp_;
  queue_ = {};
  slots_[Size(c)] = {0, -1, -1, stamp_, false};
  queue_.push({0, c});
  while (!queue_.empty()) {
    const auto [r, u] = queue_.top();
    queue_.pop();
    Slot& s = slots_[Size(u)];
    if (s.settled || r != s.dist + f_[Size(c)] - f_[Size(u)]) continue;
    s.settled = true;
    if (u != c && s.dist < 0) {  // the moat ends here
      if (!Derive(lower, u, -1, s.dist, conflict)) return false;
    } else if (!Visit(u, lower, conflict)) {
      return false;
    }
  }
  return true;
}

// Relaxes the out-edges of a node with a non-negative prefix. An upper-case edge after an ordinary
// path is a wait on its label (upper-case rule), which ends the moat when negative; it is ordinary
// again when the sum is at least -lb of that label (label removal).
bool Moats::Visit(int u, int lower_edge, std::vector<int>* conflict) {
  const Ticks d = slots_[Size(u)].dist;
  const int c = E(lower_edge).to;
  for (int ei : out_[Size(u)]) {
    const Edge& e = E(ei);
    if (e.dead || e.kind == Kind::kLower) continue;
    if (e.kind == Kind::kUpper && e.label == E(lower_edge).label) continue;  // unsuitable
    const Ticks nd = d + e.w;
    if (e.kind == Kind::kUpper && nd < -net_.links[Size(e.label)].lb) {
      if (nd < 0 && !Derive(lower_edge, u, ei, nd, conflict)) return false;
      continue;
    }
    Slot& v = slots_[Size(e.to)];
    if (v.stamp == stamp_ && (v.settled || nd >= v.dist)) continue;
    v = {nd, ei, u, stamp_, false};
    queue_.push({nd + f_[Size(c)] - f_[Size(e.to)], e.to});  // reduced: >= 0 along edges
  }
  return true;
}

// A moat from C of length `dist` to `node` (then over `last`, an upper-case edge, when given): the
// derived edge A -> W, kept when new or tighter. False on a negative cycle through A.
bool Moats::Derive(int lower_edge, int node, int last, Ticks dist, std::vector<int>* conflict) {
  const Edge& le = E(lower_edge);
  const int w_node = last >= 0 ? E(last).to : node;
  Edge d{le.from, w_node, le.w + dist, Kind::kOrdinary, -1, -1, lower_edge, -1};
  if (last >= 0 && d.w < -net_.links[Size(E(last).label)].lb) {
    d.kind = Kind::kUpper;  // still a wait after the lower-case edge
    d.label = E(last).label;
  }
  if (w_node == le.from) {  // a cycle through A
    if (d.w >= 0) return true;
    d.path = Materialise(node, last);
    edges_.push_back(d);
    Explain({static_cast<int>(edges_.size()) - 1}, conflict);
    return false;
  }
  const std::tuple<int, int, int> key{d.from, d.to, d.label + 1};
  auto it = derived_.find(key);
  if (it != derived_.end() && E(it->second).w <= d.w) return true;
  auto pit = pending_index_.find(key);
  if (pit != pending_index_.end() && pending_[pit->second].w <= d.w) return true;
  d.path = Materialise(node, last);
  if (pit != pending_index_.end()) {
    pending_[pit->second] = d;
  } else {
    pending_index_[key] = pending_.size();
    pending_.push_back(d);
  }
  return true;
}

// Adds the round's derived edges; false when none was new or tighter.
bool Moats::Commit() {
  bool changed = false;
  for (const Edge& d : pending_) {
    auto it = derived_.find({d.from, d.to, d.label + 1});
    if (it != derived_.end()) {
      Edge& old = edges_[Size(it->second)];
      if (old.w <= d.w) continue;
      old.dead = true;
    }
    derived_[{d.from, d.to, d.label + 1}] = AddEdge(d);
    changed = true;
  }
  pending_.clear();
  pending_index_.clear();
  return changed;
}

}  // namespace

bool MoatDynamicControllability(const Network& net, std::vector<int>* conflict) {
  Moats m(net);
  return m.Run(conflict);
}

}  // namespace ctb::network::internal
