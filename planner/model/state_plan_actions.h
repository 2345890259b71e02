// Internal to the model library: reading the state plan's action events, ordered temporal
// constraints, sequence and forbidden actions (contract section 15). LoadStatePlan calls these.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "planner/model/state_plan.h"

namespace ctb::actions {

// Reads a condition (ReadCondition of state_plan.cpp) at reader.Child(key).
using ConditionReader =
    std::function<std::optional<Condition>(const ObjectReader& reader, const std::string& key)>;

// A bound of an episode, temporal constraint or order: at most 10,000,000 s and a multiple of the
// domain's time resolution; false with an error at reader.Child(key) otherwise.
bool CheckBound(const ObjectReader& reader, const std::string& key, double v, const Domain& d,
                Diagnostics& diags);

// True when a `temporal` entry is an order (names an action, or "ordered": true): orders are
// kept apart from the thesis' temporal constraints (StatePlan::orders).
bool IsOrderEntry(const Json& entry);

// `constraints.actions`: each entry checked against d (located errors with suggestions; a
// transition no run can reach is a warning).
void ReadActions(const Json& group, const Domain& d, const std::vector<int>& initial, StatePlan& sp,
                 Diagnostics& diags);

// One ordered or action-based `temporal` entry.
void ReadOrder(const std::string& name, const Json& entry, const Domain& d, StatePlan& sp,
               const ConditionReader& read_condition, Diagnostics& diags);

// `constraints.sequence` and `constraints.forbidden`.
void ReadSequence(const Json& list, StatePlan& sp, Diagnostics& diags);
void ReadForbidden(const Json& list, StatePlan& sp, Diagnostics& diags);

// A shared event's endpoint that names an action ("R1Opens") or an order's end ("Then.event2").
// Returns false (nothing reported) when `text` names neither.
bool ResolveActionEndpoint(const std::string& text, const StatePlan& sp, const std::string& pointer,
                           Endpoint& out, Diagnostics& diags);

// The JSON of the action parts, as LoadStatePlan reads them, into `constraints`.
void ActionsToJson(const StatePlan& sp, const Domain& d, Json& constraints);

}  // namespace ctb::actions
