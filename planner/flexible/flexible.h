// Flexible plans (contract section 13): the temporal network of a verified trajectory, whose every
// consistent schedule is again a valid trajectory, its windows (`slack`), and the way back from a
// schedule to a trajectory that the section-5 verifier can replay.
//
// The derivation keeps what the verifier reads and frees the rest (docs/uncertainty.md):
//   - one point per transition of the plan (the origin is point 0);
//   - every automaton's stays: its duration links (contingent ones as contingent links);
//   - orders that keep every value a rule reads: for each *observer* (an automaton's guards, a
//     state-plan condition) the transitions of the automata it reads keep their plan order, and
//     transitions at one plan event that one observer reads stay at one event ([0, 0]);
//   - automatic transitions fire when they are due: the cause the plan had (their duration from
//     entry, or the event that made their guard true) stays their cause, and a guard that held
//     before without firing keeps holding only while the clock is below its lower bound;
//   - controllable transitions never overstay their upper bound while enabled;
//   - episodes, temporal constraints, shared events and the goal as links between the points
//     that mark their events, `why` naming their JSON pointer.
// Where a plan uses what this does not model (a guard that reads another automaton's command on
// an automatic transition, a condition that reads accepting automata, a replan's history), the
// derivation falls back to *rigid order*: every transition keeps the plan's event order and
// only the times move. Both are sound; rigid order is less flexible.
//
// Thread-safe: plain functions over values. Never throws (allocation aside).
#pragma once

#include <optional>
#include <random>
#include <string>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/json_io.h"
#include "planner/model/state_plan.h"
#include "planner/model/trajectory.h"
#include "planner/network/network.h"

namespace ctb::flexible {

// Why a link is in the network, in the terms the conflict-directed search (cut.h) states of
// another plan; parallel to `net.links`.
enum class LinkSource {
  kOther,      // not restated (due, overstay, pins): a conflict naming it makes no cut
  kTrivial,    // holds in every plan (a link from the origin that only keeps a pointer)
  kDuration,   // a stay: from the automaton's previous transition (or the origin) to this one
  kKept,       // an observer's order or tie: the plan's event order of its two points
  kStatePlan,  // an episode's, temporal constraint's or order's bounds between its marks
  kGoalLast,   // an automaton's last transition, no later than the goal
};
struct LinkOrigin {
  LinkSource source = LinkSource::kOther;
  // The state plan's marks its ends must be for the link to be in another plan's network (their
  // `point` fields are unused here).
  std::optional<CutMark> from_mark, to_mark;
  bool strict_tick = false;  // its lb is the one tick an automatic transition's order adds
};

struct FlexiblePlan {
  network::Network net;                  // point 0 is the origin
  std::vector<LinkOrigin> origins;       // per link of net
  std::vector<int> point_event;          // the plan event of each point (origin: 0)
  std::vector<int> point_automaton;      // -1 for the origin
  std::vector<int> point_transition;     // index within the automaton's transitions; -1 origin
  // Pairs of points that must share one event (a [0, 0] link alone allows two events at one
  // time), and pairs whose event order must stay (first no later than second).
  std::vector<std::pair<int, int>> same_event;
  std::vector<std::pair<int, int>> before;
  // (cause, transition): an automatic transition due when `cause` made its guard true; at one
  // time it must be the very next event after its cause's.
  std::vector<std::pair<int, int>> due_after;
  // The points that mark the state plan's events (0: the origin, event 0).
  std::vector<std::pair<int, int>> episode_points;   // (start, end) per episode
  std::vector<std::pair<int, int>> temporal_points;  // (event1, event2) per temporal constraint
  std::vector<std::pair<int, int>> order_points;     // (event1, event2) per order
  int goal_point = 0;
  bool rigid = false;  // the fallback above was taken
  bool rigid_by_plan = false;  // ... because of where this plan's marks fall (another may not)
  // The automata of each observer the derivation has without rigid order: a rigid order kept
  // between two points holds in another plan's network when one of these reads both.
  std::vector<std::vector<int>> observers;
  // Points that mark a state-plan event although nothing the condition reads moves there (the
  // cause of rigid_by_plan): another plan's mark at the same event need not be tied to them.
  struct FallbackMark {
    int point = 0;
    CutMark mark;            // which event of the state plan it marks
    std::vector<int> reads;  // the automata its condition reads (none of them moves there)
  };
  std::vector<FallbackMark> fallback_marks;
  long tps = 1;        // the domain's ticks per second
  std::string rigid_reason;
};

// The network of a verified trajectory `t` of domain `d` (contingent transitions marked there)
// and state plan `sp`; times of `t` are domain ticks (tps a second). nullopt, with the reason in
// `why_not`, when the domain's resolution cannot be written in milliseconds (finer than 1 ms or
// not dividing a second into whole milliseconds).
std::optional<FlexiblePlan> DeriveNetwork(const Trajectory& t, const Domain& d, const StatePlan& sp,
                                          long tps, std::string* why_not = nullptr);

// The plan's own time of every point (network ticks): the schedule the network came from.
std::vector<network::Ticks> PlanTimes(const FlexiblePlan& f, const Trajectory& plan);

// Earliest and latest time of every point over all consistent schedules (contingent links read
// as requirements), in network ticks; nullopt when the network is inconsistent.
struct Window {
  network::Ticks earliest = 0;
  std::optional<network::Ticks> latest;  // nullopt: no upper bound
};
std::optional<std::vector<Window>> Windows(const network::Network& net);

// The contract's `slack`: [{"point", "earliest", "latest"}] in seconds (absolute plan times),
// every point but the origin.
Json SlackJson(const std::vector<Window>& windows);

// A random consistent schedule (every link as a requirement): points fixed one by one in plan
// order, each uniformly within its window given those fixed before (whole domain ticks).
// nullopt when the network is inconsistent. With `extremes`, each point at one end of its window
// (ties between points are then common). For tests and simulations; O(n^2 m).
std::optional<std::vector<network::Ticks>> SampleSchedule(const FlexiblePlan& f, std::mt19937& rng,
                                                          bool extremes = false);

// The trajectory of a schedule (a time per point, network ticks): events grouped so that tied
// points share one, ordered points keep their order at one time, and each event holds all that
// may happen at once. `plan` is the trajectory the network came from (its initial state, its
// episodes and temporal constraints' anchors). nullopt with `why_not` when the schedule breaks
// a tie or an order, or the plan had a history (replans are not rebuilt).
std::optional<Trajectory> ScheduleToTrajectory(const FlexiblePlan& f, const Trajectory& plan,
                                               const std::vector<network::Ticks>& times,
                                               std::string* why_not = nullptr);

}  // namespace ctb::flexible
