#include "planner/search/expand.h"

#include <set>

#include <algorithm>
#include <cmath>

#include "planner/expr/expr_print.h"

namespace ctb::search {

namespace {

bool IsAccepting(const Expr& atom) {
  return atom.var_kind == VarKind::kEpisodeState || atom.var_kind == VarKind::kTemporalState;
}

// Why the engine cannot follow a condition: it reads commands (those of the stage an event opens
// are chosen only at the next event) or a fixed stage after the first (min(n, g) depends on the
// goal event). Stage 0 is the initial state in every run, replanned ones included.
std::string Unsupported(const Condition& c) {
  if (c.raw_info.max_fixed > 0) return "a condition reads a fixed stage after 0 (" + c.pointer + ")";
  if (!c.raw_info.commands_read.empty()) return "a condition reads commands (" + c.pointer + ")";
  return "";
}

}  // namespace

Expander::Expander(const Domain& d, const StatePlan& sp, long ticks_per_second)
    : d_(d), sp_(sp), tps_(ticks_per_second) {
  const std::size_t na = d.automata.size();
  out_.resize(na);
  readers_.resize(na);
  clock_cap_.resize(na);
  for (std::size_t a = 0; a < na; ++a) {
    const Automaton& au = d.automata[a];
    out_[a].resize(au.locations.size());
    clock_cap_[a].assign(au.locations.size(), 0);
    for (std::size_t ti = 0; ti < au.transitions.size(); ++ti) {
      const Transition& tr = au.transitions[ti];
      out_[a][tr.from].push_back(static_cast<int>(ti));
      long reach = Ticks(tr.duration.lo);
      if (tr.duration.hi) reach = std::max(reach, Ticks(*tr.duration.hi));
      clock_cap_[a][tr.from] = std::max(clock_cap_[a][tr.from], reach + 1);
      for (int r : tr.guard_info.commands_read) {
        auto& rs = readers_[r];
        if (std::find(rs.begin(), rs.end(), static_cast<int>(a)) == rs.end())
          rs.push_back(static_cast<int>(a));
      }
    }
  }
  lead_.resize(na);
  for (std::size_t a = 0; a < na; ++a)
    for (const Transition& tr : d.automata[a].transitions) {
      long lead = kInfinity;
      for (int next : out_[a][tr.to])
        lead = std::min(lead, Ticks(d.automata[a].transitions[next].duration.lo));
      lead_[a].push_back(lead == kInfinity ? 0 : lead);
    }
  for (const auto& ep : sp.episodes) {
    ep_lo_.push_back(Ticks(ep.lower));
    ep_hi_.push_back(Ticks(ep.upper));
  }
  for (const auto& tc : sp.temporals) {
    tc_lo_.push_back(Ticks(tc.lower));
    tc_hi_.push_back(Ticks(tc.upper));
  }
  std::vector<const Condition*> conds = {&sp.goal, &sp.maintenance};
  for (const auto& ep : sp.episodes) conds.insert(conds.end(), {&ep.accepting, &ep.state});
  for (const auto& tc : sp.temporals) conds.insert(conds.end(), {&tc.event1, &tc.event2});
  for (const Condition* c : conds)
    if (declined_.empty()) declined_ = Unsupported(*c);
  // Ends of episodes and second events are chosen greedily (as soon as they may), which cannot
  // make endpoints meet on one event.
  if (declined_.empty() && !sp.events.empty()) declined_ = "the state plan has shared events";
  // Orders are followed when both their ends are actions taken the first time (or `every` time, as
  // the second end); forbidden actions are never taken.
  if (declined_.empty() && !sp.action_events.empty())
    declined_ = "the state plan puts actions in shared events";
  if (declined_.empty() && !sp.cuts.empty())
    declined_ = "the search among plans has cut some (controllability conflicts)";
  for (const auto& o : sp.orders) {
    if (!declined_.empty()) break;
    for (const OrderEnd* e : {&o.first, &o.second})
      if (e->action < 0) declined_ = "an order has a condition as an end (" + o.pointer + ")";
      else if (sp.actions[e->action].occurrence == Occurrence::kLast)
        declined_ = "an order reads an action's last occurrence (" + o.pointer + ")";
    ord_lo_.push_back(Ticks(o.lower));
    ord_hi_.push_back(o.upper ? Ticks(*o.upper) : kInfinity);
  }
  for (const auto& act : sp.actions) {
    std::vector<bool> mine(d.automata[act.automaton].transitions.size(), false);
    for (int ti : act.transitions) mine[ti] = true;
    is_action_.push_back(std::move(mine));
  }
}

long Expander::Ticks(double seconds) const {
  return std::lround(seconds * static_cast<double>(tps_));
}

bool Expander::GuardHolds(const Transition& tr, const std::vector<int>& loc,
                          const std::vector<int>& cmd) const {
  // As the verifier: a location atom reads the location, any other the command.
  return Evaluate(tr.guard, [&](const Expr& atom) {
    return atom.var_kind == VarKind::kLocation ? loc[atom.target] : cmd[atom.target];
  });
}

std::vector<int> Expander::Enabled(int a, const std::vector<int>& loc,
                                   const std::vector<int>& cmd) const {
  std::vector<int> out;
  for (int ti : out_[a][loc[a]])
    if (GuardHolds(d_.automata[a].transitions[ti], loc, cmd)) out.push_back(ti);
  return out;
}

StageView Expander::View(const Node& n) const {
  StageView v;
  const std::vector<int> none(d_.automata.size(), 0);
  for (std::size_t a = 0; a < d_.automata.size(); ++a)
    v.enabled.push_back(Enabled(static_cast<int>(a), n.loc, none));
  return v;
}

bool Expander::Partners(const Node& n, Candidate& c, std::vector<int>& cmd) const {
  std::vector<std::pair<int, int>> todo = {{c.automaton, c.transition}};
  while (!todo.empty()) {
    auto [a, ti] = todo.back();
    todo.pop_back();
    const Transition& tr = d_.automata[a].transitions[ti];
    for (int b : tr.guard_info.commands_read) {
      // A command the guard reads some other way (`!=`, a disjunction) is left as no command:
      // the guard check below decides, as it did before groups.
      const int want = RequiredCommand(tr.guard, b);
      if (want <= 0 || cmd[b] != 0) continue;
      cmd[b] = want;
      c.commands.emplace_back(b, want);
      for (int tj : out_[b][n.loc[b]]) {
        const Transition& other = d_.automata[b].transitions[tj];
        if (!other.commanded || other.command != want) continue;
        todo.emplace_back(b, tj);
        c.with.emplace_back(b, tj);
      }
    }
  }
  // The partners' transitions that fire are those whose guards hold with every command given;
  // an automaton whose command enables none only carries it (Apply checks the whole event).
  std::erase_if(c.with, [&](const std::pair<int, int>& m) {
    return !GuardHolds(d_.automata[m.first].transitions[m.second], n.loc, cmd);
  });
  return GuardHolds(d_.automata[c.automaton].transitions[c.transition], n.loc, cmd);
}

std::vector<Candidate> Expander::Candidates(const Node& n, const StageView& v) const {
  std::vector<Candidate> out;
  std::set<std::vector<std::pair<int, int>>> groups;  // each group of commands offered once
  std::vector<int> cmd(d_.automata.size(), 0);
  for (std::size_t a = 0; a < d_.automata.size(); ++a) {
    for (int ti : out_[a][n.loc[a]]) {
      const Transition& tr = d_.automata[a].transitions[ti];
      Candidate c{static_cast<int>(a), ti, std::max(n.time, earliest_), kInfinity, {}, {}};
      if (tr.commanded) {
        if (tr.command <= 0) continue;  // a guard that names no single command: not chosen here
        std::fill(cmd.begin(), cmd.end(), 0);
        cmd[a] = tr.command;
        if (!Partners(n, c, cmd)) continue;
        std::erase(c.commands, std::pair{static_cast<int>(a), tr.command});
        std::erase(c.with, std::pair{static_cast<int>(a), ti});
        if (!c.commands.empty()) {
          auto key = c.commands;
          key.emplace_back(static_cast<int>(a), tr.command);
          std::sort(key.begin(), key.end());
          if (!groups.insert(std::move(key)).second) continue;
        }
      } else if (!tr.controllable ||
                 std::find(v.enabled[a].begin(), v.enabled[a].end(), ti) == v.enabled[a].end()) {
        continue;
      }
      for (auto [b, tj] : c.Members()) {
        const Transition& t = d_.automata[b].transitions[tj];
        c.earliest = std::max(c.earliest, n.entry[b] + Ticks(t.duration.lo));
        if (t.duration.hi) c.latest = std::min(c.latest, n.entry[b] + Ticks(*t.duration.hi));
      }
      if (c.earliest <= c.latest) out.push_back(std::move(c));
    }
  }
  return out;
}

// When each automatic transition enabled at the node is due (its entry plus its lower duration).
template <typename F>
void Expander::ForEachDue(const Node& n, const StageView& v, F&& f) const {
  for (std::size_t a = 0; a < v.enabled.size(); ++a)
    for (int ti : v.enabled[a]) {
      const Transition& tr = d_.automata[a].transitions[ti];
      if (!tr.commanded && !tr.controllable) f(n.entry[a] + Ticks(tr.duration.lo));
    }
}

long Expander::DueTime(const Node& n, const StageView& v) const {
  long due = kInfinity;
  ForEachDue(n, v, [&](long t) { due = std::min(due, std::max({n.time, earliest_, t})); });
  return due;
}

std::vector<long> Expander::DueTimes(const Node& n, const StageView& v) const {
  std::vector<long> out;
  ForEachDue(n, v, [&](long t) {
    if (t > n.time) out.push_back(t);
  });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<long> Expander::Targets(const Node& n) const {
  std::vector<long> out;
  const Monitors& m = n.mon;
  for (std::size_t p = 0; p < sp_.episodes.size(); ++p)
    if (m.ep_start[p] >= 0 && m.ep_end[p] < 0 && m.ep_start_t[p] + ep_lo_[p] > n.time)
      out.push_back(m.ep_start_t[p] + ep_lo_[p]);
  for (std::size_t q = 0; q < sp_.temporals.size(); ++q)
    if ((m.tc_k1[q] >= 0) != (m.tc_k2[q] >= 0) && m.tc_first_t[q] + tc_lo_[q] > n.time)
      out.push_back(m.tc_first_t[q] + tc_lo_[q]);
  for (std::size_t q = 0; q < sp_.orders.size(); ++q)
    if (m.ord_k1[q] >= 0 && m.ord_k2[q] < 0 && m.ord_t1[q] + ord_lo_[q] > n.time)
      out.push_back(m.ord_t1[q] + ord_lo_[q]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::optional<Node> Expander::Root() const {
  Node n;
  const std::size_t na = d_.automata.size();
  n.loc = sp_.initial;
  n.entry.assign(na, 0);
  n.mon.ep_start.assign(sp_.episodes.size(), -1);
  n.mon.ep_end.assign(sp_.episodes.size(), -1);
  n.mon.ep_start_t.assign(sp_.episodes.size(), kNoTime);
  n.mon.tc_k1.assign(sp_.temporals.size(), -1);
  n.mon.tc_k2.assign(sp_.temporals.size(), -1);
  n.mon.tc_first_t.assign(sp_.temporals.size(), kNoTime);
  n.mon.ord_k1.assign(sp_.orders.size(), -1);
  n.mon.ord_k2.assign(sp_.orders.size(), -1);
  n.mon.ord_t1.assign(sp_.orders.size(), kNoTime);
  n.mon.ord_t2.assign(sp_.orders.size(), kNoTime);
  if (!UpdateMonitors(nullptr, n)) return std::nullopt;
  return n;
}

std::optional<Node> Expander::Apply(const Node& parent, const StageView& v,
                                    const std::vector<std::pair<int, int>>& chosen, long time,
                                    const std::vector<std::pair<int, int>>& given) const {
  const std::size_t na = d_.automata.size();
  if (time < parent.time || time < earliest_) return std::nullopt;
  std::vector<int> cmd(na, 0), pick(na, -1);
  std::vector<char> touched(na, 0);
  for (auto [a, c] : given) {
    if (cmd[a] != 0 && cmd[a] != c) return std::nullopt;
    cmd[a] = c;
    touched[a] = 1;
    for (int b : readers_[a]) touched[b] = 1;
  }
  for (auto [a, ti] : chosen) {
    if (pick[a] >= 0) return std::nullopt;
    const Transition& tr = d_.automata[a].transitions[ti];
    pick[a] = ti;
    if (cmd[a] != 0 && tr.commanded && cmd[a] != tr.command) return std::nullopt;
    if (cmd[a] == 0) cmd[a] = tr.commanded ? tr.command : 0;
    touched[a] = 1;
    for (int b : readers_[a]) touched[b] = 1;
  }
  Node n;
  n.event = parent.event + 1;
  n.time = time;
  n.cost = parent.cost;
  n.loc = parent.loc;
  n.entry = parent.entry;
  n.mon = parent.mon;
  std::vector<int> scratch;
  for (std::size_t b = 0; b < na; ++b) {
    const std::vector<int>* en = &v.enabled[b];
    if (touched[b]) {
      scratch = Enabled(static_cast<int>(b), parent.loc, cmd);
      en = &scratch;
    }
    const long clock = time - parent.entry[b];
    const auto& trs = d_.automata[b].transitions;
    // The verifier's rules over every transition whose guard holds on the stage before.
    int required = -1;
    for (int ti : *en) {
      const Transition& tr = trs[ti];
      bool must = false;
      if (tr.commanded) {
        must = true;  // a command whose transition is enabled must take it
      } else if (tr.controllable) {
        if (tr.duration.hi && clock > Ticks(*tr.duration.hi)) return std::nullopt;  // overstay
      } else {
        const long lo = Ticks(tr.duration.lo);
        if (time > std::max(parent.time, parent.entry[b] + lo)) return std::nullopt;  // overdue
        must = clock >= lo;
      }
      if (must) {
        if (required >= 0) return std::nullopt;  // two transitions due at once: determinacy
        required = ti;
      }
    }
    int fire = pick[b];
    if (fire >= 0) {
      if (required >= 0 && required != fire) return std::nullopt;
      if (std::find(en->begin(), en->end(), fire) == en->end()) return std::nullopt;
    } else {
      fire = required;
    }
    if (fire < 0) continue;
    const Transition& tr = trs[fire];
    if (clock < Ticks(tr.duration.lo) || (tr.duration.hi && clock > Ticks(*tr.duration.hi)))
      return std::nullopt;
    n.loc[b] = tr.to;
    n.entry[b] = time;
    n.cost += tr.cost;
    n.fired.emplace_back(static_cast<int>(b), fire);
  }
  if (n.fired.empty()) return std::nullopt;  // runs are concise
  for (std::size_t a = 0; a < na; ++a)
    if (cmd[a] != 0) n.cmds_before.emplace_back(static_cast<int>(a), cmd[a]);
  if (!UpdateMonitors(&parent, n)) return std::nullopt;
  return n;
}

int Expander::InitialValue(const Expr& atom) const {
  return atom.var_kind == VarKind::kLocation ? sp_.initial[atom.target] : 0;
}

int Expander::AcceptingBefore(const Expr& atom, const Node* prev) const {
  if (!prev) return 0;  // before event 0 nothing has started
  const int k = prev->event;
  const Monitors& m = prev->mon;
  const int i = atom.target;
  if (atom.var_kind == VarKind::kEpisodeState)
    return (m.ep_start[i] >= 0 && k >= m.ep_start[i] ? 1 : 0) +
           (m.ep_end[i] >= 0 && k >= m.ep_end[i] ? 1 : 0);
  const int k1 = m.tc_k1[i], k2 = m.tc_k2[i];
  const int first = k1 < 0 ? k2 : (k2 < 0 ? k1 : std::min(k1, k2));
  const int second = (k1 < 0 || k2 < 0) ? -1 : std::max(k1, k2);
  return (first >= 0 && k >= first ? 1 : 0) + (second >= 0 && k >= second ? 1 : 0);
}

bool Expander::AtEvent(const Condition& c, const Node* prev, const Node& n) const {
  const bool change = c.raw_info.IsChange();
  if (change && !prev) return false;
  return Evaluate(c.raw, [&](const Expr& atom) {
    if (IsAccepting(atom)) return AcceptingBefore(atom, prev);
    if (atom.index.kind == IndexKind::kFixed) return InitialValue(atom);
    const bool before = change && atom.index.kind == IndexKind::kI;
    const std::vector<int>& loc = before ? prev->loc : n.loc;
    return atom.var_kind == VarKind::kLocation ? loc[atom.target] : 0;  // commands: declined
  });
}

bool Expander::OnStage(const Condition& c, const Node* prev, const Node& n) const {
  return Evaluate(c.raw, [&](const Expr& atom) {
    if (IsAccepting(atom)) return AcceptingBefore(atom, prev);
    if (atom.index.kind == IndexKind::kFixed) return InitialValue(atom);
    return atom.var_kind == VarKind::kLocation ? n.loc[atom.target] : 0;
  });
}

bool Expander::UpdateMonitors(const Node* prev, Node& n) const {
  const int j = n.event;
  const long t = n.time;
  Monitors& m = n.mon;
  for (std::size_t p = 0; p < sp_.episodes.size(); ++p) {
    const Episode& ep = sp_.episodes[p];
    if (m.ep_start[p] < 0) {
      if (AtEvent(ep.accepting, prev, n)) {
        m.ep_start[p] = j;
        m.ep_start_t[p] = t;
      }
    } else if (m.ep_end[p] < 0) {
      const long dur = t - m.ep_start_t[p];
      if (dur > ep_hi_[p]) return false;  // can no longer end within its bounds
      if (dur >= ep_lo_[p]) m.ep_end[p] = j;  // greedy: ends as soon as it may
    }
    if (m.ep_start[p] >= 0 && m.ep_end[p] < 0 && !OnStage(ep.state, prev, n)) return false;
  }
  for (std::size_t q = 0; q < sp_.temporals.size(); ++q) {
    const Temporal& tc = sp_.temporals[q];
    int& k1 = m.tc_k1[q];
    int& k2 = m.tc_k2[q];
    if (k1 < 0 && k2 < 0) {
      const bool h1 = AtEvent(tc.event1, prev, n), h2 = AtEvent(tc.event2, prev, n);
      if (h1 && h2) {
        if (tc_lo_[q] != 0) return false;  // both at its first event: accepted at once or never
        k1 = k2 = j;
      } else if (h1) {
        k1 = j;
      } else if (h2) {
        k2 = j;
      }
      if (h1 || h2) m.tc_first_t[q] = t;
    } else if (k1 < 0 || k2 < 0) {
      const long dt = t - m.tc_first_t[q];
      if (dt > tc_hi_[q]) return false;
      if (dt >= tc_lo_[q] && AtEvent(k1 < 0 ? tc.event1 : tc.event2, prev, n)) (k1 < 0 ? k1 : k2) = j;
    }
  }
  if (!UpdateOrders(n)) return false;
  bool all = AtEvent(sp_.goal, prev, n);
  for (std::size_t p = 0; all && p < sp_.episodes.size(); ++p) all = m.ep_end[p] >= 0;
  for (std::size_t q = 0; all && q < sp_.temporals.size(); ++q)
    all = m.tc_k1[q] >= 0 && m.tc_k2[q] >= 0;
  for (std::size_t q = 0; all && q < sp_.orders.size(); ++q) all = OrderAccepted(q, m);
  n.done = all;
  // The maintenance constraint holds on every stage before the goal event.
  return n.done || OnStage(sp_.maintenance, prev, n);
}

bool Expander::Fires(int action, const Node& n) const {
  const int a = sp_.actions[action].automaton;
  for (auto [b, ti] : n.fired)
    if (b == a && is_action_[action][ti]) return true;
  return false;
}

bool Expander::OrderAccepted(std::size_t q, const Monitors& m) const {
  const Order& o = sp_.orders[q];
  const bool every = sp_.actions[o.second.action].occurrence == Occurrence::kEvery;
  return every ? m.ord_k1[q] >= 0 : m.ord_k1[q] >= 0 && m.ord_k2[q] >= 0;
}

bool Expander::UpdateOrders(Node& n) const {
  const int j = n.event;
  const long t = n.time;
  for (int f : sp_.forbidden)
    if (Fires(f, n)) return false;
  Monitors& m = n.mon;
  for (std::size_t q = 0; q < sp_.orders.size(); ++q) {
    const Order& o = sp_.orders[q];
    const bool every = sp_.actions[o.second.action].occurrence == Occurrence::kEvery;
    int &k1 = m.ord_k1[q], &k2 = m.ord_k2[q];
    long &t1 = m.ord_t1[q], &t2 = m.ord_t2[q];
    const bool a = Fires(o.first.action, n), b = Fires(o.second.action, n);
    const auto within = [&](long dt) { return dt >= ord_lo_[q] && dt <= ord_hi_[q]; };
    if (a && k1 < 0) {
      k1 = j;
      t1 = t;
    }
    if (o.ordered) {
      if (b && (every || k2 < 0)) {
        if (k1 < 0 || (o.strict && k1 == j) || !within(t - t1)) return false;
        k2 = j;
        t2 = t;
      }
      // The second end can no longer come in time.
      if (!every && k1 >= 0 && k2 < 0 && t - t1 > ord_hi_[q]) return false;
      continue;
    }
    if (b && k2 < 0) {
      k2 = j;
      t2 = t;
    }
    if (k1 >= 0 && k2 >= 0) {
      if ((a || b) && !within(std::labs(t2 - t1))) return false;
    } else if (k1 >= 0 || k2 >= 0) {
      if (t - (k1 >= 0 ? t1 : t2) > ord_hi_[q]) return false;
    }
  }
  return true;
}

std::vector<long> Expander::Key(const Node& n) const {
  std::vector<long> key;
  const std::size_t na = d_.automata.size();
  key.reserve(2 * na + 2 * (sp_.episodes.size() + sp_.temporals.size()));
  for (std::size_t a = 0; a < na; ++a) {
    key.push_back(n.loc[a]);
    key.push_back(std::min(n.time - n.entry[a], clock_cap_[a][n.loc[a]]));
  }
  const Monitors& m = n.mon;
  for (std::size_t p = 0; p < sp_.episodes.size(); ++p) {
    const int status = (m.ep_start[p] >= 0 ? 1 : 0) + (m.ep_end[p] >= 0 ? 1 : 0);
    key.push_back(status);
    key.push_back(status == 1 ? std::min(n.time - m.ep_start_t[p], ep_hi_[p] + 1) : 0);
  }
  for (std::size_t q = 0; q < sp_.temporals.size(); ++q) {
    const int status = (m.tc_k1[q] >= 0 ? 1 : 0) + (m.tc_k2[q] >= 0 ? 2 : 0);
    key.push_back(status);
    key.push_back(status == 1 || status == 2 ? std::min(n.time - m.tc_first_t[q], tc_hi_[q] + 1)
                                             : 0);
  }
  // Orders: which ends are done and how long ago the one the other waits for happened (an
  // `every` end stays open: its first end's age matters while the run goes on).
  for (std::size_t q = 0; q < sp_.orders.size(); ++q) {
    const int status = (m.ord_k1[q] >= 0 ? 1 : 0) + (m.ord_k2[q] >= 0 ? 2 : 0);
    key.push_back(status);
    const long since = m.ord_k1[q] >= 0 ? n.time - m.ord_t1[q] : m.ord_k2[q] >= 0 ? n.time - m.ord_t2[q] : 0;
    const long cap = (ord_hi_[q] < kInfinity ? ord_hi_[q] : ord_lo_[q]) + 1;  // beyond it no rule differs
    key.push_back(std::min(since, cap));
  }
  return key;
}

}  // namespace ctb::search
