// JSON of temporal networks: the `/networks/check` body (contract section 13) and the `network` of
// an answer.
#pragma once

#include <optional>

#include "planner/model/json_io.h"
#include "planner/network/check.h"
#include "planner/network/network.h"

namespace ctb::network {

// Parses {"points": ["a", ...], "links": [{"from", "to", "lb", "ub"?, "contingent"?}]} strictly:
// unknown keys, wrong types, duplicate point names, unknown point names (with a suggestion), bounds
// that are not finite, not a whole number of milliseconds or beyond kMaxAbsSeconds, and every rule
// of Validate are errors at their JSON pointer ("/links/3/ub"), all of them reported. `ub` absent
// or null is +infinity (requirement links only). Memory linear in the body. Returns nullopt when
// diags has an error.
std::optional<Network> ParseCheckBody(const Json& body, Diagnostics& diags);

// The answer of /networks/check: {"consistent", "strong", "dynamic", "conflict"? , "ms"}.
Json CheckResultToJson(const CheckResult& r);

// The contract's `network` object: points with id, kind and labels; links with from, to, lb, ub
// (null for +inf), kind ("contingent" | "requirement") and why, in seconds.
Json NetworkToJson(const Network& net);

}  // namespace ctb::network
