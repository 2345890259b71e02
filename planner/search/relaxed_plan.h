// Internal to the search library: the FF heuristic over the delete relaxation of the automata,
// evaluated from a search node. Facts are "automaton a is (has been) in location l"; one action
// per transition and per alternative of its guard (the positive location atoms it needs;
// commands and negations dropped, as in planner/analyze/relaxed_cost.cpp). From a node, the
// first transition of each automaton costs only the part of its lower duration not yet spent.
// What the state plan still needs is read as clauses (goal_clauses.h): each clause gets one fact,
// cheapest first, one location per automaton within a condition, and facts another condition's
// choice already brought cost nothing more.
//
// For makespan, transitions that fire on one event by construction (a commanded transition whose
// guard requires another automaton's command, and that automaton's transitions on it: a PDDL
// action compiled onto several objects) are one event of the relaxed plan: it costs the longest of
// them once, not their sum (an action's end moving three automata is one wait of its duration).
// An automaton whose every way out of its location has closed (each transition's upper duration
// bound already passed) stays there: its transitions are left out of the relaxation, so a run
// that let an action's end go by is seen to be dead.
//
// The goal's top-level "a != l" atoms (an imported PDDL model's "no action still runs": not in a
// step location) are needs too: an automaton in such a location needs the cheapest other location
// the goal allows, so the relaxed plan counts the end of a running action and sees when it can
// never come.
#pragma once

#include <utility>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"
#include "planner/search/expand.h"
#include "planner/search/goal_clauses.h"

namespace ctb::search {

struct Estimate {
  bool dead = false;  // some needed location is unreachable even in the relaxation: prune
  double h = 0;
  // Transitions of the relaxed plan the planner can choose now (commanded or controllable, from
  // the automaton's current location, every needed location already held): (automaton, index).
  std::vector<std::pair<int, int>> helpful;
};

class RelaxedPlan {
 public:
  RelaxedPlan(const Domain& d, const StatePlan& sp, Objective objective, long ticks_per_second);
  Estimate Evaluate(const Node& n) const;

 private:
  // What each condition needs, and whether it is read on one stage (not a change).
  struct Need {
    Clauses clauses;
    bool one_stage = true;
  };
  struct Action {
    std::vector<int> pre;  // facts; pre[0] is the source location
    int add = 0;
    int automaton = 0;
    int transition = 0;
    double cost = 0;  // from a location entered at the node's time
    long lo = 0;      // ticks
    bool choosable = false;
    int group = 0;    // the event it fires on (see above); its own when it has no partners
    long hi = -1;     // ticks; -1 when unbounded
  };
  int Fact(int a, int l) const { return offset_[a] + l; }
  double ActionCost(const Action& act, const Node& n) const;
  // The conditions still to be met at n (the goal first), and the time that must still pass.
  void Needed(const Node& n, std::vector<const Need*>& needed, double& wait) const;
  // The facts the relaxed plan supports; false when some clause cannot be reached.
  bool Targets(const Node& n, const std::vector<double>& cost, std::vector<int>& facts,
               double& wait) const;

  const Domain& d_;
  const StatePlan& sp_;
  Objective objective_;
  long tps_;
  std::vector<int> offset_;
  int facts_ = 0;
  int groups_ = 0;
  std::vector<Action> actions_;
  std::vector<std::vector<int>> pre_of_;  // fact -> actions needing it
  std::vector<std::vector<int>> out_of_;  // fact (a location) -> actions leaving it
  std::vector<std::vector<int>> stays_;   // automaton -> its actions
  Need goal_;  // what the end state needs
  // Per automaton, the locations the goal's top-level conjuncts refuse ("a != l"); empty when none.
  std::vector<std::vector<char>> refused_;
  std::vector<Need> ep_acc_, tc_ev1_, tc_ev2_;
};

}  // namespace ctb::search
