// Devices that take turns (issue 29 item 1), for the planner tests and bench/turns.py's shape:
// device k goes off -> (prep, prep_k s) -> warming (warm_k s) -> on [-> ready after tail_k s],
// started by its command; the state plan asks every device on (or ready) and allows one warm-up
// at a time (pairwise exclusions in the maintenance constraint, in the form asked). With `bypass`
// a device may also be switched from off to on directly, so it need not take a turn.
#pragma once

#include <string>
#include <vector>

#include "test_util.h"

namespace ctb::testing {

struct Device {
  int prep = 0, warm = 1, tail = 0;
  bool bypass = false;
};

// kNotAllThree: no three consecutive devices warm at once; kAtMostTwo (`not (a /\ b /\ c)`) and
// kAtMostTwoOr (`a != .. \/ b != .. \/ c != ..`): no three of all the devices warm at once.
enum class ExclusionForm { kNotBoth, kOrNot, kImplies, kNotAllThree, kAtMostTwo, kAtMostTwoOr };

struct TurnProblem {
  Domain domain;
  StatePlan plan;
};

inline Json TurnDomainJson(const std::vector<Device>& devs) {
  Json automata = Json::array();
  for (std::size_t k = 0; k < devs.size(); ++k) {
    const Device& v = devs[k];
    const std::string name = "dev" + std::to_string(k + 1);
    Json locs = {"off", "warming", "on"};
    Json ts = Json::array();
    const std::string start = name + "u[i]==start";
    if (v.prep > 0) {
      locs.push_back("prep");
      ts.push_back({{"from", "off"}, {"to", "prep"}, {"guard", start}});
      ts.push_back({{"from", "prep"}, {"to", "warming"}, {"duration", {v.prep, v.prep}}});
    } else {
      ts.push_back({{"from", "off"}, {"to", "warming"}, {"guard", start}});
    }
    ts.push_back({{"from", "warming"}, {"to", "on"}, {"duration", {v.warm, v.warm}}});
    if (v.tail > 0) {
      locs.push_back("ready");
      ts.push_back({{"from", "on"}, {"to", "ready"}, {"duration", {v.tail, v.tail}}});
    }
    Json cmds = {"start"};
    if (v.bypass) {
      cmds.push_back("skip");
      ts.push_back({{"from", "off"}, {"to", "on"}, {"guard", name + "u[i]==skip"}});
    }
    automata.push_back({{"name", name}, {"locations", locs}, {"commands", cmds}, {"transitions", ts}});
  }
  return {{"name", "turns"}, {"description", "devices that warm up one at a time"},
          {"automata", automata}};
}

inline std::string Warming(std::size_t k) { return "dev" + std::to_string(k + 1) + "l[i]==warming"; }
inline std::string NotWarming(std::size_t k) { return "dev" + std::to_string(k + 1) + "l[i]!=warming"; }

inline std::string TurnMaintenance(std::size_t n, ExclusionForm form) {
  std::string m;
  auto add = [&](const std::string& c) { m += (m.empty() ? "" : " /\\ ") + c; };
  if (form == ExclusionForm::kNotAllThree) {
    for (std::size_t a = 0; a + 2 < n; ++a)
      add("not (" + Warming(a) + " /\\ " + Warming(a + 1) + " /\\ " + Warming(a + 2) + ")");
    return m.empty() ? "true" : m;
  }
  if (form == ExclusionForm::kAtMostTwo || form == ExclusionForm::kAtMostTwoOr) {
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t b = a + 1; b < n; ++b)
        for (std::size_t c = b + 1; c < n; ++c)
          add(form == ExclusionForm::kAtMostTwo
                  ? "not (" + Warming(a) + " /\\ " + Warming(b) + " /\\ " + Warming(c) + ")"
                  : "(" + NotWarming(a) + " \\/ " + NotWarming(b) + " \\/ " + NotWarming(c) + ")");
    return m.empty() ? "true" : m;
  }
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) switch (form) {
        case ExclusionForm::kNotBoth: add("not (" + Warming(a) + " /\\ " + Warming(b) + ")"); break;
        case ExclusionForm::kOrNot: add("(" + NotWarming(a) + " \\/ " + NotWarming(b) + ")"); break;
        default: add("(" + Warming(a) + " -> " + NotWarming(b) + ")"); break;
      }
  return m.empty() ? "true" : m;
}

inline Json TurnPlanJson(const std::vector<Device>& devs, ExclusionForm form) {
  Json init = Json::object();
  std::string goal;
  for (std::size_t k = 0; k < devs.size(); ++k) {
    const std::string name = "dev" + std::to_string(k + 1);
    init[name] = "off";
    goal += (goal.empty() ? "" : " /\\ ") + name + "l[i+1]==" + (devs[k].tail > 0 ? "ready" : "on");
  }
  return {{"initial_state", init},
          {"end_state", {{"maintenance_constraint", TurnMaintenance(devs.size(), form)},
                         {"goal_constraint", goal}}},
          {"objective", "makespan"}};
}

inline TurnProblem MakeTurns(const std::vector<Device>& devs,
                             ExclusionForm form = ExclusionForm::kNotBoth) {
  Diagnostics diags;
  auto d = LoadDomain(TurnDomainJson(devs), diags);
  if (!d) {
    ADD_FAILURE() << AllErrors(diags);
    return {};
  }
  auto sp = LoadStatePlan(TurnPlanJson(devs, form), *d, diags);
  if (!sp) {
    ADD_FAILURE() << AllErrors(diags);
    return {};
  }
  return {*d, *sp};
}

}  // namespace ctb::testing
