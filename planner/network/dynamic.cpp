// Dynamic controllability: Morris 2014, "Dynamic controllability and dispatchability
// relationships" (CPAIOR 2014), with instantaneous reaction. The network is dynamically
// controllable iff its labelled distance graph has no semi-reducible negative cycle. DCbackprop
// runs from every negative node (a node with a negative incoming edge): a Dijkstra search
// backwards from the node that starts with one of its negative in-edges and continues over
// non-negative edges only (the negative in-edges of a negative node met on the way are first
// bypassed by a recursive call). Where the distance becomes non-negative, a non-negative
// ordinary edge is added; a lower-case edge is not followed right after the upper-case edge of
// its own contingent link. A recursive call on a node already on the call stack, or a path back
// to the source of negative length, is a semi-reducible negative cycle.
//
// Conflicts (Bhargava, Vaquero & Williams 2018): every derived edge remembers the path it
// summarises, so the cycle's edges expand to the input links they came from.
#include <pthread.h>

#include <algorithm>
#include <functional>
#include <queue>
#include <set>
#include <unordered_map>

#include "planner/network/check.h"

namespace ctb::network {
namespace {

enum class EdgeKind { kOrdinary, kLower, kUpper };

struct Edge {
  int from = 0;
  int to = 0;
  Ticks w = 0;
  EdgeKind kind = EdgeKind::kOrdinary;
  int link = -1;      // input edges: the link; derived: -1
  int path = -1;      // derived edges: the path node of `from` in the search that derived it
  bool dead = false;  // superseded by a shorter derived edge between the same points
};

// A path towards a search's source: an edge, then the rest (-1 at the source).
struct PathNode {
  int edge = 0;
  int next = -1;
};

// One node of a search: its distance to the source and the path that achieves it.
struct Entry {
  Ticks dist = 0;
  int edge = -1;  // the first edge of the path from this node to the source
  int init = -1;  // the path's last edge (an in-edge of the source)
  int path = -1;  // the materialised path node, or -1
  bool settled = false;
};

// One DCbackprop search: its source and the nodes reached.
struct Search {
  int source = 0;
  std::unordered_map<int, Entry> at;
};
using Queue = std::priority_queue<std::pair<Ticks, int>, std::vector<std::pair<Ticks, int>>,
                                  std::greater<>>;

class Morris {
 public:
  explicit Morris(const Network& net)
      : n_(static_cast<int>(net.points.size())), in_(static_cast<std::size_t>(n_)) {
    for (std::size_t i = 0; i < net.links.size(); ++i) AddLink(net.links[i], static_cast<int>(i));
    negative_.assign(static_cast<std::size_t>(n_), 0);
    for (const Edge& e : edges_) {
      if (e.w < 0 || e.kind == EdgeKind::kUpper) negative_[static_cast<std::size_t>(e.to)] = 1;
    }
    status_.assign(static_cast<std::size_t>(n_), 0);
  }

  bool Run() {
    for (int v = 0; v < n_; ++v) {
      if (negative_[static_cast<std::size_t>(v)] && !BackProp(v, -1)) return false;
    }
    return true;
  }

  // The input links of the negative cycle found (after Run() returned false), sorted.
  std::vector<int> ConflictLinks() const {
    std::set<int> links;
    std::vector<char> seen(edges_.size(), 0);
    std::vector<int> stack;
    for (int p : cycle_paths_) PushPath(p, stack);
    while (!stack.empty()) {
      const std::size_t ei = static_cast<std::size_t>(stack.back());
      stack.pop_back();
      if (seen[ei]) continue;
      seen[ei] = 1;
      const Edge& e = edges_[ei];
      if (e.link >= 0) {
        links.insert(e.link);
      } else {
        PushPath(e.path, stack);
      }
    }
    return std::vector<int>(links.begin(), links.end());
  }

 private:
  void AddEdge(Edge e) {
    in_[static_cast<std::size_t>(e.to)].push_back(static_cast<int>(edges_.size()));
    edges_.push_back(e);
  }

  // A link's distance graph; a contingent link (A, C, x, y) also gets the lower-case edge
  // A -> C (c: x) and the upper-case edge C -> A (C: -y).
  void AddLink(const Link& l, int li) {
    if (l.ub) AddEdge({l.from, l.to, *l.ub, EdgeKind::kOrdinary, li});
    AddEdge({l.to, l.from, -l.lb, EdgeKind::kOrdinary, li});
    if (l.contingent) {
      AddEdge({l.from, l.to, l.lb, EdgeKind::kLower, li});
      AddEdge({l.to, l.from, -*l.ub, EdgeKind::kUpper, li});
    }
  }

  void PushPath(int p, std::vector<int>& stack) const {
    for (; p >= 0; p = paths_[static_cast<std::size_t>(p)].next) {
      stack.push_back(paths_[static_cast<std::size_t>(p)].edge);
    }
  }

  // The path node of v in search s (creating the nodes of its path on first use).
  int Materialise(Search& s, int v) {
    Entry& e = s.at.at(v);
    if (e.path >= 0) return e.path;
    const int next_node = edges_[static_cast<std::size_t>(e.edge)].to;
    const int next = next_node == s.source ? -1 : Materialise(s, next_node);
    Entry& again = s.at.at(v);
    again.path = static_cast<int>(paths_.size());
    paths_.push_back({again.edge, next});
    return again.path;
  }

  // A non-negative ordinary edge u -> source, unless one at least as short exists.
  void AddDerived(int u, int source, Ticks w, int path) {
    const long long key = static_cast<long long>(u) * n_ + source;
    auto it = derived_.find(key);
    if (it != derived_.end()) {
      Edge& old = edges_[static_cast<std::size_t>(it->second)];
      if (old.w <= w) return;
      old.dead = true;
    }
    derived_[key] = static_cast<int>(edges_.size());
    AddEdge({u, source, w, EdgeKind::kOrdinary, -1, path});
  }

  // Whether the lower-case edge e may come before the path of u: not when that path starts with
  // the upper-case edge of the same contingent link (which can only be the search's first edge).
  bool Suitable(const Edge& e, const Entry& at_u) const {
    if (e.kind != EdgeKind::kLower || at_u.edge < 0) return true;
    const Edge& next = edges_[static_cast<std::size_t>(at_u.edge)];
    return !(next.kind == EdgeKind::kUpper && next.link == e.link);
  }

  static bool Improves(const Search& s, int v, Ticks d) {
    auto it = s.at.find(v);
    return it == s.at.end() || (!it->second.settled && d < it->second.dist);
  }

  bool Fail(Search& s, int u) {
    cycle_paths_.push_back(Materialise(s, u));
    return false;
  }

  bool BackProp(int source, int trigger_path);
  bool Propagate(Search& s, Queue& q, int source, int u);

  int n_;
  std::vector<std::vector<int>> in_;
  std::vector<Edge> edges_;
  std::vector<PathNode> paths_;
  std::vector<char> negative_;
  std::vector<char> status_;  // 0 not yet, 1 on the call stack, 2 done
  std::unordered_map<long long, int> derived_;
  // The call stack: each call's source and the path that led its caller to it.
  std::vector<std::pair<int, int>> stack_;
  std::vector<int> cycle_paths_;
};

bool Morris::BackProp(int source, int trigger_path) {
  const std::size_t us = static_cast<std::size_t>(source);
  if (status_[us] == 1) {  // a cycle of calls: the paths from the earlier call on
    auto it = std::find_if(stack_.begin(), stack_.end(),
                           [&](const auto& f) { return f.first == source; });
    for (++it; it != stack_.end(); ++it) cycle_paths_.push_back(it->second);
    cycle_paths_.push_back(trigger_path);
    return false;
  }
  if (status_[us] == 2) return true;
  status_[us] = 1;
  stack_.push_back({source, trigger_path});
  Search s;
  s.source = source;
  Queue q;
  for (int ei : in_[us]) {
    const Edge& e = edges_[static_cast<std::size_t>(ei)];
    if (e.dead || (e.w >= 0 && e.kind != EdgeKind::kUpper)) continue;
    if (!Improves(s, e.from, e.w)) continue;
    s.at[e.from] = {e.w, ei, ei, -1, false};
    q.push({e.w, e.from});
  }
  bool ok = true;
  while (ok && !q.empty()) {
    const auto [d, u] = q.top();
    q.pop();
    Entry& at = s.at.at(u);
    if (at.settled || d != at.dist) continue;
    at.settled = true;
    ok = Propagate(s, q, source, u);
  }
  stack_.pop_back();
  status_[us] = ok ? 2 : 1;
  return ok;
}

// One settled node u of the search from `source`.
bool Morris::Propagate(Search& s, Queue& q, int source, int u) {
  const Ticks d = s.at.at(u).dist;
  if (u == source) return d >= 0 || Fail(s, u);
  if (d >= 0) {
    AddDerived(u, source, d, Materialise(s, u));
    return true;
  }
  if (negative_[static_cast<std::size_t>(u)] && !BackProp(u, Materialise(s, u))) return false;
  const Entry at = s.at.at(u);
  const std::vector<int>& in = in_[static_cast<std::size_t>(u)];
  for (std::size_t k = 0; k < in.size(); ++k) {
    const int ei = in[k];
    const Edge& e = edges_[static_cast<std::size_t>(ei)];
    if (e.dead || e.w < 0 || e.kind == EdgeKind::kUpper || !Suitable(e, at)) continue;
    const Ticks nd = d + e.w;
    if (!Improves(s, e.from, nd)) continue;
    s.at[e.from] = {nd, ei, at.init, -1, false};
    q.push({nd, e.from});
  }
  return true;
}

// Runs fn on a thread with a large stack: DCbackprop recurses once per negative node on a chain.
void RunWithLargeStack(const std::function<void()>& fn) {
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  pthread_attr_setstacksize(&attr, std::size_t{1} << 30);
  pthread_t th;
  auto trampoline = [](void* arg) -> void* {
    (*static_cast<const std::function<void()>*>(arg))();
    return nullptr;
  };
  if (pthread_create(&th, &attr, trampoline, const_cast<std::function<void()>*>(&fn)) != 0) {
    fn();  // no thread: the caller's stack
  } else {
    pthread_join(th, nullptr);
  }
  pthread_attr_destroy(&attr);
}

}  // namespace

bool IsDynamicallyControllable(const Network& net, std::vector<int>* conflict) {
  bool dc = true;
  RunWithLargeStack([&] {
    Morris m(net);
    dc = m.Run();
    if (!dc && conflict) *conflict = m.ConflictLinks();
  });
  return dc;
}

}  // namespace ctb::network
