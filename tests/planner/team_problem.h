// The `assign` family of bench/families.py, for the planner tests: a team of n robots
// (config/templates/search_rescue_team.json) where robot k's timed moves take (k-1) mod 3 + 1
// times as long, and the goal "every person rescued by some robot" (which robot rescues whom is
// free). With three robots or more the optimum makespan is 30: the slowest robot (three times
// slower) still has to rescue someone, through the door the fast robot opened.
// CostTeam is the `cost` family (issue 29 item 2): the same speeds, robot k's moves cost 3, 2 or 1
// each (the fast robots dearest) and the last leg to person p (p-1) mod 3 + 1 times that, with
// `persons` persons (fewer than robots: the `cost_spare` family).
#pragma once

#include <string>

#include "planner/model/templates.h"
#include "test_util.h"

namespace ctb::testing {

struct TeamProblem {
  Domain domain;
  StatePlan plan;
};

inline TeamProblem MakeTeam(int n, bool costs, int persons) {
  Diagnostics d;
  auto t = ReadJsonFile(ConfigDir() + "/templates/search_rescue_team.json", d);
  ExpandOptions o;
  o.parameters["N"] = n;
  auto x = t ? ExpandTemplates(*t, d, o) : std::nullopt;
  if (!x) {
    ADD_FAILURE() << AllErrors(d);
    return {};
  }
  Json doc = x->document;
  for (Json& a : doc["automata"]) {
    const std::string name = a["name"];
    if (name.rfind("robot", 0) != 0) continue;
    const int factor = 1 + (std::stoi(name.substr(5)) - 1) % 3;
    for (Json& tr : a["transitions"])
      if (tr.contains("duration"))
        for (Json& v : tr["duration"])
          if (!v.is_null()) v = v.get<double>() * factor;
    if (!costs) continue;
    const int rate = 4 - factor;
    for (Json& tr : a["transitions"]) {
      const std::string to = tr["to"];
      const bool last = to.rfind("rescuedPerson", 0) == 0;
      tr["cost"] = last ? rate * (1 + (std::stoi(to.substr(13)) - 1) % 3) : rate;
    }
  }
  Json init = {{"door1", "closed"}, {"door2", "closed"}, {"door3", "open"}};
  std::string goal;
  for (int k = 1; k <= n; ++k) init["robot" + std::to_string(k)] = "outside";
  for (int p = 1; p <= persons; ++p) {
    std::string any;
    for (int k = 1; k <= n; ++k)
      any += (k > 1 ? " \\/ " : "") + ("robot" + std::to_string(k)) + "l[i+1]==rescuedPerson" +
             std::to_string(p);
    goal += (p > 1 ? " /\\ (" : "(") + any + ")";
  }
  Json sp = {{"initial_state", init},
             {"end_state", {{"maintenance_constraint", "true"}, {"goal_constraint", goal}}}};
  auto dom = LoadDomain(doc, d);
  auto plan = dom ? LoadStatePlan(sp, *dom, d) : std::nullopt;
  if (!plan) {
    ADD_FAILURE() << AllErrors(d);
    return {};
  }
  return {std::move(*dom), std::move(*plan)};
}

inline TeamProblem MixedSpeedTeam(int n) { return MakeTeam(n, false, n); }
inline TeamProblem CostTeam(int robots, int persons) { return MakeTeam(robots, true, persons); }

}  // namespace ctb::testing
