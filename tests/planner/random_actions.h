// Random action rules (contract section 15) for the random problems of random_problem.h: up to
// two actions of the problem's automata (by command or by from/to; first, last or every), then
// one of: forbidden, a sequence, an order in either order, an ordered one with a condition as its
// second end, an ordered one between the two actions. Deterministic for the generator's state.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "planner/model/domain.h"

namespace ctb::testing {

inline Json RandomActionRules(const Json& domain_json, const Domain& d, std::mt19937& rng) {
  auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  (void)domain_json;
  Json actions = Json::object();
  std::vector<std::string> names, occurrences;
  for (int n = 0; n < 2; ++n) {
    const int a = static_cast<int>(pick(d.automata.size()));
    const Automaton& au = d.automata[a];
    if (au.transitions.empty()) continue;
    const Transition& t = au.transitions[pick(au.transitions.size())];
    Json act = {{"automaton", au.name}};
    if (t.commanded && t.command > 0 && pick(2) == 0) {
      act["command"] = au.commands[t.command - 1];
    } else {
      act["from"] = au.locations[t.from];
      act["to"] = au.locations[t.to];
    }
    const char* occ[] = {"first", "first", "last", "every"};
    std::string o = occ[pick(4)];
    if (o != "first") act["occurrence"] = o;
    const std::string name = "Act" + std::to_string(n);
    actions[name] = act;
    names.push_back(name);
    occurrences.push_back(o);
  }
  Json c = {{"actions", actions}};
  if (names.size() < 2) {
    if (!names.empty()) c["forbidden"] = {names[0]};
    return c;
  }
  const bool every0 = occurrences[0] == "every", every1 = occurrences[1] == "every";
  Json order = {{"event1", names[0]}, {"event2", names[1]}, {"lower_bound", static_cast<int>(pick(3))}};
  if (pick(2)) order["upper_bound"] = order["lower_bound"].get<int>() + static_cast<int>(pick(3));
  switch (pick(5)) {
    case 0:  // forbidden
      c["forbidden"] = {names[pick(2)]};
      break;
    case 1:  // a sequence
      if (every0 || every1) c["forbidden"] = {names[0]};
      else c["sequence"] = {names[0], names[1]};
      break;
    case 2:  // either order
      if (every0 || every1) break;
      c["temporal"] = {{"Either", order}};
      break;
    case 3:  // ordered, a condition as the second end
      if (every0) break;
      order.erase("event2");
      order["accepting_event2_constraint"] = domain_json["automata"][0]["name"].get<std::string>() +
                                             "[i+1]==" + d.automata[0].locations[pick(d.automata[0].locations.size())];
      order["ordered"] = true;
      c["temporal"] = {{"Then", order}};
      break;
    default:  // ordered actions
      if (every0) break;
      order["ordered"] = true;
      c["temporal"] = {{"Then", order}};
  }
  return c;
}

// Adds `rules` (RandomActionRules) to a state plan's JSON, keeping its own temporal entries.
inline void AddActionRules(Json& state_plan, const Json& rules) {
  Json& constraints = state_plan["constraints"];
  if (!constraints.is_object()) constraints = Json::object();
  for (auto& [k, v] : rules.items()) {
    if (k == "temporal" && constraints.contains("temporal"))
      for (auto& [n, t] : v.items()) constraints["temporal"][n] = t;
    else constraints[k] = v;
  }
}

}  // namespace ctb::testing
