#include "planner/replan/diff.h"

#include <map>
#include <tuple>

namespace ctb::replan {

namespace {

struct Item {
  std::string automaton, from, to;
  Json command;
  Json time;   // seconds, as in the answer
  double t = 0;
  bool used = false;
};

Json ItemJson(const Item& i, const Json& before, const Json& after) {
  Json j = {{"automaton", i.automaton}, {"from", i.from}, {"to", i.to}};
  if (i.command.is_string()) j["command"] = i.command;
  if (!before.is_null()) j["time_before"] = before;
  if (!after.is_null()) j["time_after"] = after;
  return j;
}

}  // namespace

Json DiffAgainstPrevious(const Trajectory& plan, const Domain& d, const Situation& s) {
  using Key = std::tuple<std::string, std::string, std::string>;
  std::map<Key, std::vector<Item>> before, after;
  for (const auto& p : s.baseline) {
    const Automaton& au = d.automata[p.automaton];
    const Transition& t = au.transitions[p.transition];
    Item i{au.name, au.locations[t.from], au.locations[t.to], Json(), Json(), 0, false};
    if (t.commanded && t.command > 0) i.command = au.commands[t.command - 1];
    i.t = static_cast<double>(p.time) / static_cast<double>(s.tps);
    i.time = s.tps == 1 ? Json(p.time) : Json(i.t);
    before[{i.automaton, i.from, i.to}].push_back(i);
  }
  const int p = plan.history ? plan.history->events() : 0;
  for (const auto& f : plan.fired) {
    if (f.event <= p) continue;  // executed
    const Automaton& au = d.automata[f.automaton];
    const Transition& t = au.transitions[f.transition];
    Item i{au.name, au.locations[t.from], au.locations[t.to], Json(), Json(), 0, false};
    const int cmd = plan.commands[f.automaton][f.event - 1];
    if (t.commanded && cmd > 0) i.command = au.commands[cmd - 1];
    const long ticks = plan.events[f.event];
    i.t = static_cast<double>(ticks) / static_cast<double>(s.tps);
    i.time = s.tps == 1 ? Json(ticks) : Json(i.t);
    after[{i.automaton, i.from, i.to}].push_back(i);
  }
  Json kept = Json::array(), moved = Json::array(), added = Json::array(), dropped = Json::array();
  for (auto& [key, news] : after) {
    auto& olds = before[key];
    for (auto& n : news)
      for (auto& o : olds)
        if (!o.used && o.t == n.t) {
          o.used = n.used = true;
          kept.push_back(ItemJson(n, o.time, n.time));
          break;
        }
    auto o = olds.begin();
    for (auto& n : news) {
      if (n.used) continue;
      while (o != olds.end() && o->used) ++o;
      if (o == olds.end()) {
        added.push_back(ItemJson(n, Json(), n.time));
        continue;
      }
      o->used = n.used = true;
      moved.push_back(ItemJson(n, o->time, n.time));
    }
  }
  for (auto& [key, olds] : before)
    for (auto& o : olds)
      if (!o.used) dropped.push_back(ItemJson(o, o.time, Json()));
  return {{"kept", kept}, {"moved", moved}, {"added", added}, {"dropped", dropped}};
}

long Changes(const Json& diff) {
  return static_cast<long>(diff["moved"].size() + diff["added"].size() + diff["dropped"].size());
}

}  // namespace ctb::replan
