#include <cmath>

#include "planner/trajectory.h"

namespace ctb {

namespace {

bool IntArray(const Json& j, std::size_t min_size) {
  if (!j.is_array() || j.size() < min_size) return false;
  for (const auto& v : j)
    if (!v.is_number_integer()) return false;
  return true;
}

// A 2-D solver array is a list of rows; rows may be empty when the second range is.
bool IntMatrix(const Json& j, std::size_t rows, std::size_t min_cols) {
  if (!j.is_array() || j.size() != rows) return false;
  for (const auto& r : j)
    if (!IntArray(r, min_cols)) return false;
  return true;
}

double Seconds(long ticks, long tps) { return static_cast<double>(ticks) / static_cast<double>(tps); }

Json Time(long ticks, long tps) {
  if (tps == 1) return ticks;
  return Seconds(ticks, tps);
}

}  // namespace

std::optional<Trajectory> ExtractTrajectory(const Json& s, const Domain& d, const StatePlan& sp,
                                            int H, std::string& error) {
  const std::size_t na = d.automata.size();
  auto missing = [&](const char* what) {
    error = std::string("solver answer lacks a valid '") + what + "'";
    return std::nullopt;
  };
  if (!s.is_object()) return missing("solution");
  if (!s.contains("g") || !s["g"].is_number_integer()) return missing("g");
  if (!s.contains("e") || !IntArray(s["e"], H + 1)) return missing("e");
  if (!s.contains("L") || !IntMatrix(s["L"], na, H + 1)) return missing("L");
  if (!s.contains("U") || !IntMatrix(s["U"], na, H + 1)) return missing("U");
  if (H > 0 && (!s.contains("X") || !IntMatrix(s["X"], na, H))) return missing("X");
  Trajectory t;
  t.horizon = H;
  t.goal_event = s["g"].get<int>();
  const int g = t.goal_event;
  if (g < 0 || g > H) return missing("g");
  for (int k = 0; k <= g; ++k) t.events.push_back(s["e"][k].get<long>());
  t.locations.assign(na, {});
  t.commands.assign(na, {});
  // Global transition ids are numbered automaton by automaton from 1, as in Analyze().
  std::vector<int> first_id(na, 1);
  for (std::size_t a = 1; a < na; ++a)
    first_id[a] = first_id[a - 1] + static_cast<int>(d.automata[a - 1].transitions.size());
  for (std::size_t a = 0; a < na; ++a) {
    for (int k = 0; k <= g; ++k) {
      int loc = s["L"][a][k].get<int>();
      if (loc < 0 || loc >= static_cast<int>(d.automata[a].locations.size())) return missing("L");
      t.locations[a].push_back(loc);
      int cmd = s["U"][a][k].get<int>();
      if (cmd < 0 || cmd > static_cast<int>(d.automata[a].commands.size())) return missing("U");
      t.commands[a].push_back(k < g ? cmd : 0);
    }
  }
  for (int k = 0; k < g; ++k) {
    for (std::size_t a = 0; a < na; ++a) {
      int id = s["X"][a][k].get<int>();
      if (id == 0) continue;
      int idx = id - first_id[a];
      if (idx < 0 || idx >= static_cast<int>(d.automata[a].transitions.size())) return missing("X");
      t.fired.push_back({k + 1, static_cast<int>(a), idx});
    }
  }
  auto pairs = [&](const char* a, const char* b, std::size_t n,
                   std::vector<std::pair<int, int>>& out) -> bool {
    if (n == 0) return true;
    if (!s.contains(a) || !s.contains(b) || !IntArray(s[a], n) || !IntArray(s[b], n)) return false;
    for (std::size_t i = 0; i < n; ++i) out.emplace_back(s[a][i].get<int>(), s[b][i].get<int>());
    return true;
  };
  if (!pairs("EP_S", "EP_E", sp.episodes.size(), t.episodes)) return missing("EP_S/EP_E");
  if (!pairs("TC_1", "TC_2", sp.temporals.size(), t.temporals)) return missing("TC_1/TC_2");
  return t;
}

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
  for (const auto& f : t.fired) {
    const Automaton& a = d.automata[f.automaton];
    const Transition& tr = a.transitions[f.transition];
    Json j = {{"time", Time(t.events[f.event], tps)}, {"event", f.event},
              {"automaton", a.name}, {"from", a.locations[tr.from]}, {"to", a.locations[tr.to]}};
    int cmd = t.commands[f.automaton][f.event - 1];
    j["command"] = tr.commanded && cmd > 0 ? Json(a.commands[cmd - 1]) : Json();
    transitions.push_back(j);
  }
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
  out["episodes"] = eps;
  out["temporal"] = tcs;
  return out;
}

}  // namespace ctb
