#include "planner/network/check.h"

#include <algorithm>
#include <chrono>

#include "planner/network/dynamic_internal.h"
#include "planner/network/stn.h"

namespace ctb::network {

bool IsConsistent(const Network& net, std::vector<int>* cycle) {
  const std::vector<internal::StnEdge> edges = internal::DistanceEdges(net);
  std::vector<int> cycle_edges;
  if (internal::BellmanFord(static_cast<int>(net.points.size()), edges, nullptr, &cycle_edges)) {
    return true;
  }
  if (cycle) {
    cycle->clear();
    for (int e : cycle_edges) cycle->push_back(edges[static_cast<std::size_t>(e)].link);
    std::sort(cycle->begin(), cycle->end());
    cycle->erase(std::unique(cycle->begin(), cycle->end()), cycle->end());
  }
  return false;
}

bool IsDynamicallyControllable(const Network& net, std::vector<int>* conflict) {
  return internal::MorrisDynamicControllability(net, conflict);
}

CheckResult CheckNetwork(const Network& net) {
  const auto start = std::chrono::steady_clock::now();
  CheckResult r;
  r.consistent = IsConsistent(net, &r.conflict);
  if (r.consistent) {
    r.strong = IsStronglyControllable(net);
    // One schedule for every outcome is also a dispatch strategy: strong implies dynamic, and
    // Morris's searches (the costly part) are only needed when the network is not strong.
    r.dynamic = r.strong || IsDynamicallyControllable(net, &r.conflict);
  } else if (r.conflict.empty()) {  // Bellman-Ford stopped at its bound without
                                    // a cycle
    IsDynamicallyControllable(net, &r.conflict);
  }
  const auto end = std::chrono::steady_clock::now();
  r.ms = std::chrono::duration<double, std::milli>(end - start).count();
  return r;
}

}  // namespace ctb::network
