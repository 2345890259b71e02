// Dynamic controllability: Morris 2014, "Dynamic controllability and
// dispatchability relationships" (CPAIOR 2014), with instantaneous reaction.
// The network is dynamically controllable iff its labelled distance graph has
// no semi-reducible negative cycle. DCbackprop runs from every negative node (a
// node with a negative incoming edge): a Dijkstra search backwards from the
// node that starts with one of its negative in-edges and continues over
// non-negative edges only (the negative in-edges of a negative node met on the
// way are first bypassed by a recursive call). Where the distance becomes
// non-negative, a non-negative ordinary edge is added; a lower-case edge is not
// followed right after the upper-case edge of its own contingent link. A
// recursive call on a node already on the call stack, or a path back to the
// source of negative length, is a semi-reducible negative cycle.
//
// Conflicts (Bhargava, Vaquero & Williams 2018): every derived edge remembers
// the path it summarises, so the cycle's edges expand to the input links they
// came from.
#include <pthread.h>

#include <algorithm>
#include <functional>
#include <queue>
#include <set>
#include <unordered_map>

#include "planner/network/dynamic_internal.h"

namespace ctb::network {
namespace {

enum class EdgeKind { kOrdinary, kLower, kUpper };

struct Edge {
  int from = 0;
  int to = 0;
  Ticks w = 0;
  EdgeKind kind = EdgeKind::kOrdinary;
  int link = -1;      // input edges: the link; derived: -1
  int path = -1;      // derived edges: the path node of `from` in the search that
                      // derived it
  bool dead = false;  // superseded by a shorter derived edge between the same points
};

// A path towards a search's source: an edge, then the rest (-1 at the source).
struct PathNode {
  int edge = 0;
  int next = -1;
};

// One node of a search: its distance to the source and the path that achieves
// it. The search keeps the paths that end with the upper-case edge of a
// contingent link activated by the source apart from the others (one class per
// such link, key = node and class): the lower-case edge of that link may not
// come before them, but may come before every other path, and a shorter path of
// the forbidden class must not hide a longer one of another class.
struct Entry {
  Ticks dist = 0;
  int edge = -1;        // the first edge of the path from this node to the source
  long long next = -1;  // the key of the next node on the path, or -1 at the source
  int path = -1;        // the materialised path node, or -1
  bool settled = false;
};

// One DCbackprop search: its source and the keys reached.
struct Search {
  int source = 0;
  std::unordered_map<long long, Entry> at;
};
using Queue = std::priority_queue<std::pair<Ticks, long long>,
                                  std::vector<std::pair<Ticks, long long>>, std::greater<>>;

class Morris {
 public:
  explicit Morris(const Network &net)
      : n_(static_cast<int>(net.points.size())), in_(static_cast<std::size_t>(n_)) {
    for (std::size_t i = 0; i < net.links.size(); ++i) AddLink(net.links[i], static_cast<int>(i));
    negative_.assign(static_cast<std::size_t>(n_), 0);
    for (const Edge &e : edges_) {
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

  // The input links of the negative cycle found (after Run() returned false),
  // sorted.
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
      const Edge &e = edges_[ei];
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

  // A link's distance graph; a contingent link (A, C, x, y) also gets the
  // lower-case edge A -> C (c: x) and the upper-case edge C -> A (C: -y).
  void AddLink(const Link &l, int li) {
    if (l.ub) AddEdge({l.from, l.to, *l.ub, EdgeKind::kOrdinary, li});
    AddEdge({l.to, l.from, -l.lb, EdgeKind::kOrdinary, li});
    if (l.contingent) {
      AddEdge({l.from, l.to, l.lb, EdgeKind::kLower, li});
      AddEdge({l.to, l.from, -*l.ub, EdgeKind::kUpper, li});
    }
  }

  void PushPath(int p, std::vector<int> &stack) const {
    for (; p >= 0; p = paths_[static_cast<std::size_t>(p)].next) {
      stack.push_back(paths_[static_cast<std::size_t>(p)].edge);
    }
  }

  // The path node of key k in search s (creating the nodes of its path on first
  // use).
  int Materialise(Search &s, long long k) {
    Entry &e = s.at.at(k);
    if (e.path >= 0) return e.path;
    const int next = e.next < 0 ? -1 : Materialise(s, e.next);
    e.path = static_cast<int>(paths_.size());
    paths_.push_back({e.edge, next});
    return e.path;
  }

  // A non-negative ordinary edge u -> source, unless one at least as short
  // exists.
  void AddDerived(int u, int source, Ticks w, int path) {
    const long long key = static_cast<long long>(u) * n_ + source;
    auto it = derived_.find(key);
    if (it != derived_.end()) {
      Edge &old = edges_[static_cast<std::size_t>(it->second)];
      if (old.w <= w) return;
      old.dead = true;
    }
    derived_[key] = static_cast<int>(edges_.size());
    AddEdge({u, source, w, EdgeKind::kOrdinary, -1, path});
  }

  // Keys: node and class (0: the path does not end with an upper-case edge; 1 +
  // link: it ends with the upper-case edge of that contingent link).
  long long KeyOf(int node, int cls) const { return static_cast<long long>(cls) * n_ + node; }
  int NodeOf(long long key) const { return static_cast<int>(key % n_); }
  int ClassOf(long long key) const { return static_cast<int>(key / n_); }

  // Whether the lower-case edge e may come before the path of key k: not when
  // that path ends with the upper-case edge of the same contingent link.
  bool Suitable(const Edge &e, long long k) const {
    return e.kind != EdgeKind::kLower || ClassOf(k) != 1 + e.link;
  }

  // Records d as the distance of key k when it is shorter than what the search
  // has.
  static bool Relax(Search &s, Queue &q, long long k, Ticks d, int edge, long long next) {
    auto it = s.at.find(k);
    if (it != s.at.end() && (it->second.settled || d >= it->second.dist)) return false;
    s.at[k] = {d, edge, next, -1, false};
    q.push({d, k});
    return true;
  }

  bool Fail(Search &s, long long k) {
    cycle_paths_.push_back(Materialise(s, k));
    return false;
  }

  bool BackProp(int source, int trigger_path);
  bool Propagate(Search &s, Queue &q, long long k);

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
                           [&](const auto &f) { return f.first == source; });
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
    const Edge &e = edges_[static_cast<std::size_t>(ei)];
    const bool upper = e.kind == EdgeKind::kUpper;
    if (e.dead || (e.w >= 0 && !upper)) continue;
    Relax(s, q, KeyOf(e.from, upper ? 1 + e.link : 0), e.w, ei, -1);
  }
  bool ok = true;
  while (ok && !q.empty()) {
    const auto [d, k] = q.top();
    q.pop();
    Entry &at = s.at.at(k);
    if (at.settled || d != at.dist) continue;
    at.settled = true;
    ok = Propagate(s, q, k);
  }
  stack_.pop_back();
  status_[us] = ok ? 2 : 1;
  return ok;
}

// One settled key k of the search.
bool Morris::Propagate(Search &s, Queue &q, long long k) {
  const int u = NodeOf(k);
  const Ticks d = s.at.at(k).dist;
  if (u == s.source) return d >= 0 || Fail(s, k);
  if (d >= 0) {
    AddDerived(u, s.source, d, Materialise(s, k));
    return true;
  }
  if (negative_[static_cast<std::size_t>(u)] && status_[static_cast<std::size_t>(u)] != 2 &&
      !BackProp(u, Materialise(s, k))) {
    return false;
  }
  const std::vector<int> &in = in_[static_cast<std::size_t>(u)];
  for (std::size_t i = 0; i < in.size(); ++i) {
    const Edge &e = edges_[static_cast<std::size_t>(in[i])];
    if (e.dead || e.w < 0 || e.kind == EdgeKind::kUpper || !Suitable(e, k)) continue;
    Relax(s, q, KeyOf(e.from, ClassOf(k)), d + e.w, in[i], k);
  }
  return true;
}

// Runs fn on a thread with a large stack: DCbackprop recurses once per negative
// node on a chain.
void RunWithLargeStack(const std::function<void()> &fn) {
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  pthread_attr_setstacksize(&attr, std::size_t{1} << 30);
  pthread_t th;
  auto trampoline = [](void *arg) -> void * {
    (*static_cast<const std::function<void()> *>(arg))();
    return nullptr;
  };
  if (pthread_create(&th, &attr, trampoline, const_cast<std::function<void()> *>(&fn)) != 0) {
    fn();  // no thread: the caller's stack
  } else {
    pthread_join(th, nullptr);
  }
  pthread_attr_destroy(&attr);
}

}  // namespace

namespace internal {

bool MorrisDynamicControllability(const Network &net, std::vector<int> *conflict) {
  bool dc = true;
  RunWithLargeStack([&] {
    Morris m(net);
    dc = m.Run();
    if (!dc && conflict) *conflict = m.ConflictLinks();
  });
  return dc;
}

}  // namespace internal
}  // namespace ctb::network
