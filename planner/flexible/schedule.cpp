// Windows, sampled schedules and the trajectory of a schedule (flexible.h).
#include <algorithm>
#include <deque>
#include <map>
#include <numeric>
#include <optional>
#include <tuple>

#include "planner/flexible/flexible.h"

namespace ctb::flexible {

namespace {

using network::Network;
using network::Ticks;

struct Edge {
  int to;
  Ticks w;
};

// The distance graph (t(v) - t(u) <= w as u -> v of weight w), forward or reversed.
std::vector<std::vector<Edge>> Graph(const Network& net, bool reversed,
                                     const std::vector<std::pair<int, Ticks>>& fixed = {}) {
  std::vector<std::vector<Edge>> g(net.points.size());
  auto add = [&](int u, int v, Ticks w) {
    if (reversed) g[v].push_back({u, w});
    else g[u].push_back({v, w});
  };
  for (const auto& l : net.links) {
    if (l.ub) add(l.from, l.to, *l.ub);
    add(l.to, l.from, -l.lb);
  }
  for (const auto& [p, t] : fixed) {
    add(0, p, t);
    add(p, 0, -t);
  }
  return g;
}

// Shortest distances from point 0 (SPFA); nullopt on a negative cycle. kInfinity: unreachable.
std::optional<std::vector<Ticks>> FromOrigin(const std::vector<std::vector<Edge>>& g) {
  const std::size_t n = g.size();
  std::vector<Ticks> dist(n, network::kInfinity);
  std::vector<int> relaxed(n, 0);
  std::vector<bool> queued(n, false);
  std::deque<int> q = {0};
  dist[0] = 0;
  queued[0] = true;
  while (!q.empty()) {
    const int u = q.front();
    q.pop_front();
    queued[u] = false;
    for (const Edge& e : g[u]) {
      if (dist[u] + e.w >= dist[e.to]) continue;
      dist[e.to] = dist[u] + e.w;
      if (++relaxed[e.to] > static_cast<int>(n)) return std::nullopt;
      if (!queued[e.to]) {
        queued[e.to] = true;
        q.push_back(e.to);
      }
    }
  }
  return dist;
}

std::optional<std::vector<Window>> WindowsWith(const Network& net,
                                              const std::vector<std::pair<int, Ticks>>& fixed) {
  auto latest = FromOrigin(Graph(net, false, fixed));
  auto back = FromOrigin(Graph(net, true, fixed));
  if (!latest || !back || (*latest)[0] < 0 || (*back)[0] < 0) return std::nullopt;
  std::vector<Window> w(net.points.size());
  for (std::size_t p = 0; p < w.size(); ++p) {
    w[p].earliest = (*back)[p] >= network::kInfinity ? 0 : -(*back)[p];
    if ((*latest)[p] < network::kInfinity) w[p].latest = (*latest)[p];
  }
  return w;
}

class Rebuild {
 public:
  Rebuild(const FlexiblePlan& f, const Trajectory& plan, const std::vector<Ticks>& times)
      : f_(f), plan_(plan), times_(times), n_(static_cast<int>(f.net.points.size())), group_(n_) {
    std::iota(group_.begin(), group_.end(), 0);
  }

  std::optional<Trajectory> Run(std::string& why) {
    for (const auto& [x, y] : f_.same_event) {
      if (times_[x] != times_[y]) return (why = "tied points at different times"), std::nullopt;
      group_[Find(x)] = Find(y);
    }
    for (const auto& [x, y] : f_.before)
      if (times_[x] > times_[y]) return (why = "an order is broken"), std::nullopt;
    if (!Levels(why)) return std::nullopt;
    return Build();
  }

 private:
  int Find(int x) { return group_[x] == x ? x : group_[x] = Find(group_[x]); }

  // Events: by time, then by level among same-time groups (longest chain of `before`).
  bool Levels(std::string& why) {
    std::map<int, std::vector<int>> succ;
    std::map<int, int> indegree;
    for (int p = 1; p < n_; ++p) indegree[Find(p)] += 0;
    auto edge = [&](int x, int y) {
      const int gx = Find(x), gy = Find(y);
      if (gx == gy || times_[x] != times_[y] || x == 0) return;
      succ[gx].push_back(gy);
      ++indegree[gy];
    };
    for (const auto& [x, y] : f_.before) edge(x, y);
    // A transition due when its cause made its guard true is the very next event after it: what
    // must precede it at that moment (no later in the plan than the cause) precedes the cause.
    for (const auto& [c, x] : f_.due_after) {
      if (times_[c] != times_[x]) continue;
      for (const auto& [z, y] : f_.before)
        if (y == x && z != c && times_[z] == times_[x] && f_.point_event[z] <= f_.point_event[c])
          edge(z, c);
    }
    std::deque<int> ready;
    for (const auto& [g, d] : indegree)
      if (d == 0) ready.push_back(g);
    std::map<int, int> level;
    int seen = 0;
    while (!ready.empty()) {
      const int g = ready.front();
      ready.pop_front();
      ++seen;
      for (int h : succ[g]) {
        level[h] = std::max(level[h], level[g] + 1);
        if (--indegree[h] == 0) ready.push_back(h);
      }
    }
    if (seen != static_cast<int>(indegree.size())) return (why = "a cycle of orders"), false;
    for (const auto& [g, d] : indegree) keys_[g] = {times_[g], level[g]};
    return true;
  }

  Trajectory Build() {
    std::map<std::pair<Ticks, int>, int> event_of_key;
    for (const auto& [g, key] : keys_) event_of_key[key] = 0;
    Trajectory t;
    t.events = {0};
    for (auto& [key, k] : event_of_key) {
      k = static_cast<int>(t.events.size());
      t.events.push_back(key.first / (network::kTicksPerSecond / f_.tps));
    }
    const int g = static_cast<int>(t.events.size()) - 1;
    const std::size_t na = plan_.locations.size();
    t.locations.assign(na, std::vector<int>(g + 1, 0));
    t.commands.assign(na, std::vector<int>(g + 1, 0));
    std::vector<std::vector<int>> fired_at(g + 1);
    auto event_of = [&](int p) { return p == 0 ? 0 : event_of_key[keys_[Find(p)]]; };
    for (int p = 1; p < n_; ++p) {
      const int k = event_of(p);
      t.fired.push_back({k, f_.point_automaton[p], f_.point_transition[p]});
      fired_at[k].push_back(p);
    }
    std::sort(t.fired.begin(), t.fired.end(), [](const auto& x, const auto& y) {
      return std::tie(x.event, x.automaton) < std::tie(y.event, y.automaton);
    });
    for (std::size_t a = 0; a < na; ++a) t.locations[a][0] = plan_.locations[a][0];
    for (int k = 1; k <= g; ++k) {
      for (std::size_t a = 0; a < na; ++a) t.locations[a][k] = t.locations[a][k - 1];
      for (int p : fired_at[k]) {
        const int a = f_.point_automaton[p];
        t.locations[a][k] = plan_.locations[a][f_.point_event[p]];
        t.commands[a][k - 1] = plan_.commands[a][f_.point_event[p] - 1];
      }
    }
    for (const auto& [s, e] : f_.episode_points) t.episodes.emplace_back(event_of(s), event_of(e));
    for (const auto& [a, b] : f_.temporal_points) t.temporals.emplace_back(event_of(a), event_of(b));
    for (const auto& [a, b] : f_.order_points) t.orders.emplace_back(event_of(a), event_of(b));
    t.goal_event = g;
    t.horizon = std::max(plan_.horizon, g);
    return t;
  }

  const FlexiblePlan& f_;
  const Trajectory& plan_;
  const std::vector<Ticks>& times_;
  const int n_;
  std::vector<int> group_;
  std::map<int, std::pair<Ticks, int>> keys_;  // group -> (time, level)
};

}  // namespace

std::optional<std::vector<Window>> Windows(const Network& net) { return WindowsWith(net, {}); }

std::vector<Ticks> PlanTimes(const FlexiblePlan& f, const Trajectory& plan) {
  std::vector<Ticks> times;
  for (int e : f.point_event) times.push_back(plan.events[e] * (network::kTicksPerSecond / f.tps));
  return times;
}

Json SlackJson(const std::vector<Window>& windows) {
  Json out = Json::array();
  for (std::size_t p = 1; p < windows.size(); ++p)
    out.push_back({{"point", p},
                   {"earliest", network::SecondsFromTicks(windows[p].earliest)},
                   {"latest", windows[p].latest ? Json(network::SecondsFromTicks(*windows[p].latest))
                                                : Json()}});
  return out;
}

std::optional<std::vector<Ticks>> SampleSchedule(const FlexiblePlan& f, std::mt19937& rng,
                                                 bool extremes) {
  const Ticks step = network::kTicksPerSecond / f.tps;
  std::vector<std::pair<int, Ticks>> fixed;
  std::vector<Ticks> times(f.net.points.size(), 0);
  for (std::size_t p = 1; p < f.net.points.size(); ++p) {
    auto w = WindowsWith(f.net, fixed);
    if (!w) return std::nullopt;
    const Ticks lo = (*w)[p].earliest;
    // An open window: up to a minute past its earliest time (whole domain ticks).
    const Ticks hi = (*w)[p].latest.value_or(lo + 60 * network::kTicksPerSecond);
    const Ticks steps = (hi - lo) / step;
    const Ticks k = extremes ? (rng() % 2 ? 0 : std::max<Ticks>(0, steps))
                             : std::uniform_int_distribution<Ticks>(0, std::max<Ticks>(0, steps))(rng);
    times[p] = lo + step * k;
    fixed.emplace_back(static_cast<int>(p), times[p]);
  }
  if (!WindowsWith(f.net, fixed)) return std::nullopt;
  return times;
}

std::optional<Trajectory> ScheduleToTrajectory(const FlexiblePlan& f, const Trajectory& plan,
                                               const std::vector<Ticks>& times,
                                               std::string* why_not) {
  std::string why;
  if (plan.history) why = "a replan's schedule is not rebuilt";
  else if (times.size() != f.net.points.size()) why = "one time per point expected";
  std::optional<Trajectory> t;
  if (why.empty()) t = Rebuild(f, plan, times).Run(why);
  if (!t && why_not) *why_not = why;
  return t;
}

}  // namespace ctb::flexible
