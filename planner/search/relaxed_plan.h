// Internal to the search library: the FF heuristic over the delete relaxation of the automata,
// evaluated from a search node. Facts are "automaton a is (has been) in location l"; one action
// per transition and per alternative of its guard (the positive location atoms it needs;
// commands and negations dropped, as in planner/analyze/relaxed_cost.cpp). From a node, the
// first transition of each automaton costs only the part of its lower duration not yet spent.
#pragma once

#include <utility>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"
#include "planner/search/expand.h"

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
  struct Action {
    std::vector<int> pre;  // facts; pre[0] is the source location
    int add = 0;
    int automaton = 0;
    int transition = 0;
    double cost = 0;  // from a location entered at the node's time
    long lo = 0;      // ticks
    bool choosable = false;
  };
  int Fact(int a, int l) const { return offset_[a] + l; }
  double ActionCost(const Action& act, const Node& n) const;
  void Needed(const Node& n, std::vector<int>& facts, double& wait) const;

  const Domain& d_;
  const StatePlan& sp_;
  Objective objective_;
  long tps_;
  std::vector<int> offset_;
  int facts_ = 0;
  std::vector<Action> actions_;
  std::vector<std::vector<int>> pre_of_;  // fact -> actions needing it
  std::vector<std::pair<int, int>> goal_;  // the end state's needed locations
  std::vector<std::vector<std::pair<int, int>>> ep_acc_, tc_ev1_, tc_ev2_;
};

}  // namespace ctb::search
