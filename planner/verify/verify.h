// The independent verifier: replays a trajectory against the contract's semantics. It depends on
// the model and expression libraries only (never on the encoder), which the build enforces.
#pragma once

#include <string>
#include <vector>

#include "planner/model/trajectory.h"

namespace ctb {

// Independent replay against the contract's semantics (sections 2 and 3). Returns every
// violation found; empty means the trajectory is a valid plan for the state plan.
// allow_idle_events: events that carry no transition are accepted (the relaxed runs the split
// uses for its lower bounds, docs/encoding.md); never for an answer.
// With t.history (replanning): stages 0..p must be the history's, whose events are taken as
// reported (no model rule is checked on them); later events must be at or after history->now and
// obey every rule from the history's entry times; the state plan is judged on the whole run.
std::vector<std::string> VerifyTrajectory(const Trajectory& t, const Domain& d,
                                          const StatePlan& sp, long ticks_per_second,
                                          bool allow_idle_events = false);

// The same replay, stopped at the first violation: true when t is a valid plan. For callers that
// judge many candidates (brute-force enumeration in the tests) and need no reasons.
bool TrajectoryIsPlan(const Trajectory& t, const Domain& d, const StatePlan& sp,
                      long ticks_per_second);

}  // namespace ctb
