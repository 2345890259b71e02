// PddlPlan: a trajectory of an imported model as a PDDL 2.1 plan (import.h).
#include <algorithm>
#include <cstdio>
#include <map>
#include <tuple>

#include "interchange/pddl/import.h"

namespace ctb::pddl {

namespace {

std::string Seconds(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f", t);
  return buf;
}

// One transition of a timing automaton on an action's command.
struct Mark {
  double time = 0;
  long event = 0;
  const PlanAction* action = nullptr;
};

}  // namespace

std::string PddlPlan(const Json& trajectory, const std::vector<PlanAction>& actions) {
  std::map<std::pair<std::string, std::string>, const PlanAction*> by_key;
  for (const auto& a : actions) by_key[{a.automaton, a.command}] = &a;
  std::vector<Mark> marks;
  if (trajectory.is_object() && trajectory.contains("transitions") &&
      trajectory["transitions"].is_array())
    for (const auto& t : trajectory["transitions"]) {
      if (!t.contains("command") || !t["command"].is_string()) continue;
      auto it = by_key.find({t.value("automaton", ""), t["command"].get<std::string>()});
      if (it == by_key.end() || !t["time"].is_number()) continue;
      marks.push_back(Mark{t["time"].get<double>(), t.value("event", 0L), it->second});
    }
  std::stable_sort(marks.begin(), marks.end(), [](const Mark& a, const Mark& b) {
    return std::tie(a.time, a.event) < std::tie(b.time, b.event);
  });
  // A durative action's marks alternate start, end (no action overlaps itself).
  std::map<const PlanAction*, std::size_t> open;  // action -> index of its start line
  std::vector<std::tuple<double, std::string, std::string>> lines;  // time, action, duration
  std::vector<bool> ended;
  for (const Mark& m : marks) {
    if (!m.action->durative) {
      lines.emplace_back(m.time, m.action->pddl, "");
      ended.push_back(true);
      continue;
    }
    auto it = open.find(m.action);
    if (it == open.end()) {
      open[m.action] = lines.size();
      lines.emplace_back(m.time, m.action->pddl, "");
      ended.push_back(false);
    } else {
      auto& [start, pddl, duration] = lines[it->second];
      duration = " [" + Seconds(m.time - start) + "]";
      ended[it->second] = true;
      open.erase(it);
    }
  }
  std::string out;
  for (std::size_t k = 0; k < lines.size(); ++k)
    if (ended[k])
      out += Seconds(std::get<0>(lines[k])) + ": " + std::get<1>(lines[k]) + std::get<2>(lines[k]) +
             "\n";
  return out;
}

}  // namespace ctb::pddl
