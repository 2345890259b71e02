// Dynamic controllability: Morris 2014, "Dynamic controllability and dispatchability relationships"
// (CPAIOR 2014), with instantaneous reaction. The network is dynamically controllable iff its
// labelled distance graph has no semi-reducible negative cycle. DCbackprop runs from every negative
// node (a node with a negative incoming edge): a Dijkstra search backwards from the node that
// starts with its negative in-edges and continues over non-negative edges only; where the distance
// becomes non-negative, a non-negative ordinary edge to the source is added and the search stops
// there. A negative node met on the way must have been processed first (its negative in-edges are
// then bypassed by such edges): Morris recurses; here the search stops, that node is processed, and
// the search starts again, so searches never nest and use flat arrays. The paths that begin with an
// upper-case edge are searched apart from the others (one search per upper-case in-edge): the
// lower-case edge of the same contingent link may not precede them. A node met again while it
// waits, or a path back to the source of negative length, is a semi-reducible negative cycle.
//
// Conflicts (Bhargava, Vaquero & Williams 2018): every derived edge remembers the path it
// summarises, so the cycle's edges expand to the input links they came from.

#include <algorithm>
#include <functional>
#include <queue>
#include <set>
#include <unordered_map>

#include "planner/network/dynamic_internal.h"
#include "planner/network/stn.h"

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

class Morris {
 public:
  explicit Morris(const Network& net) : n_(net.points.size()), in_(n_) {
    for (std::size_t i = 0; i < net.links.size(); ++i) AddLink(net.links[i], static_cast<int>(i));
    negative_.assign(n_, 0);
    for (const Edge& e : edges_) {
      if (e.w < 0 || e.kind == EdgeKind::kUpper) negative_[U(e.to)] = 1;
    }
    status_.assign(n_, 0);
    dist_.assign(n_, 0);
    edge_.assign(n_, -1);
    next_.assign(n_, -1);
    path_.assign(n_, -1);
    stamp_.assign(n_, 0);
    path_stamp_.assign(n_, 0);
    settled_.assign(n_, 0);
  }

  // Every negative node, the latest first (by a consistent schedule): a search from a point needs
  // the searches from the points after it, which are then done.
  bool Run() {
    std::vector<int> order;
    for (std::size_t v = 0; v < n_; ++v) {
      if (negative_[v]) order.push_back(static_cast<int>(v));
    }
    std::vector<internal::StnEdge> stn;
    for (const Edge& e : edges_) {
      if (e.kind == EdgeKind::kOrdinary) stn.push_back({e.from, e.to, e.w, -1});
    }
    std::vector<Ticks> f;
    if (internal::BellmanFord(static_cast<int>(n_), stn, &f, nullptr)) {
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return f[U(a)] > f[U(b)]; });
    }
    for (int v : order) {
      if (status_[U(v)] != 2 && !Process(v)) return false;
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
      const std::size_t ei = U(stack.back());
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
  enum class Outcome { kDone, kNeed, kCycle };

  static std::size_t U(int i) { return static_cast<std::size_t>(i); }

  void AddEdge(Edge e) {
    in_[U(e.to)].push_back(static_cast<int>(edges_.size()));
    edges_.push_back(e);
  }

  // A link's distance graph; a contingent link (A, C, x, y) also gets the lower-case edge A -> C
  // (c: x) and the upper-case edge C -> A (C: -y).
  void AddLink(const Link& l, int li) {
    if (l.ub) AddEdge({l.from, l.to, *l.ub, EdgeKind::kOrdinary, li});
    AddEdge({l.to, l.from, -l.lb, EdgeKind::kOrdinary, li});
    if (l.contingent) {
      AddEdge({l.from, l.to, l.lb, EdgeKind::kLower, li});
      AddEdge({l.to, l.from, -*l.ub, EdgeKind::kUpper, li});
    }
  }

  void PushPath(int p, std::vector<int>& stack) const {
    for (; p >= 0; p = paths_[U(p)].next) stack.push_back(paths_[U(p)].edge);
  }

  // The path node of u in the current search (its path's nodes created on first use).
  int Materialise(int u) {
    std::vector<int> chain;
    int v = u;
    for (; v >= 0 && path_stamp_[U(v)] != search_; v = next_[U(v)]) chain.push_back(v);
    int next = v < 0 ? -1 : path_[U(v)];
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      paths_.push_back({edge_[U(*it)], next});
      next = static_cast<int>(paths_.size()) - 1;
      path_[U(*it)] = next;
      path_stamp_[U(*it)] = search_;
    }
    return next;
  }

  // A non-negative ordinary edge u -> source, unless one at least as short exists.
  void AddDerived(int u, int source, Ticks w, int path) {
    const long long key = static_cast<long long>(u) * static_cast<long long>(n_) + source;
    auto it = derived_.find(key);
    if (it != derived_.end()) {
      Edge& old = edges_[U(it->second)];
      if (old.w <= w) return;
      old.dead = true;
    }
    derived_[key] = static_cast<int>(edges_.size());
    AddEdge({u, source, w, EdgeKind::kOrdinary, -1, path});
  }

  void Relax(int v, Ticks d, int edge, int next) {
    if (stamp_[U(v)] == search_ && (settled_[U(v)] || d >= dist_[U(v)])) return;
    stamp_[U(v)] = search_;
    settled_[U(v)] = 0;
    dist_[U(v)] = d;
    edge_[U(v)] = edge;
    next_[U(v)] = next;
    queue_.push({d, v});
  }

  bool Process(int source);
  Outcome SearchAll(int source);
  Outcome Search(int source, int cls);

  std::size_t n_;
  std::vector<std::vector<int>> in_;
  std::vector<Edge> edges_;
  std::vector<PathNode> paths_;
  std::vector<char> negative_;
  std::vector<char> status_;  // 0 not yet, 1 on the chain of waiting searches, 2 done
  std::unordered_map<long long, int> derived_;
  // The current search, in arrays stamped with its number (searches never nest).
  unsigned search_ = 0;
  std::vector<Ticks> dist_;
  std::vector<int> edge_;  // the first edge of the path from the node to the source
  std::vector<int> next_;  // the next node on it, -1 at the source
  std::vector<int> path_;
  std::vector<unsigned> stamp_, path_stamp_;
  std::vector<char> settled_;
  std::priority_queue<std::pair<Ticks, int>, std::vector<std::pair<Ticks, int>>, std::greater<>>
      queue_;
  int need_ = -1, need_path_ = -1;  // after kNeed: the negative node to process first
  // Sources waiting for another's search, and the path that led each to the next.
  std::vector<std::pair<int, int>> chain_;
  std::vector<int> cycle_paths_;
};

// DCbackprop without recursion: a search that meets a negative node not yet processed stops; that
// node is processed first, then the search starts again (on a graph with more edges). A node met
// again while it waits is Morris's "ancestor call with the same source": the paths along the chain
// form a semi-reducible negative cycle.
bool Morris::Process(int source) {
  chain_.assign(1, {source, -1});
  status_[U(source)] = 1;
  while (!chain_.empty()) {
    const int src = chain_.back().first;
    const Outcome o = SearchAll(src);
    if (o == Outcome::kCycle) return false;
    if (o == Outcome::kDone) {
      status_[U(src)] = 2;
      chain_.pop_back();
      continue;
    }
    if (status_[U(need_)] == 1) {
      auto it = std::find_if(chain_.begin(), chain_.end(),
                             [&](const auto& c) { return c.first == need_; });
      for (++it; it != chain_.end(); ++it) cycle_paths_.push_back(it->second);
      cycle_paths_.push_back(need_path_);
      return false;
    }
    status_[U(need_)] = 1;
    chain_.push_back({need_, need_path_});
  }
  return true;
}

// One search per class of the source's negative in-edges: the ordinary ones together, then each
// upper-case edge alone (the lower-case edge of the same link may not precede its paths).
Morris::Outcome Morris::SearchAll(int source) {
  bool ordinary = false;
  for (int ei : in_[U(source)]) {
    const Edge& e = edges_[U(ei)];
    if (!e.dead && e.kind == EdgeKind::kOrdinary && e.w < 0) ordinary = true;
  }
  if (ordinary) {
    const Outcome o = Search(source, -1);
    if (o != Outcome::kDone) return o;
  }
  for (std::size_t i = 0; i < in_[U(source)].size(); ++i) {
    const Edge& e = edges_[U(in_[U(source)][i])];
    if (e.kind != EdgeKind::kUpper) continue;
    const Outcome o = Search(source, in_[U(source)][i]);
    if (o != Outcome::kDone) return o;
  }
  return Outcome::kDone;
}

// The Dijkstra search backwards from `source`, starting with its negative ordinary in-edges (upper
// < 0) or with the upper-case edge `upper`.
Morris::Outcome Morris::Search(int source, int upper) {
  ++search_;
  queue_ = {};
  const int cls = upper < 0 ? -1 : edges_[U(upper)].link;
  if (upper >= 0) {
    Relax(edges_[U(upper)].from, edges_[U(upper)].w, upper, -1);
  } else {
    for (int ei : in_[U(source)]) {
      const Edge& e = edges_[U(ei)];
      if (!e.dead && e.kind == EdgeKind::kOrdinary && e.w < 0) Relax(e.from, e.w, ei, -1);
    }
  }
  while (!queue_.empty()) {
    const auto [d, u] = queue_.top();
    queue_.pop();
    if (settled_[U(u)] || d != dist_[U(u)]) continue;
    settled_[U(u)] = 1;
    if (u == source) {
      if (d >= 0) continue;
      cycle_paths_.push_back(Materialise(u));
      return Outcome::kCycle;
    }
    if (d >= 0) {
      AddDerived(u, source, d, Materialise(u));
      continue;
    }
    if (negative_[U(u)] && status_[U(u)] != 2) {
      need_ = u;
      need_path_ = Materialise(u);
      return Outcome::kNeed;
    }
    for (std::size_t i = 0; i < in_[U(u)].size(); ++i) {
      const Edge& e = edges_[U(in_[U(u)][i])];
      if (e.dead || e.w < 0 || e.kind == EdgeKind::kUpper) continue;
      if (e.kind == EdgeKind::kLower && e.link == cls) continue;  // unsuitable
      Relax(e.from, d + e.w, in_[U(u)][i], u);
    }
  }
  return Outcome::kDone;
}

}  // namespace

namespace internal {

bool MorrisDynamicControllability(const Network& net, std::vector<int>* conflict) {
  Morris m(net);
  const bool dc = m.Run();
  if (!dc && conflict) *conflict = m.ConflictLinks();
  return dc;
}

}  // namespace internal
}  // namespace ctb::network
