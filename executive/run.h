// The executive's decisions for one execution (contract section 14), as plain logic over values:
// no clock, no thread, no store, no device. app/ drives it (a thread per live execution, the
// store, the adapters); tests drive it with hand-made times.
//
// A Run holds the plan being dispatched (a section-5 answer with its `network` and `slack`), what
// the devices reported, what was dispatched, and the transitions reported blocked. At each moment:
//   - a commanded transition is dispatched once every point its network orders before it has
//     happened and its window, given what has happened (the network with those times fixed and
//     every other point not before now), has opened;
//   - a report that is the automaton's next planned transition, at a time inside the plan's slack
//     for it and with a consistent schedule left for the rest, moves nothing;
//   - anything else (another transition, a time outside the slack, a failed move, a planned
//     transition overdue) asks for a replan (contract section 11) from the history so far.
// Times are plan seconds (e[0] = 0 is when the execution started). Thread-compatible (one caller
// at a time). Never throws (allocation aside).
#pragma once

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "planner/flexible/flexible.h"
#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/json_io.h"
#include "planner/network/network.h"

namespace ctb::exec {

enum class State { kRunning, kSucceeded, kFailed, kStopped };
const char* StateName(State s);
std::optional<State> ParseState(const std::string& s);

// A command for a device: {"command", "from", "to", "at"} on the wire (plus the automaton).
struct Command {
  std::string automaton, command, from, to;
  double at = 0;
  Json ToJson() const;  // {"automaton", "command", "from", "to", "at"}
};

// What a device said (contract 14): a transition done (`location`) or a move it cannot make
// (`failed`, a command), at plan time `time`.
struct Report {
  std::string automaton;
  std::optional<std::string> location;
  std::optional<std::string> failed;
  double time = 0;
  Json ToJson() const;  // {"automaton", "location" | "failed", "time"}
  bool operator==(const Report& o) const {
    return automaton == o.automaton && location == o.location && failed == o.failed && time == o.time;
  }
};

// Parses {"automaton", "location" | "failed", "time"} strictly (unknown keys, wrong types,
// both or neither of location and failed); errors at prefix + "/<field>". nullopt on error.
std::optional<Report> ParseReport(const Json& j, const std::string& prefix, Diagnostics& diags);

// What Advance decided.
struct Decision {
  std::vector<Command> dispatch;      // send these now (already recorded as dispatched)
  std::optional<std::string> replan;  // why the plan must be replanned now
  bool finished = false;              // every point of the plan happened: succeeded
};

// What a report did.
struct Applied {
  bool duplicate = false;             // equal to a stored report: nothing changed
  std::optional<std::string> replan;  // why it asks for a replan
};

class Run {
 public:
  explicit Run(const Domain& d) : d_(&d) {}

  // Takes `plan` (a section-5 answer with `network`, `slack`, `transitions` and `timelines`) as
  // the plan to dispatch from `now`. Its transitions marked "executed" are the history. The first
  // plan also sets every automaton's starting location. kInternal when the plan lacks a network.
  std::optional<Error> Adopt(const Json& plan, double now);

  // After adopting a plan made from the first `from` entries of the history: the later entries
  // (reports that came while it was made) taken as its next transitions where they are; false
  // when one is not, and the plan must be made again.
  bool Replay(std::size_t from);

  // Dispatch decisions at `now` (call after every change and at NextWake()).
  Decision Advance(double now);
  // The next moment Advance may decide something without a report (a window opening, a planned
  // transition becoming overdue); nullopt when only a report can move things.
  std::optional<double> NextWake(double now) const;

  // Checks a report against the domain and what happened (errors at prefix + "/<field>"), then
  // records it. A report equal to a stored one is a duplicate and changes nothing.
  std::variant<Applied, Error> Apply(const Report& r, double now, const std::string& prefix = "");

  // The replanning request (contract 11) from what happened: {now, executed, blocked, trajectory}.
  Json ReplanRequest(double now) const;

  // How late a device's report may describe a moment (transport and reaction, plan seconds);
  // a report that late is still on time, and a planned transition is overdue only after it.
  void SetGrace(double seconds) { grace_ = static_cast<network::Ticks>(seconds * network::kTicksPerSecond); }

  // For a simulated team (sim.h): every point of the plan (index 0, the origin, has automaton
  // "") and, given what happened, each point's window at `now`.
  struct PointView {
    std::string automaton, from, to, command;  // command "": the device moves on its own
    bool contingent = false;
    int activation = -1;   // contingent: the point its duration runs from
    double lb = 0, ub = 0;  // contingent: its duration's bounds
    bool ready = false;     // its turn has come (a command: to be sent; a device: to move)
    std::optional<double> at, sent;
  };
  std::vector<PointView> Points() const;
  struct WindowView {
    double earliest = 0;
    std::optional<double> latest;
  };
  std::optional<std::vector<WindowView>> WindowsAt(double now) const;

  void Finish(State s, std::string why = "");
  State state() const { return state_; }
  const std::string& why() const { return why_; }
  const Json& plan() const { return plan_; }
  const Json& history() const { return history_; }
  const std::vector<Report>& reports() const { return reports_; }

  // The whole state as JSON and back (the store's copy); FromJson refuses a document it cannot
  // read (kInternal naming what).
  Json ToJson() const;
  std::optional<Error> FromJson(const Json& j);

 private:
  struct Point {
    int automaton = -1;  // -1: the origin
    int from = -1, to = -1;
    std::string command;                 // "" when the device moves on its own
    std::optional<network::Ticks> at;    // when it happened (reported)
    std::optional<network::Ticks> sent;  // when its command was dispatched
  };

  std::optional<Error> ReadPlan(const Json& plan);
  network::Network Remainder(network::Ticks now) const;
  int NextPointOf(int automaton) const;  // the first point of the automaton not yet happened
  bool AllHappened() const;
  bool Ready(int q) const;
  bool DeviceReady(int q) const;
  network::Ticks OnGrid(double now) const;  // now, down to the domain's resolution
  std::string Describe(int q) const;
  std::string WhyInconsistent(network::Ticks now) const;
  std::optional<std::vector<flexible::Window>> HappenedWindows() const;

  const Domain* d_;
  State state_ = State::kRunning;
  std::string why_;
  Json plan_;
  Json history_ = Json::array();  // contract 11's executed list
  Json blocked_ = Json::array();
  std::vector<Report> reports_;
  std::vector<int> location_;       // every automaton's current location
  std::vector<network::Ticks> entered_;  // when it entered it
  network::Network net_;
  std::vector<Point> points_;
  network::Ticks grace_ = network::kTicksPerSecond / 2;
  network::Ticks floor_ = 0;  // no point of the plan still to come happens before this
};

}  // namespace ctb::exec
