#include "planner/network/stn.h"

#include <algorithm>
#include <deque>

namespace ctb::network::internal {

std::vector<StnEdge> DistanceEdges(const Network &net) {
  std::vector<StnEdge> edges;
  edges.reserve(net.links.size() * 2);
  for (std::size_t i = 0; i < net.links.size(); ++i) {
    const Link &l = net.links[i];
    const int li = static_cast<int>(i);
    if (l.ub)
      edges.push_back({l.from, l.to, *l.ub, li});
    edges.push_back({l.to, l.from, -l.lb, li});
  }
  return edges;
}

namespace {

// A cycle of the predecessor graph (edge indices in cycle order), or empty.
// Every such cycle of Bellman-Ford's predecessor graph is negative.
std::vector<int> PredecessorCycle(const std::vector<StnEdge> &edges,
                                  const std::vector<int> &pred) {
  const std::size_t n = pred.size();
  std::vector<int> mark(n, -1); // the start of the walk that visited the node
  for (std::size_t s = 0; s < n; ++s) {
    if (mark[s] >= 0)
      continue;
    std::size_t v = s;
    while (mark[v] < 0) {
      mark[v] = static_cast<int>(s);
      const int e = pred[v];
      if (e < 0)
        break;
      v = static_cast<std::size_t>(edges[static_cast<std::size_t>(e)].from);
    }
    if (mark[v] != static_cast<int>(s) || pred[v] < 0)
      continue;
    std::vector<int> cycle; // v is on a cycle found in this walk
    std::size_t u = v;
    do {
      const int e = pred[u];
      cycle.push_back(e);
      u = static_cast<std::size_t>(edges[static_cast<std::size_t>(e)].from);
    } while (u != v);
    std::reverse(cycle.begin(), cycle.end());
    return cycle;
  }
  return {};
}

} // namespace

bool BellmanFord(int n, const std::vector<StnEdge> &edges,
                 std::vector<Ticks> *potential, std::vector<int> *cycle) {
  if (n <= 0)
    return true;
  const std::size_t un = static_cast<std::size_t>(n);
  std::vector<std::vector<int>> out(un);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    out[static_cast<std::size_t>(edges[i].from)].push_back(static_cast<int>(i));
  }
  std::vector<Ticks> dist(un, 0);
  std::vector<int> pred(un, -1);
  std::vector<char> queued(un, 1);
  std::deque<int> queue;
  for (int v = 0; v < n; ++v)
    queue.push_back(v);
  std::size_t relaxations = 0;
  const std::size_t limit = un * (edges.size() + 1) + un;
  while (!queue.empty()) {
    const int u = queue.front();
    queue.pop_front();
    queued[static_cast<std::size_t>(u)] = 0;
    for (int ei : out[static_cast<std::size_t>(u)]) {
      const StnEdge &e = edges[static_cast<std::size_t>(ei)];
      const Ticks nd = dist[static_cast<std::size_t>(u)] + e.w;
      const std::size_t v = static_cast<std::size_t>(e.to);
      if (nd >= dist[v])
        continue;
      dist[v] = nd;
      pred[v] = ei;
      ++relaxations;
      if (relaxations % un == 0 || relaxations > limit) {
        std::vector<int> c = PredecessorCycle(edges, pred);
        if (!c.empty() ||
            relaxations > limit) { // beyond Bellman-Ford's bound: a cycle
          if (cycle)
            *cycle = std::move(c);
          return false;
        }
      }
      if (!queued[v])
        queued[v] = 1, queue.push_back(e.to);
    }
  }
  if (potential)
    *potential = std::move(dist);
  return true;
}

} // namespace ctb::network::internal
