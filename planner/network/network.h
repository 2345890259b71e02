// Temporal networks with uncertainty (STNUs, contract section 13): the public types shared by the
// `/networks/check` front ends and by the plan-to-network derivation.
//
// Time is exact: a bound is a whole number of ticks (`Ticks`, 1 tick = 1 ms). Controllability
// checks add and compare sums of bounds along paths; with doubles a zero-length cycle can come out
// as -1e-15 and flip an answer, with integers it cannot. The contract's JSON carries seconds
// (integers in practice, fractions allowed by domains); `TicksFromSeconds` converts exactly and
// refuses values that are not a multiple of 1 ms or whose magnitude exceeds kMaxAbsSeconds, so that
// no sum over a path of up to 10^6 links can overflow.
//
// Semantics of a link from u to v with bounds [lb, ub]: t(v) - t(u) in [lb, ub].
//   - requirement link: the dispatcher must make it hold; lb may be negative, ub may be +inf;
//   - contingent link: nature picks t(v) - t(u) anywhere in [lb, ub] (0 <= lb <= ub, ub finite); v
//     is then a contingent point and the end of exactly one contingent link; u is its activation
//     point. Contingent links form a forest (no contingent cycle).
// Thread-safe: plain values.
#pragma once

#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "planner/model/error.h"

namespace ctb::network {

using Ticks = long long;
inline constexpr Ticks kTicksPerSecond = 1000;
// Bounds beyond +-10^9 s (about 31 years) are refused as absurd.
inline constexpr double kMaxAbsSeconds = 1e9;
// Larger than any sum of bounds along a simple path of any network we accept.
inline constexpr Ticks kInfinity = std::numeric_limits<Ticks>::max() / 4;

enum class PointKind { kOrigin, kControllable, kContingent };
const char* PointKindName(PointKind k);  // "origin" | "controllable" | "contingent"

struct Point {
  int id = 0;        // the index of the point in Network::points
  std::string name;  // a bare network's name ("a"); derived networks may leave it empty
  PointKind kind = PointKind::kControllable;
  // Optional descriptive labels printed with the point (automaton, from, to, command, ...).
  std::map<std::string, std::string> labels;
};

struct Link {
  int from = 0;  // indices into Network::points
  int to = 0;
  Ticks lb = 0;
  std::optional<Ticks> ub;  // nullopt: +infinity (requirement links only)
  bool contingent = false;
  std::string why;  // where the link comes from (a JSON pointer or words); may be empty
};

struct Network {
  std::vector<Point> points;
  std::vector<Link> links;
};

// Exact conversions. Returns nullopt when `seconds` is not finite, not a whole number of ticks
// (within 1e-9 s) or beyond kMaxAbsSeconds.
std::optional<Ticks> TicksFromSeconds(double seconds);
double SecondsFromTicks(Ticks t);

// The rules on one link's bounds (contingent: 0 <= lb <= ub < inf; requirement: lb <= ub), recorded
// at pointer + "/lb" or "/ub".
void CheckLinkBounds(const Link& link, const std::string& pointer, Diagnostics& diags);

// Structural rules of a network: link ends are valid point indices, contingent links have 0 <= lb
// <= ub < inf, requirement links lb <= ub, no point is the end of two contingent links, the
// contingent links form no cycle, a point's kind agrees with the links (contingent iff the end of a
// contingent link; at most one origin, which is no contingent link's end). Each problem is recorded
// at "/links/<i>" (or "/points/<i>") plus "/lb", "/ub" where it is a bound's. Returns diags.ok()
// for this network.
bool Validate(const Network& net, Diagnostics& diags);

}  // namespace ctb::network
