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
  // The tree as written (unchecked), when the text has quantifiers (every/any, expr.h): the
  // restatement says them as written; raw and expr hold their expansion.
  std::optional<Expr> written;
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

// Action events (contract section 15): the event at which a transition of one automaton fires.
enum class Occurrence { kFirst, kLast, kEvery };
const char* OccurrenceName(Occurrence o);

struct ActionEvent {
  std::string name;
  int automaton = -1;
  std::vector<int> transitions;  // indices within the automaton; firing any of them counts
  Occurrence occurrence = Occurrence::kFirst;
  std::string command;           // as written ("" when given by from/to only)
  std::string from, to;          // as written ("" when not given)
  std::string pointer;           // /constraints/actions/<name>

  // True when transition `transition` of automaton `a` firing is this action.
  bool Names(int a, int transition) const;
};

// One end of an order: an action event, or (action < 0) an accepting condition.
struct OrderEnd {
  int action = -1;  // index into actions
  Condition condition;
};

// A temporal constraint that names an action or is `ordered`, or a step of `sequence`
// (contract section 15). Kept apart from the thesis' temporal constraints, whose either-order
// semantics every analysis reads; an analysis that ignores these only relaxes the problem.
// Events (deterministic, so the encoder and the verifier agree on them):
//  - an action end: its first / last firing; `every`: only as `second` of an ordered one;
//  - a condition as `first` of an ordered one: the first event at which it holds;
//  - a condition as `second`: the earliest event at or after the other end (after it, when
//    strict) at which it holds and the lower bound has passed;
//  - either order (`ordered` false, at least one action end): a condition end is the first
//    event it holds when that is not after the action's event, else as a `second` above.
struct Order {
  std::string name;     // the temporal constraint's name; "" for a sequence step
  OrderEnd first, second;
  bool ordered = true;  // false: either order
  bool strict = false;  // sequence: `second` at a later event than `first`
  double lower = 0;
  std::optional<double> upper;  // nullopt: unbounded
  std::string pointer;  // /constraints/temporal/<name> or /constraints/sequence/<k>
};

enum class EndpointKind { kEpisodeStart, kEpisodeEnd, kEvent1, kEvent2, kAction, kOrder1, kOrder2 };

struct Endpoint {
  EndpointKind kind;
  int index;         // into episodes, temporals, actions or orders
  std::string text;  // as written, e.g. "ProjectorOn.end"
};

struct SharedEvent {
  std::string name;
  std::vector<Endpoint> endpoints;
};

// A cut of the conflict-directed search among plans (planner/flexible/cut.h, solve/
// controllable.cpp): no plan may contain this pattern. Never read from JSON: the search adds cuts
// to its own copy of a state plan, and only the MiniZinc encoding reads them (the engines that do
// not decline, as for action rules). A plan contains the pattern when its transitions can be
// assigned to the points so that every literal holds.
struct CutPoint {
  int automaton = -1;   // -1: the origin (event 0)
  int transition = -1;  // index within the automaton's transitions
};
struct CutMark {
  enum class Kind { kEndpoint, kGoal };
  Kind kind = Kind::kEndpoint;
  EndpointKind endpoint = EndpointKind::kEpisodeStart;  // kEndpoint: EP_S, EP_E, TC_1, TC_2, AK, O_1, O_2
  int index = 0;
  int point = 0;  // the mark's event is this point's
};
struct PlanCut {
  std::vector<CutPoint> points;
  std::vector<std::pair<int, int>> same;    // one event
  std::vector<std::pair<int, int>> before;  // first at an earlier event
  std::vector<std::pair<int, int>> next;    // second is its automaton's very next transition
  std::vector<int> first;                   // its automaton's first transition
  std::vector<int> last;                    // its automaton's last transition
  std::vector<CutMark> marks;
  std::vector<std::pair<int, int>> quiet;   // (point, automaton): that automaton does not move there
};

struct StatePlan {
  std::vector<int> initial;  // location index per automaton of the domain
  Condition maintenance;
  Condition goal;
  std::vector<Episode> episodes;
  std::vector<Temporal> temporals;
  std::vector<SharedEvent> events;
  // Shared events with an action's or an order's endpoint (contract section 15): apart from
  // `events`, which every analysis reads, so that ignoring them relaxes the problem.
  std::vector<SharedEvent> action_events;
  std::vector<ActionEvent> actions;
  std::vector<Order> orders;
  std::vector<int> sequence;   // indices into actions, as written (its steps are in orders)
  std::vector<int> forbidden;  // indices into actions: none of their transitions may fire
  Objective objective = Objective::kCost;
  std::vector<PlanCut> cuts;  // internal: the conflict-directed search's (never from JSON)

  // True when the state plan orders or forbids actions (the engines that do not read these
  // decline: the first-plan engine, z3, the split into parts, symmetry breaking).
  // Cuts (above) count as such rules.
  bool HasActionRules() const {
    return !orders.empty() || !forbidden.empty() || !action_events.empty() || !cuts.empty();
  }
  // Both lists of shared events, `events` first.
  std::vector<const SharedEvent*> AllSharedEvents() const;
};

// Loads and checks a state plan against d. Errors (with pointers and offsets) and warnings (a
// fixed stage index where [i] was likely meant) go to diags; nullopt on any error. Never throws.
std::optional<StatePlan> LoadStatePlan(const Json& j, const Domain& d, Diagnostics& diags);

// The contract's JSON form of a state plan (the texts as written).
Json StatePlanToJson(const StatePlan& sp, const Domain& d);

}  // namespace ctb
