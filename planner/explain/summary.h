// The plain-language restatement of a checked state plan (contract section 9,
// `state_plan_summary`): one sentence per part, each with the JSON pointer of that part.
//
// Deterministic: generated from the conditions as written (Condition::raw) and the bounds, never
// from the LLM. Order: the initial state, the goal, the maintenance constraint (when it is not
// `true`), the episodes, the temporal constraints, the shared events. Bounds are always stated
// with their numbers, and worded apart: "exactly N s", "within 0 to N s" (at most), "at least
// N s" (an upper bound of 10,000,000 s, the largest allowed, reads as none), "between L and H s".
// Thread-safe; never throws.
#pragma once

#include <string>

#include "planner/model/domain.h"
#include "planner/model/json_io.h"
#include "planner/model/state_plan.h"

namespace ctb {

// [{"pointer", "text"}, ...]
Json SummarizeStatePlan(const Domain& d, const StatePlan& sp);

// A condition in words, read as at an event (a change reads "X goes from A to B").
std::string ConditionWords(const Domain& d, const StatePlan& sp, const Condition& c);

// A duration bound pair in words: "exactly 30 s", "within 0 to 60 s", ...
std::string BoundWords(double lower, double upper);

// Seconds as printed in sentences: "30", "0.5".
std::string SecondsText(double v);

}  // namespace ctb
