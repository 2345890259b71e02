// Automata that take turns (issue 29 item 1): a lower bound on the makespan when the state plan's
// maintenance constraint keeps some locations from being occupied at once (one warm-up at a
// time, one robot in a doorway).
//
// The maintenance constraint holds on every stage before the goal event, so two locations it
// excludes pairwise (a conjunct `not (a[i]==l /\ b[i]==m)`, `a[i]!=l \/ b[i]!=m` or
// `a[i]==l -> b[i]!=m`) are never occupied on one stage: their visits before the goal are
// disjoint in time. A set of locations excluded pairwise (a clique; two locations of one automaton
// are exclusive by themselves) is a machine that serves one visit at a time. A location is a job
// on it when its automaton must visit it: the goal pins the automaton elsewhere, it does not
// start there, and no path of its graph reaches the goal's location without passing through it.
// A job j is released at r_j (the earliest arrival, analyze/earliest.h), lasts at least p_j (the
// least lower duration of a transition out of the location) and leaves a tail of at least q_j (the
// fastest way on from there to the goal's location). Every set of jobs is then served one after
// another, so for all R and Q
//   goal >= R + sum{p_j : r_j >= R, q_j >= Q} + Q
// (the one-machine bound of scheduling; the last of those jobs to end still has its tail to go).
// A visit is one stay, so with at most 8 jobs on a machine the bound is the exact optimum of the
// machine without preemption instead: the best order, each job as early as its release and the
// job before allow (every order is tried; an order's value is its latest end plus tail).
// At most k at once (issue 29 item 1): a conjunct `not (A1 /\ ... /\ Am)` or
// `not A1 \/ ... \/ not Am` (m >= 3 locations of distinct automata) keeps the m from being
// occupied together: at most m - 1 of them at once. A pool of jobs in which every k + 1 form such
// a group (k = m - 1) is k machines, and for all R and Q
//   goal >= R + ceil(sum{p_j : r_j >= R, q_j >= Q} / k) + Q,   and goal >= r_j + p_j + q_j
// (their work fits between R and goal - Q on k machines).
// Counts time only; sound whatever the guards say, since it only drops constraints.
#pragma once

#include "planner/analyze/earliest.h"
#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb {

struct TurnBound {
  long makespan_ticks = 0;  // no plan accepts its end state earlier
  int machines = 0;         // cliques of excluded locations that held at least two jobs
  int jobs = 0;             // jobs on the clique that gave the bound
};

// `ticks`: the earliest arrivals in ticks (nullptr: every release at 0). No bound (all zero) for a
// goal that reads a change or a maintenance constraint that excludes nothing.
TurnBound ComputeTurnBound(const Domain& d, const StatePlan& sp, const EarliestTimes* ticks);

}  // namespace ctb
