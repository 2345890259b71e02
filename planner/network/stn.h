// Internal to planner/network: simple temporal networks as distance graphs and Bellman-Ford.
//
// An edge u -> v of weight w states t(v) - t(u) <= w. `link` is the input link the edge comes from
// (for certificates), or -1.
#pragma once

#include <vector>

#include "planner/network/network.h"

namespace ctb::network::internal {

struct StnEdge {
  int from = 0;
  int to = 0;
  Ticks w = 0;
  int link = -1;
};

// The distance graph of every link read as a requirement: u -> v ub (when finite), v -> u -lb.
std::vector<StnEdge> DistanceEdges(const Network& net);

// Bellman-Ford with Goldberg-Radzik's ordering from a virtual source joined to every node by a 0
// edge. Returns true when there is no negative cycle; `potential` (optional) then receives
// shortest distances (<= 0) from the virtual source, a feasible schedule. Otherwise `cycle`
// (optional) receives the indices into `edges` of one negative cycle, in order. O(n m) in the
// worst case, near-linear on plan-like networks.
bool BellmanFord(int n, const std::vector<StnEdge>& edges, std::vector<Ticks>* potential,
                 std::vector<int>* cycle);

}  // namespace ctb::network::internal
