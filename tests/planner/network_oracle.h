// Slow, independent oracles for the temporal-network checker (tests only): they share no code with
// planner/network beyond the Network type.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "planner/network/network.h"

namespace ctb::network::testing {

// Strong controllability by enumeration: one copy of every contingent point per combination of
// contingent durations at their extremes, all constraints of all combinations in one STN over the
// shared controllable points; consistent (Floyd-Warshall) iff strongly controllable (each
// constraint is linear in the durations, so holding at the corners of the box is holding
// everywhere). Exponential in the number of contingent links.
bool OracleStrong(const Network& net);

// Consistency by Floyd-Warshall.
bool OracleConsistent(const Network& net);

// Dynamic controllability by a game search in discrete time, for tiny networks with integer tick
// bounds (a few points, bounds below 8): at each integer time, nature first decides which activated
// contingent points finish now, then the agent may execute one controllable point after another,
// seeing each outcome (a contingent link of lb 0 activated now is decided by nature right after its
// activation); or wait for the next time. The agent wins when every point is executed and every
// link holds. States (relative times, clamped beyond every bound) are memoised.
bool OracleDynamic(const Network& net);

// A random network with `n` points, up to `k` contingent links and `m` requirement links, all
// bounds within [-max_bound, max_bound] ticks (contingent: [0, max_bound]).
Network RandomNetwork(std::mt19937& rng, int n, int k, int m, int max_bound);

// The network restricted to the given links (every point kept; a point stays contingent only if its
// contingent link is kept).
Network Restrict(const Network& net, const std::vector<int>& links);

}  // namespace ctb::network::testing
