#include "tests/planner/network_oracle.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <unordered_map>

namespace ctb::network::testing {
namespace {

constexpr Ticks kInf = 1LL << 50;

struct Constraint {
  int u, v;
  Ticks w;  // t(v) - t(u) <= w
};

bool FloydConsistent(int n, const std::vector<Constraint>& cs) {
  std::vector<Ticks> d(static_cast<std::size_t>(n * n), kInf);
  auto at = [&](int i, int j) -> Ticks& { return d[static_cast<std::size_t>(i * n + j)]; };
  for (int i = 0; i < n; ++i) at(i, i) = 0;
  for (const Constraint& c : cs) at(c.u, c.v) = std::min(at(c.u, c.v), c.w);
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < n; ++i) {
      if (at(i, k) >= kInf) continue;
      for (int j = 0; j < n; ++j) {
        if (at(k, j) < kInf) at(i, j) = std::min(at(i, j), at(i, k) + at(k, j));
      }
      if (at(i, i) < 0) return false;
    }
  }
  return true;
}

void AddLink(std::vector<Constraint>& cs, int u, int v, Ticks lb, std::optional<Ticks> ub) {
  if (ub) cs.push_back({u, v, *ub});
  cs.push_back({v, u, -lb});
}

}  // namespace

bool OracleConsistent(const Network& net) {
  std::vector<Constraint> cs;
  for (const Link& l : net.links) AddLink(cs, l.from, l.to, l.lb, l.ub);
  return FloydConsistent(static_cast<int>(net.points.size()), cs);
}

bool OracleStrong(const Network& net) {
  const int n = static_cast<int>(net.points.size());
  std::vector<int> contingent;  // link indices
  for (std::size_t i = 0; i < net.links.size(); ++i) {
    if (net.links[i].contingent) contingent.push_back(static_cast<int>(i));
  }
  const int k = static_cast<int>(contingent.size());
  auto var = [&](int scenario, int p) {
    return net.points[static_cast<std::size_t>(p)].kind == PointKind::kContingent
               ? n + scenario * n + p
               : p;
  };
  std::vector<Constraint> cs;
  for (int s = 0; s < (1 << k); ++s) {
    for (int j = 0; j < k; ++j) {  // the scenario's duration of each contingent link
      const Link& l = net.links[static_cast<std::size_t>(contingent[static_cast<std::size_t>(j)])];
      const Ticks d = (s >> j) & 1 ? *l.ub : l.lb;
      AddLink(cs, var(s, l.from), var(s, l.to), d, d);
    }
    for (const Link& l : net.links) {
      if (!l.contingent) AddLink(cs, var(s, l.from), var(s, l.to), l.lb, l.ub);
    }
  }
  return FloydConsistent(n + (1 << k) * n, cs);
}

namespace {

class Game {
 public:
  explicit Game(const Network& net) : net_(net), n_(static_cast<int>(net.points.size())) {
    Ticks biggest = 0;
    for (const Link& l : net.links) {
      biggest = std::max(biggest, std::llabs(l.lb));
      if (l.ub) biggest = std::max(biggest, std::llabs(*l.ub));
    }
    clamp_ = static_cast<int>(biggest) + 1;
    parent_.assign(static_cast<std::size_t>(n_), -1);
    for (std::size_t i = 0; i < net.links.size(); ++i) {
      if (net.links[i].contingent)
        parent_[static_cast<std::size_t>(net.links[i].to)] = static_cast<int>(i);
    }
  }

  bool Solve() {
    State s;
    s.fill(-1);
    return Agent(s);
  }

 private:
  using State = std::array<int, 8>;  // per point: -1 not yet, else now - its
                                     // time (clamped)

  std::uint64_t Key(const State& s) const {
    std::uint64_t k = 0;
    for (int i = 0; i < n_; ++i)
      k = k * 64 + static_cast<std::uint64_t>(s[static_cast<std::size_t>(i)] + 1);
    return k;
  }

  Ticks Rel(const State& s, int p) const { return s[static_cast<std::size_t>(p)]; }

  // Links between p (executed now, relative time 0) and the points executed before.
  bool HoldsAt(const State& s, int p) const {
    for (const Link& l : net_.links) {
      const int other = l.from == p ? l.to : l.to == p ? l.from : -1;
      if (other < 0 || Rel(s, other) < 0) continue;
      const Ticks diff = l.from == p ? -Rel(s, other) : Rel(s, other);  // t(to) - t(from)
      if (diff < l.lb || (l.ub && diff > *l.ub)) return false;
    }
    return true;
  }

  // After waiting: links from an executed point to one not yet executed that can no longer hold.
  bool Viable(const State& s) const {
    for (const Link& l : net_.links) {
      const Ticks rf = Rel(s, l.from), rt = Rel(s, l.to);
      if (rf >= 0 && rt < 0 && l.ub && rf > *l.ub) return false;
      if (rt >= 0 && rf < 0 && rt > -l.lb) return false;
    }
    return true;
  }

  // Contingent points activated by `p` with lb 0 (nature decides at once whether they finish).
  std::vector<int> ZeroChildren(int p) const {
    std::vector<int> out;
    for (const Link& l : net_.links) {
      if (l.contingent && l.from == p && l.lb == 0) out.push_back(l.to);
    }
    return out;
  }

  bool Nature(const State& s, const std::vector<int>& cands) {
    const int m = static_cast<int>(cands.size());
    for (int mask = 0; mask < (1 << m); ++mask) {
      State t = s;
      bool forced_missing = false;
      for (int j = 0; j < m; ++j) {
        const int c = cands[static_cast<std::size_t>(j)];
        const Link& l = net_.links[static_cast<std::size_t>(parent_[static_cast<std::size_t>(c)])];
        const bool now = (mask >> j) & 1;
        if (!now && l.ub && Rel(s, l.from) >= *l.ub) forced_missing = true;
        if (now) t[static_cast<std::size_t>(c)] = 0;
      }
      if (forced_missing) continue;
      std::vector<int> next;
      bool holds = true;
      for (int j = 0; j < m; ++j) {
        if (!((mask >> j) & 1)) continue;
        const int c = cands[static_cast<std::size_t>(j)];
        holds = holds && HoldsAt(t, c);
        for (int z : ZeroChildren(c)) next.push_back(z);
      }
      if (!holds) return false;
      if (!(next.empty() ? Agent(t) : Nature(t, next))) return false;
    }
    return true;
  }

  bool Agent(const State& s) {
    const std::uint64_t key = Key(s);
    if (auto it = memo_.find(key); it != memo_.end()) return it->second;
    const bool win = AgentMoves(s);
    memo_[key] = win;
    return win;
  }

  bool AgentMoves(const State& s) {
    bool all = true, any = false;
    for (int p = 0; p < n_; ++p) {
      const bool done = Rel(s, p) >= 0;
      all = all && done;
      any = any || done;
    }
    if (all) return true;
    for (int p = 0; p < n_; ++p) {
      if (Rel(s, p) >= 0 || net_.points[static_cast<std::size_t>(p)].kind == PointKind::kContingent)
        continue;
      State t = s;
      t[static_cast<std::size_t>(p)] = 0;
      if (!HoldsAt(t, p)) continue;
      const std::vector<int> z = ZeroChildren(p);
      if (z.empty() ? Agent(t) : Nature(t, z)) return true;
    }
    return any && Wait(s);
  }

  bool Wait(const State& s) {
    State t = s;
    for (int p = 0; p < n_; ++p) {
      int& r = t[static_cast<std::size_t>(p)];
      if (r >= 0) r = std::min(r + 1, clamp_);
    }
    if (!Viable(t)) return false;
    std::vector<int> cands;
    for (int c = 0; c < n_; ++c) {
      const int pl = parent_[static_cast<std::size_t>(c)];
      if (pl < 0 || Rel(t, c) >= 0) continue;
      const Link& l = net_.links[static_cast<std::size_t>(pl)];
      if (Rel(t, l.from) >= 0 && Rel(t, l.from) >= l.lb) cands.push_back(c);
    }
    if (t == s && cands.empty()) return false;  // waiting changes nothing
    return cands.empty() ? Agent(t) : Nature(t, cands);
  }

  const Network& net_;
  int n_;
  int clamp_ = 1;
  std::vector<int> parent_;
  std::unordered_map<std::uint64_t, bool> memo_;
};

}  // namespace

bool OracleDynamic(const Network& net) {
  if (net.points.size() > 8) std::abort();
  return Game(net).Solve();
}

Network RandomNetwork(std::mt19937& rng, int n, int k, int m, int max_bound) {
  auto uni = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  // Half the networks are planted: bounds around a hidden schedule (times increasing with the
  // index), so that most are consistent and the interesting answers (dynamic but not strong,
  // consistent but not dynamic) are frequent; the other half have free bounds.
  const bool planted = uni(0, 1) == 1;
  std::vector<int> t(static_cast<std::size_t>(n), 0);
  for (int i = 1; i < n; ++i)
    t[static_cast<std::size_t>(i)] =
        t[static_cast<std::size_t>(i - 1)] + uni(0, std::max(1, max_bound / 2));
  auto hidden = [&](int u, int v) {
    return t[static_cast<std::size_t>(v)] - t[static_cast<std::size_t>(u)];
  };
  auto clampb = [&](Ticks x) { return std::clamp<Ticks>(x, -max_bound, max_bound); };
  Network net;
  for (int i = 0; i < n; ++i)
    net.points.push_back({i, "p" + std::to_string(i), PointKind::kControllable, {}});
  for (int j = 0; j < k && n >= 2; ++j) {
    const int c = uni(1, n - 1);
    if (net.points[static_cast<std::size_t>(c)].kind == PointKind::kContingent) continue;
    const int a = uni(0, c - 1);  // activations come earlier in index order: a forest
    Ticks lb = uni(0, max_bound), ub = lb + uni(0, max_bound - static_cast<int>(lb));
    if (planted) {
      const Ticks d = std::min<Ticks>(hidden(a, c), max_bound);
      lb = std::max<Ticks>(0, d - uni(0, 2));
      ub = std::min<Ticks>(max_bound, d + uni(0, 2));
    }
    net.links.push_back({a, c, lb, ub, true, ""});
    net.points[static_cast<std::size_t>(c)].kind = PointKind::kContingent;
  }
  for (int j = 0; j < m; ++j) {
    const int u = uni(0, n - 1);
    int v = uni(0, n - 2);
    if (v >= u) ++v;
    Ticks lb = uni(-max_bound, max_bound);
    std::optional<Ticks> ub;
    if (planted) {
      const Ticks d = hidden(u, v);
      lb = clampb(d - uni(0, 2));
      if (uni(0, 3) > 0) ub = clampb(d + uni(0, 2));
    } else if (uni(0, 3) > 0) {
      ub = std::min<Ticks>(lb + uni(0, max_bound), max_bound);
    }
    if (ub && *ub < lb) ub = lb;
    net.links.push_back({u, v, lb, ub, false, ""});
  }
  std::shuffle(net.links.begin(), net.links.end(), rng);
  return net;
}

Network Restrict(const Network& net, const std::vector<int>& links) {
  Network out;
  out.points = net.points;
  for (Point& p : out.points) p.kind = PointKind::kControllable;
  for (int i : links) {
    const Link& l = net.links[static_cast<std::size_t>(i)];
    out.links.push_back(l);
    if (l.contingent) out.points[static_cast<std::size_t>(l.to)].kind = PointKind::kContingent;
  }
  return out;
}

}  // namespace ctb::network::testing
