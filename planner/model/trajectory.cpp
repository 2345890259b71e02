#include "planner/model/trajectory.h"

#include <cmath>

namespace ctb {

namespace {

double Seconds(long ticks, long tps) { return static_cast<double>(ticks) / static_cast<double>(tps); }

Json Time(long ticks, long tps) {
  if (tps == 1) return ticks;
  return Seconds(ticks, tps);
}

}  // namespace

long TrajectoryCost(const Trajectory& t, const Domain& d) {
  long c = 0;
  for (const auto& f : t.fired) c += d.automata[f.automaton].transitions[f.transition].cost;
  return c;
}

Json TrajectoryToJson(const Trajectory& t, const Domain& d, const StatePlan& sp, long tps) {
  Json out;
  const int g = t.goal_event;
  out["horizon"] = t.horizon;
  out["goal_reached_at"] = Time(t.events[g], tps);
  Json events = Json::array();
  for (long e : t.events) events.push_back(Time(e, tps));
  out["events"] = events;
  Json timelines = Json::object();
  for (std::size_t a = 0; a < d.automata.size(); ++a) {
    Json segs = Json::array();
    int start = 0;
    for (int k = 1; k <= g + 1; ++k) {
      if (k <= g && t.locations[a][k] == t.locations[a][start]) continue;
      long end = k <= g ? t.events[k] : t.events[g];
      segs.push_back({{"location", d.automata[a].locations[t.locations[a][start]]},
                      {"start", Time(t.events[start], tps)},
                      {"end", Time(end, tps)}});
      start = k;
    }
    timelines[d.automata[a].name] = segs;
  }
  out["timelines"] = timelines;
  Json transitions = Json::array();
  const int p = t.history ? t.history->events() : 0;
  std::size_t next_jump = 0;
  auto jumps_before = [&](int event) {
    if (!t.history) return;
    const auto& jumps = t.history->jumps;
    for (; next_jump < jumps.size() && jumps[next_jump].event < event; ++next_jump) {
      const ObservedJump& j = jumps[next_jump];
      const Automaton& a = d.automata[j.automaton];
      transitions.push_back({{"time", Time(t.events[j.event], tps)}, {"event", j.event},
                             {"automaton", a.name}, {"from", a.locations[j.from]},
                             {"to", a.locations[j.to]}, {"command", nullptr},
                             {"observed", true}});
    }
  };
  for (const auto& f : t.fired) {
    jumps_before(f.event + 1);
    const Automaton& a = d.automata[f.automaton];
    const Transition& tr = a.transitions[f.transition];
    Json j = {{"time", Time(t.events[f.event], tps)}, {"event", f.event},
              {"automaton", a.name}, {"from", a.locations[tr.from]}, {"to", a.locations[tr.to]}};
    int cmd = t.commands[f.automaton][f.event - 1];
    j["command"] = tr.commanded && cmd > 0 ? Json(a.commands[cmd - 1]) : Json();
    if (f.event <= p) j["executed"] = true;
    transitions.push_back(j);
  }
  jumps_before(g + 1);
  out["transitions"] = transitions;
  Json eps = Json::object(), tcs = Json::object();
  for (std::size_t p = 0; p < sp.episodes.size(); ++p)
    eps[sp.episodes[p].name] = {{"start", Time(t.events[t.episodes[p].first], tps)},
                                {"end", Time(t.events[t.episodes[p].second], tps)},
                                {"start_event", t.episodes[p].first},
                                {"end_event", t.episodes[p].second}};
  for (std::size_t q = 0; q < sp.temporals.size(); ++q)
    tcs[sp.temporals[q].name] = {{"event1", Time(t.events[t.temporals[q].first], tps)},
                                 {"event2", Time(t.events[t.temporals[q].second], tps)},
                                 {"event1_event", t.temporals[q].first},
                                 {"event2_event", t.temporals[q].second}};
  // Named orders (contract section 15) as temporal constraints; sequence steps have no name.
  for (std::size_t q = 0; q < sp.orders.size() && q < t.orders.size(); ++q) {
    if (sp.orders[q].name.empty()) continue;
    auto [k1, k2] = t.orders[q];
    if (k1 < 0 || k2 < 0 || k1 > g || k2 > g) continue;
    tcs[sp.orders[q].name] = {{"event1", Time(t.events[k1], tps)}, {"event2", Time(t.events[k2], tps)},
                              {"event1_event", k1}, {"event2_event", k2}};
  }
  out["episodes"] = eps;
  out["temporal"] = tcs;
  return out;
}

}  // namespace ctb
