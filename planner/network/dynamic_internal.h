// Internal to planner/network: the two dynamic-controllability checkers. Both answer the same
// question (instantaneous reaction); check.cpp uses the moat reductions, the tests compare them.
#pragma once

#include <vector>

#include "planner/network/network.h"

namespace ctb::network::internal {

// Morris 2014's DCbackprop (dynamic.cpp): O(n^3); on plan-like networks, whose points are mostly
// ordered, each search covers every later point, so it grows as n^2.
bool MorrisDynamicControllability(const Network& net, std::vector<int>* conflict);

// Iterated moat reductions (Morris 2006) with potentials (moats.cpp): a Dijkstra per contingent
// link per round.
bool MoatDynamicControllability(const Network& net, std::vector<int>* conflict);

}  // namespace ctb::network::internal
