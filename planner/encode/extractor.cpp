#include <cmath>

#include "planner/encode/extract.h"

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
  if (!pairs("O_1", "O_2", sp.orders.size(), t.orders)) return missing("O_1/O_2");
  return t;
}

}  // namespace ctb
