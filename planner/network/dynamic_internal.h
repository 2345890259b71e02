// Internal to planner/network: two dynamic-controllability checkers. Both answer the same question
// (instantaneous reaction); check.cpp uses Morris 2014 (faster on the benchmark's networks), the
// tests compare them with each other and with the slow oracles.
#pragma once

#include <vector>

#include "planner/network/network.h"

namespace ctb::network::internal {

// Morris 2014's DCbackprop (dynamic.cpp): O(n^3). Each search covers the points whose distance to
// its source is negative (on plan-like networks, the later points within reach of the source's
// largest lower bound), so the time grows faster than linearly with the network.
bool MorrisDynamicControllability(const Network& net, std::vector<int>* conflict);

// Iterated moat reductions (Morris 2006) with potentials (moats.cpp): a Dijkstra per contingent
// link per round.
bool MoatDynamicControllability(const Network& net, std::vector<int>* conflict);

}  // namespace ctb::network::internal
