// Consistency, strong and dynamic controllability of a temporal network (docs/uncertainty.md).
//
//   - consistent: some assignment of times satisfies every link (contingent links read as
//     requirements). Bellman-Ford (Goldberg-Radzik order) from a virtual source; the certificate of
//     an inconsistent network is a negative cycle of links.
//   - strong: one time for every controllable point works for every outcome of the contingent links
//     (Vidal & Fargier 1999): each link is rewritten in terms of the activation points of its
//     contingent ends with the worst-case bounds, and the resulting STN must be consistent.
//   - dynamic: a dispatcher that sees outcomes as they happen (instantaneous reaction) always
//     succeeds; Morris 2014's O(n^3) DCbackprop (semi-reducible negative cycles), without
//     recursion.
//   - conflict (when not dynamic): indices of input links whose subnetwork (every point kept) is
//     itself not dynamically controllable: the provenance of the negative cycle found, as Bhargava
//     et al. 2018 extract it.
// Every function expects a network that passed Validate (network.h). Thread-safe; never throws
// (an allocation failure aside).
#pragma once

#include <vector>

#include "planner/network/network.h"

namespace ctb::network {

struct CheckResult {
  bool consistent = false;
  bool strong = false;
  bool dynamic = false;
  std::vector<int> conflict;  // sorted link indices; empty when dynamic
  double ms = 0;              // wall time of the whole check
};

// Consistency; when inconsistent and `cycle` is given, the links of a negative cycle (sorted).
bool IsConsistent(const Network& net, std::vector<int>* cycle = nullptr);

// Strong controllability (exact).
bool IsStronglyControllable(const Network& net);

// Dynamic controllability; when not and `conflict` is given, the conflict's links (sorted).
bool IsDynamicallyControllable(const Network& net, std::vector<int>* conflict = nullptr);

// All of the above.
CheckResult CheckNetwork(const Network& net);

}  // namespace ctb::network
