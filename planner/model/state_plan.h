// The state plan (contract section 3): initial state, end state, episodes, temporal constraints,
// shared events and the objective, checked against a domain.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/expr_check.h"

namespace ctb {

enum class Objective { kCost, kMakespan, kCostThenMakespan };
const char* ObjectiveName(Objective o);
std::optional<Objective> ParseObjective(const std::string& s);

// A checked condition. `raw` is the tree as written (what the verifier reads); `expr` is its
// normalised form (expr/normalize.h), which the split, the bounds and the encoder read. `info`
// describes `expr` but keeps raw's classification (change or state), so both mean the same.
struct Condition {
  std::string text;
  Expr expr;
  ExprInfo info;
  Expr raw;
  ExprInfo raw_info;
  std::string pointer;
};

struct Episode {
  std::string name;
  Condition accepting;
  Condition state;
  double lower = 0, upper = 0;  // seconds
};

struct Temporal {
  std::string name;
  Condition event1;
  Condition event2;
  double lower = 0, upper = 0;
};

enum class EndpointKind { kEpisodeStart, kEpisodeEnd, kEvent1, kEvent2 };

struct Endpoint {
  EndpointKind kind;
  int index;         // into episodes or temporals
  std::string text;  // as written, e.g. "ProjectorOn.end"
};

struct SharedEvent {
  std::string name;
  std::vector<Endpoint> endpoints;
};

struct StatePlan {
  std::vector<int> initial;  // location index per automaton of the domain
  Condition maintenance;
  Condition goal;
  std::vector<Episode> episodes;
  std::vector<Temporal> temporals;
  std::vector<SharedEvent> events;
  Objective objective = Objective::kCost;
};

// Loads and checks a state plan against d. Errors (with pointers and offsets) and warnings (a
// fixed stage index where [i] was likely meant) go to diags; nullopt on any error. Never throws.
std::optional<StatePlan> LoadStatePlan(const Json& j, const Domain& d, Diagnostics& diags);

// The contract's JSON form of a state plan (the texts as written).
Json StatePlanToJson(const StatePlan& sp, const Domain& d);

}  // namespace ctb
