// Internal to the search library: search states and their successors under the verifier's rules
// (planner/verify/verifier.cpp is the reference for every rule applied here).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb::search {

constexpr long kNoTime = -1;

// The state plan's accepting automata as far as the run has gone. Event indices are -1 while
// unknown; an index known at a node is at most the node's event.
struct Monitors {
  std::vector<int> ep_start, ep_end;
  std::vector<long> ep_start_t;  // ticks, once started
  std::vector<int> tc_k1, tc_k2;  // the events at which event 1 / event 2 are accepted
  std::vector<long> tc_first_t;   // ticks, once active
  // Orders (contract section 15; actions as both ends): the events of their two ends, and their
  // times; for an `every` second end, ord_k2 is its last firing so far.
  std::vector<int> ord_k1, ord_k2;
  std::vector<long> ord_t1, ord_t2;
};

// A run up to its last event k (time `time`), standing on stage k.
struct Node {
  int parent = -1;
  int event = 0;
  long time = 0;
  long cost = 0;
  std::vector<int> loc;     // stage k
  std::vector<long> entry;  // when each automaton entered its location (ticks)
  std::vector<std::pair<int, int>> cmds_before;  // (automaton, command) of stage k-1, non-zero
  std::vector<std::pair<int, int>> fired;        // (automaton, transition) at event k
  Monitors mon;
  bool done = false;  // the end state is accepted at event k (k is the goal event)
};

// What a stage allows with every command the no-op: per automaton, the transitions leaving its
// location whose guard holds.
struct StageView {
  std::vector<std::vector<int>> enabled;
};

// A transition the planner may choose at a node (commanded with one command, or controllable),
// with the window of times it may fire in.
struct Candidate {
  int automaton = 0;
  int transition = 0;
  long earliest = 0;
  long latest = 0;  // kInfinity when unbounded
  // Commands given to other automata on the same stage because this transition's guard, and the
  // guards of the transitions those commands enable, read them (a PDDL action compiled onto
  // several objects, docs/pddl.md). A given command whose transition is enabled fires with it.
  std::vector<std::pair<int, int>> commands;  // (automaton, command)
  std::vector<std::pair<int, int>> with;      // the transitions those commands make fire

  // The transitions that fire together: this one and `with`.
  std::vector<std::pair<int, int>> Members() const {
    std::vector<std::pair<int, int>> all = {{automaton, transition}};
    all.insert(all.end(), with.begin(), with.end());
    return all;
  }
};

constexpr long kInfinity = 1L << 60;

class Expander {
 public:
  Expander(const Domain& d, const StatePlan& sp, long ticks_per_second);

  // Empty when the engine can run on this state plan; otherwise why not.
  const std::string& Declined() const { return declined_; }

  // The run of no events; nullopt when stage 0 already breaks the state plan.
  std::optional<Node> Root() const;

  // Replanning: no event after the start node may come before `t` (the history's now).
  void SetEarliest(long t) { earliest_ = t; }
  // A stage taken as reported (replanning's history, planner/search/history_nodes.h): only the
  // state plan's monitors are updated at it, no rule of the model is checked. False when the run
  // can no longer be valid.
  bool Reported(const Node* prev, Node& n) const { return UpdateMonitors(prev, n); }

  StageView View(const Node& n) const;
  std::vector<Candidate> Candidates(const Node& n, const StageView& v) const;
  // The next time an automatic transition is due with no command given; kInfinity when none is.
  long DueTime(const Node& n, const StageView& v) const;
  // The times (after the node's) at which automatic transitions enabled now are due.
  std::vector<long> DueTimes(const Node& n, const StageView& v) const;
  // The times (after the node's) at which an active episode or temporal constraint reaches its
  // lower bound.
  std::vector<long> Targets(const Node& n) const;

  // The next event at `time`, the chosen transitions firing there (their commands given on the
  // stage before), with whatever else must fire. nullopt when the verifier would refuse it.
  // `given`: (automaton, command) pairs given on the stage before without choosing a transition
  // (Candidate::commands); an enabled transition they command fires.
  std::optional<Node> Apply(const Node& parent, const StageView& v,
                            const std::vector<std::pair<int, int>>& chosen, long time,
                            const std::vector<std::pair<int, int>>& given = {}) const;

  // A key of the node's future: locations, clocks capped where no bound reads them further,
  // monitors with their relative times.
  std::vector<long> Key(const Node& n) const;

  long Ticks(double seconds) const;
  // The least time an automaton stays where transition ti takes it (the least lower duration of
  // the transitions out of its destination; 0 when there are none): firing ti that long before a
  // target time makes the next change land on it (an automatic shutdown ending on a deadline).
  long Lead(int a, int ti) const { return lead_[a][ti]; }
  const std::vector<int>& Outgoing(int a, int loc) const { return out_[a][loc]; }

 private:
  template <typename F>
  void ForEachDue(const Node& n, const StageView& v, F&& f) const;
  bool GuardHolds(const Transition& tr, const std::vector<int>& loc,
                  const std::vector<int>& cmd) const;
  std::vector<int> Enabled(int a, const std::vector<int>& loc, const std::vector<int>& cmd) const;
  // The commands the guards of c's transition and of the transitions they enable require of
  // other automata (RequiredCommand), filled into c.commands and c.with; false when a guard of
  // the group does not hold with them (two guards that want different commands of one automaton).
  bool Partners(const Node& n, Candidate& c, std::vector<int>& cmd) const;
  // The monitors' update at event j (the verifier's episode, temporal, goal and maintenance
  // rules); false when the run can no longer be valid.
  bool UpdateMonitors(const Node* prev, Node& n) const;
  bool AtEvent(const Condition& c, const Node* prev, const Node& n) const;
  bool OnStage(const Condition& c, const Node* prev, const Node& n) const;
  // A location read at fixed stage 0 (the only fixed stage followed): the initial location.
  int InitialValue(const Expr& atom) const;
  int AcceptingBefore(const Expr& atom, const Node* prev) const;

  const Domain& d_;
  const StatePlan& sp_;
  long tps_;
  long earliest_ = 0;
  std::string declined_;
  std::vector<std::vector<std::vector<int>>> out_;  // [automaton][location] -> transitions
  std::vector<std::vector<int>> readers_;           // automata whose guards read a's command
  std::vector<std::vector<long>> clock_cap_;        // [automaton][location]
  std::vector<std::vector<long>> lead_;             // [automaton][transition]
  std::vector<long> ep_lo_, ep_hi_, tc_lo_, tc_hi_;
  std::vector<long> ord_lo_, ord_hi_;           // ticks; kInfinity: no upper bound
  std::vector<std::vector<bool>> is_action_;    // [action][transition of its automaton]

  // The orders' and forbidden actions' rules at event j (the verifier's); false when broken.
  bool UpdateOrders(Node& n) const;
  bool Fires(int action, const Node& n) const;
  bool OrderAccepted(std::size_t q, const Monitors& m) const;
};

}  // namespace ctb::search
