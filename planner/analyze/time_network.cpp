#include "planner/model/number_text.h"
#include "planner/analyze/time_network.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

namespace ctb::analysis {

namespace {

constexpr double kEps = 1e-9;

bool PositiveLocation(const Expr& e) {
  return e.op == Expr::Op::kAtom && e.var_kind == VarKind::kLocation && !e.not_equal &&
         e.index.kind != IndexKind::kFixed;
}

// Earliest time e can hold when each location is entered no earlier than arr says. What it
// cannot bound counts as 0 (a lower bound must never overshoot).
double EarliestOf(const Expr& e, const std::vector<std::vector<double>>& arr) {
  switch (e.op) {
    case Expr::Op::kFalse: return kInf;
    case Expr::Op::kAtom: return PositiveLocation(e) ? arr[e.target][e.value_code] : 0;
    case Expr::Op::kAnd: return std::max(EarliestOf(e.kids[0], arr), EarliestOf(e.kids[1], arr));
    case Expr::Op::kOr: return std::min(EarliestOf(e.kids[0], arr), EarliestOf(e.kids[1], arr));
    default: return 0;
  }
}

// First entries over the abstraction's usable transitions (Bellman-Ford from above): a transition
// fires no earlier than its source's entry plus its lower duration, nor before every location
// its guard needs (a positive atom of a conjunction) has been entered.
std::vector<std::vector<double>> Arrivals(const Domain& d, const Abstraction& ab) {
  std::vector<std::vector<double>> arr(d.automata.size());
  std::size_t n = 0;
  for (std::size_t a = 0; a < d.automata.size(); ++a) {
    arr[a].assign(d.automata[a].locations.size(), kInf);
    arr[a][ab.init[a]] = 0;
    n += arr[a].size();
  }
  for (std::size_t round = 0; round <= n + 1; ++round) {
    bool changed = false;
    for (std::size_t a = 0; a < d.automata.size(); ++a)
      for (std::size_t t = 0; t < d.automata[a].transitions.size(); ++t) {
        const Transition& tr = d.automata[a].transitions[t];
        if (!ab.usable[a][t] || std::isinf(arr[a][tr.from])) continue;
        double fire = std::max(arr[a][tr.from] + tr.duration.lo, EarliestOf(tr.guard, arr));
        if (fire < arr[a][tr.to] - kEps) arr[a][tr.to] = fire, changed = true;
      }
    if (!changed) return arr;
  }
  // Not settled (cannot happen with non-negative durations): claim nothing.
  for (auto& v : arr) std::fill(v.begin(), v.end(), 0.0);
  return arr;
}

// The condition's value in the initial state (state conditions only; unknown atoms: kUnknown).
Tv InitialValue(const Expr& e, const std::vector<int>& init) {
  switch (e.op) {
    case Expr::Op::kTrue: return Tv::kTrue;
    case Expr::Op::kFalse: return Tv::kFalse;
    case Expr::Op::kNot: return Not(InitialValue(e.kids[0], init));
    case Expr::Op::kAnd: return And(InitialValue(e.kids[0], init), InitialValue(e.kids[1], init));
    case Expr::Op::kOr: return Or(InitialValue(e.kids[0], init), InitialValue(e.kids[1], init));
    case Expr::Op::kImplies:
      return Or(Not(InitialValue(e.kids[0], init)), InitialValue(e.kids[1], init));
    case Expr::Op::kIff: {
      Tv a = InitialValue(e.kids[0], init), b = InitialValue(e.kids[1], init);
      if (a == Tv::kUnknown || b == Tv::kUnknown) return Tv::kUnknown;
      return a == b ? Tv::kTrue : Tv::kFalse;
    }
    case Expr::Op::kAtom:
    case Expr::Op::kEvery:  // quantifiers are expanded at load: unknown if one were left
    case Expr::Op::kAny: break;
  }
  if (e.var_kind != VarKind::kLocation) return Tv::kUnknown;
  return (init[e.target] == e.value_code) != e.not_equal ? Tv::kTrue : Tv::kFalse;
}

// The one automaton whose locations alone decide c, or -1 (other atoms, several automata).
int SoleAutomaton(const Expr& e) {
  if (e.op == Expr::Op::kAtom) return e.var_kind == VarKind::kLocation ? e.target : -2;
  int who = -1;
  for (const auto& k : e.kids) {
    int x = SoleAutomaton(k);
    if (x == -2 || (x >= 0 && who >= 0 && x != who)) return -2;
    if (x >= 0) who = x;
  }
  return who;
}

struct Node {
  std::string owner;  // the part the node belongs to ("" for the origin)
  std::string desc;   // "the start of episode P"
  const Condition* cond = nullptr;  // what holds at the node (null: none known)
  const Condition* state = nullptr;  // an episode start: its state constraint on the next stage
  bool first = false;  // the first event at which cond holds
  std::vector<std::vector<Opt>> opts;  // per automaton, the options possible at the node
};

struct Edge {
  int u = 0, v = 0;
  double w = 0;                    // x_v - x_u <= w
  std::set<std::string> parts;     // the parts the edge needs
  std::string why;
  std::string bound;               // the bound pointer of a state-plan bound edge
};

class Network {
 public:
  Network(const Domain& d, const StatePlan& sp, const Abstraction& ab, const std::string& maint)
      : d_(d), sp_(sp), ab_(ab), maint_(maint), arr_(Arrivals(d, ab)) {}

  std::optional<TimeConflict> Run() {
    BuildNodes();
    BuildEdges();
    Gaps();
    std::set<std::string> all;
    for (const auto& e : edges_) all.insert(e.parts.begin(), e.parts.end());
    if (!maint_.empty()) all.insert(maint_);
    std::vector<Leaf> proof;
    if (!Refuted(all, &proof)) return std::nullopt;
    // Deletion filter over the parts the proof used: a smallest set the network still refutes.
    std::set<std::string> keep;
    for (const auto& leaf : proof)
      for (const auto& e : leaf.cycle) keep.insert(e.parts.begin(), e.parts.end());
    if (!Refuted(keep, nullptr)) keep = all;  // the case split chose otherwise: start from all
    for (const std::string& p : std::set<std::string>(keep)) {
      if (p == maint_) continue;  // the abstraction itself needs it
      std::set<std::string> rest = keep;
      rest.erase(p);
      if (Refuted(rest, nullptr)) keep = rest;
    }
    proof.clear();
    Refuted(keep, &proof);
    TimeConflict out;
    for (const auto& p : keep)
      if (p != maint_) out.parts.push_back(p);
    if (keep.count(maint_)) out.parts.push_back(maint_);
    out.text = Text(proof);
    Hints(keep, out.hints);
    return out;
  }

 private:
  int AddNode(Node n) {
    nodes_.push_back(std::move(n));
    return static_cast<int>(nodes_.size()) - 1;
  }

  std::vector<std::vector<Opt>> OptionsOf(const std::vector<Term>& terms) const {
    return Project(ab_, terms);
  }

  // The options at a node, an event no later than the goal event: besides the node's terms, the
  // guards of the transitions taken there hold on the stage before, and so does the maintenance
  // constraint under it (that stage is before the goal event; at e[0] the abstraction's initial
  // state satisfies it).
  std::vector<std::vector<Opt>> NodeOptions(std::vector<Term> terms) const {
    if (!maint_.empty()) terms.push_back(OnStageBefore(sp_.maintenance));
    return Project(ab_, terms, true);
  }

  void BuildNodes() {
    Node z;
    z.desc = "the start";
    z.opts.resize(d_.automata.size());
    for (std::size_t a = 0; a < d_.automata.size(); ++a) z.opts[a] = {{ab_.init[a], ab_.init[a]}};
    AddNode(z);
    for (const auto& ep : sp_.episodes) {
      const std::string p = "/constraints/episodes/" + PointerToken(ep.name);
      Node s{p, "the start of episode " + ep.name, &ep.accepting, &ep.state, true, {}};
      s.opts = NodeOptions({AtEvent(ep.accepting), OnStage(ep.state)});
      Node e{p, "the end of episode " + ep.name, nullptr, nullptr, false, {}};
      // At the end event the stage before it still satisfies the state constraint.
      e.opts = NodeOptions({OnStageBefore(ep.state)});
      ep_.push_back({AddNode(s), AddNode(e)});
    }
    for (const auto& tc : sp_.temporals) {
      const std::string p = "/constraints/temporal/" + PointerToken(tc.name);
      // Which condition activates the constraint: one that surely holds at e[0], or one the
      // other cannot precede; else unknown (either order).
      int order = 0;  // 1: event 1 first, 2: event 2 first
      if (SurelyInitially(tc.event1) || Precedes(tc.event1, tc.event2)) order = 1;
      else if (SurelyInitially(tc.event2) || Precedes(tc.event2, tc.event1)) order = 2;
      Node a{p, "", nullptr, nullptr, order != 0, {}}, b{p, "", nullptr, nullptr, false, {}};
      if (order) {
        const Condition& c1 = order == 1 ? tc.event1 : tc.event2;
        const Condition& c2 = order == 1 ? tc.event2 : tc.event1;
        a.cond = &c1, b.cond = &c2;
        a.opts = NodeOptions({AtEvent(c1)}), b.opts = NodeOptions({AtEvent(c2)});
        a.desc = std::string("event ") + (order == 1 ? "1" : "2") + " of temporal constraint " + tc.name;
        b.desc = std::string("event ") + (order == 1 ? "2" : "1") + " of temporal constraint " + tc.name;
      } else {
        auto o1 = NodeOptions({AtEvent(tc.event1)}), o2 = NodeOptions({AtEvent(tc.event2)});
        for (std::size_t k = 0; k < o1.size(); ++k) o1[k].insert(o1[k].end(), o2[k].begin(), o2[k].end());
        a.opts = b.opts = o1;
        a.desc = "the first event of temporal constraint " + tc.name;
        b.desc = "the second event of temporal constraint " + tc.name;
      }
      tc_.push_back({AddNode(a), AddNode(b), order});
    }
  }

  // held[l]: whether the condition read on one stage may hold with automaton a in l.
  std::vector<char> Held(const Condition& c, int a) const {
    const int n = static_cast<int>(d_.automata[a].locations.size());
    std::vector<char> held(n, 1);
    std::vector<std::vector<Opt>> opts = ab_.stage_opts;
    for (int l = 0; l < n; ++l) {
      opts[a] = {{l, l}};
      std::vector<Term> terms{OnStage(c)};
      held[l] = SatSearch(ab_.init, opts, terms).Run();
    }
    return held;
  }

  bool SurelyInitially(const Condition& c) const {
    return !c.raw_info.IsChange() && InitialValue(c.raw, ab_.init) == Tv::kTrue;
  }

  // Whether `later` cannot hold at any event before the first at which `first` holds. Needs
  // `first` to depend on one automaton's locations only (then it holds exactly when that
  // automaton takes one of its options), and follows that automaton's paths avoiding them.
  bool Precedes(const Condition& first, const Condition& later) const {
    const int a = SoleAutomaton(first.raw);
    if (a < 0) return false;
    auto holds = OptionsOf({AtEvent(first)});
    auto in = [&](const Opt& o) {
      for (const Opt& x : holds[a])
        if (x.prev == o.prev && x.next == o.next) return true;
      return false;
    };
    const int init = ab_.init[a];
    if (!first.raw_info.IsChange() && in({init, init})) return true;  // it holds at e[0]
    // `later` may hold at e[0], read on the initial stage, before any change `first` needs.
    if (!later.raw_info.IsChange() && InitialValue(later.raw, ab_.init) != Tv::kFalse) return false;
    std::vector<char> seen(d_.automata[a].locations.size(), 0);
    seen[init] = 1;
    for (bool grew = true; grew;) {
      grew = false;
      for (const Opt& o : ab_.event_opts[a])
        if (o.prev != o.next && seen[o.prev] && !seen[o.next] && !in(o)) seen[o.next] = 1, grew = true;
    }
    std::vector<std::vector<Opt>> opts = ab_.event_opts;
    opts[a].clear();
    for (const Opt& o : ab_.event_opts[a])
      if (seen[o.prev] && seen[o.next] && !in(o)) opts[a].push_back(o);
    if (opts[a].empty()) return true;
    std::vector<Term> terms{AtEvent(later)};
    return !SatSearch(ab_.init, opts, terms).Run();
  }

  void Add(int u, int v, double w, std::set<std::string> parts, std::string why,
           std::string bound = "") {
    if (!nodes_[u].owner.empty()) parts.insert(nodes_[u].owner);
    if (!nodes_[v].owner.empty()) parts.insert(nodes_[v].owner);
    edges_.push_back({u, v, w, std::move(parts), std::move(why), std::move(bound)});
  }

  // " while the maintenance constraint holds" under it.
  std::string Under() const { return maint_.empty() ? "" : " while the maintenance constraint holds"; }

  std::set<std::string> Automata() const {
    return maint_.empty() ? std::set<std::string>{} : std::set<std::string>{maint_};
  }

  // Edges from the automata between node x and a node y at the same or a later event.
  void Travel(int x, int y, const std::set<std::string>& extra) {
    double gap = LeastGap(ab_, nodes_[x].opts, nodes_[y].opts);
    if (gap <= kEps || std::isinf(gap)) return;
    auto parts = Automata();
    parts.insert(extra.begin(), extra.end());
    Add(y, x, -gap, parts,
        nodes_[y].desc + " comes at least " + NumberText(gap) + " s after " + nodes_[x].desc + Under());
  }

  void BuildEdges() {
    const int n = static_cast<int>(nodes_.size());
    for (int v = 1; v < n; ++v) {
      Add(v, 0, 0, {}, "");
      double t = 0;
      const Node& x = nodes_[v];
      if (x.cond) t = EarliestOf(x.cond->raw, arr_);
      else if (x.opts.size() && v > 0) {
        // Either condition (a temporal constraint of unknown order).
        const Temporal* tc = nullptr;
        for (std::size_t q = 0; q < tc_.size(); ++q)
          if (tc_[q].a == v || tc_[q].b == v) tc = &sp_.temporals[q];
        if (tc) t = std::min(EarliestOf(tc->event1.raw, arr_), EarliestOf(tc->event2.raw, arr_));
      }
      if (t > kEps && !std::isinf(t))
        Add(v, 0, -t, Automata(), x.desc + " cannot come before " + NumberText(t) + " s" + Under());
      if (x.first && x.cond && SurelyInitially(*x.cond))
        Add(0, v, 0, {}, x.desc + " is at the start (its condition holds in the initial state)");
    }
    for (std::size_t p = 0; p < ep_.size(); ++p) {
      const Episode& ep = sp_.episodes[p];
      const std::string ptr = nodes_[ep_[p].s].owner;
      Add(ep_[p].s, ep_[p].e, ep.upper, {}, "episode " + ep.name + " lasts at most " + NumberText(ep.upper) + " s",
          ptr + "/upper_bound");
      Add(ep_[p].e, ep_[p].s, -ep.lower, {}, "episode " + ep.name + " lasts at least " + NumberText(ep.lower) + " s",
          ptr + "/lower_bound");
    }
    for (std::size_t q = 0; q < tc_.size(); ++q) {
      const Temporal& tc = sp_.temporals[q];
      const std::string ptr = nodes_[tc_[q].a].owner;
      Add(tc_[q].a, tc_[q].b, tc.upper, {},
          "temporal constraint " + tc.name + " allows at most " + NumberText(tc.upper) + " s between its events",
          ptr + "/upper_bound");
      Add(tc_[q].b, tc_[q].a, -tc.lower, {},
          "temporal constraint " + tc.name + " needs at least " + NumberText(tc.lower) + " s between its events",
          ptr + "/lower_bound");
      Travel(tc_[q].a, tc_[q].b, {});
    }
    for (const auto& ev : sp_.events) {
      const std::string ptr = "/constraints/event/" + PointerToken(ev.name);
      int prev = -1;
      for (const auto& e : ev.endpoints) {
        int v = NodeOf(e);
        if (v < 0) continue;
        if (prev >= 0) {
          // Which node a temporal constraint's endpoint is may rest on the abstraction (rule 5).
          std::set<std::string> parts = Automata();
          parts.insert(ptr);
          Add(prev, v, 0, parts, "shared event " + ev.name + " puts " + nodes_[prev].desc +
                                     " and " + nodes_[v].desc + " on one event");
          Add(v, prev, 0, parts, "shared event " + ev.name + " puts " + nodes_[prev].desc +
                                     " and " + nodes_[v].desc + " on one event");
        }
        prev = v;
      }
    }
    // Order: y cannot hold before the first occurrence of x's condition.
    for (int x = 1; x < n; ++x) {
      if (!nodes_[x].first || !nodes_[x].cond) continue;
      for (int y = 1; y < n; ++y) {
        if (y == x || !nodes_[y].cond || !Precedes(*nodes_[x].cond, *nodes_[y].cond)) continue;
        Travel(x, y, {});
        // Dwell: an episode starting at x keeps its automata where y cannot hold, until its end.
        for (std::size_t p = 0; p < ep_.size(); ++p)
          if (ep_[p].s == x) Dwell(p, y);
      }
    }
    for (std::size_t p = 0; p < ep_.size(); ++p) Travel(ep_[p].s, ep_[p].e, {});
  }

  // y comes at or after the start of episode p: if y's condition cannot hold on an event whose
  // next stage satisfies the state constraint, y comes after the episode's end.
  void Dwell(std::size_t p, int y) {
    const Episode& ep = sp_.episodes[p];
    std::vector<std::vector<Opt>> inside = ab_.event_opts;
    for (std::size_t a = 0; a < d_.automata.size(); ++a) {
      auto held = Held(ep.state, static_cast<int>(a));
      std::vector<Opt> keep;
      for (const Opt& o : inside[a])
        if (held[o.next]) keep.push_back(o);
      inside[a] = keep;
    }
    std::vector<Term> terms{AtEvent(*nodes_[y].cond)};
    if (SatSearch(ab_.init, inside, terms).Run()) return;
    const int e = ep_[p].e;
    double gap = LeastGap(ab_, nodes_[e].opts, nodes_[y].opts);
    if (gap <= kEps || std::isinf(gap)) gap = 0;
    auto parts = Automata();
    Add(y, e, -gap, parts,
        nodes_[y].desc + " comes after the end of episode " + ep.name + " (its state constraint "
        "rules it out until then)" + (gap > kEps ? ", at least " + NumberText(gap) + " s after it" : "") +
            Under());
  }

  int NodeOf(const Endpoint& e) const {
    switch (e.kind) {
      case EndpointKind::kEpisodeStart: return ep_[e.index].s;
      case EndpointKind::kEpisodeEnd: return ep_[e.index].e;
      case EndpointKind::kEvent1:
        return tc_[e.index].order == 1 ? tc_[e.index].a : tc_[e.index].order == 2 ? tc_[e.index].b : -1;
      case EndpointKind::kEvent2:
        return tc_[e.index].order == 1 ? tc_[e.index].b : tc_[e.index].order == 2 ? tc_[e.index].a : -1;
    }
    return -1;
  }

  bool Usable(const Edge& e, const std::set<std::string>& parts) const {
    for (const auto& p : e.parts)
      if (!parts.count(p)) return false;
    return true;
  }

  // Floyd-Warshall over `edges`: true when they hold a negative cycle (its edges in `cycle`);
  // else the shortest distances (dist[u * n + v] bounds x_v - x_u) in `dist`.
  bool NegativeCycle(const std::vector<Edge>& edges, std::vector<Edge>* cycle,
                     std::vector<double>* dist_out) const {
    const int n = static_cast<int>(nodes_.size());
    std::vector<double> dist(n * n, kInf);
    std::vector<int> via(n * n, -1);  // the last edge of the best path
    for (int k = 0; k < n; ++k) dist[k * n + k] = 0;
    for (int k = 0; k < static_cast<int>(edges.size()); ++k) {
      const Edge& e = edges[k];
      if (e.w < dist[e.u * n + e.v]) dist[e.u * n + e.v] = e.w, via[e.u * n + e.v] = k;
    }
    for (int k = 0; k < n; ++k)
      for (int i = 0; i < n; ++i) {
        if (std::isinf(dist[i * n + k])) continue;
        for (int j = 0; j < n; ++j)
          if (dist[i * n + k] + dist[k * n + j] < dist[i * n + j] - kEps) {
            dist[i * n + j] = dist[i * n + k] + dist[k * n + j];
            via[i * n + j] = via[k * n + j];
          }
      }
    for (int i = 0; i < n; ++i) {
      if (dist[i * n + i] >= -kEps) continue;
      if (cycle) {
        // Walk back from i along the last edges of the best path i -> i.
        cycle->clear();
        int j = i, guard = 0;
        do {
          int k = via[i * n + j];
          if (k < 0) break;
          cycle->push_back(edges[k]);
          j = edges[k].u;
        } while (j != i && ++guard <= n);
        std::reverse(cycle->begin(), cycle->end());
      }
      return true;
    }
    if (dist_out) *dist_out = std::move(dist);
    return false;
  }

  // One branch of a proof: a negative cycle under the orders of nodes assumed in `cases`.
  struct Leaf {
    std::vector<std::string> cases;
    std::vector<Edge> cycle;
  };

  // Whether the network of the edges whose parts are all in `parts` has no solution (with edge
  // `override_edge`'s weight replaced by override_w). Two nodes happen in one order or the other
  // (by event number, so by time), and each order brings the travel time between them (rule 6):
  // when no order of a pair is implied already, the proof splits on it and needs a negative
  // cycle in both branches (a disjunctive temporal network). At most kSplitBudget networks are
  // solved; beyond, no proof. The leaves go to `proof`.
  bool Refuted(const std::set<std::string>& parts, std::vector<Leaf>* proof,
               int override_edge = -1, double override_w = 0) const {
    std::vector<Edge> edges;
    for (int k = 0; k < static_cast<int>(edges_.size()); ++k) {
      if (!Usable(edges_[k], parts)) continue;
      edges.push_back(edges_[k]);
      if (k == override_edge) edges.back().w = override_w;
    }
    std::vector<std::string> cases;
    int budget = kSplitBudget;
    return Split(parts, edges, cases, proof, budget);
  }

  static constexpr int kSplitBudget = 64;

  bool Split(const std::set<std::string>& parts, std::vector<Edge>& edges,
             std::vector<std::string>& cases, std::vector<Leaf>* proof, int& budget) const {
    if (--budget < 0) return false;
    std::vector<Edge> cycle;
    std::vector<double> dist;
    if (NegativeCycle(edges, proof ? &cycle : nullptr, &dist)) {
      if (proof) proof->push_back({cases, std::move(cycle)});
      return true;
    }
    const int n = static_cast<int>(nodes_.size());
    // The pair to split on: one whose either order is refuted at once first.
    int bx = -1, by = -1, best = -1;
    for (int x = 1; x < n; ++x)
      for (int y = x + 1; y < n; ++y) {
        const double gxy = gap_[x * n + y], gyx = gap_[y * n + x];
        if (gxy <= kEps && gyx <= kEps) continue;
        if (!Present(x, parts) || !Present(y, parts)) continue;
        // "x first" adds x_x - x_y <= -gxy; implied already: the branch adds nothing.
        if (dist[y * n + x] <= -gxy + kEps || dist[x * n + y] <= -gyx + kEps) continue;
        const int score = (dist[x * n + y] - gxy < -kEps) + (dist[y * n + x] - gyx < -kEps);
        if (score > best) best = score, bx = x, by = y;
      }
    if (bx < 0) return false;
    for (int first : {bx, by}) {
      const int later = first == bx ? by : bx;
      const double g = gap_[first * n + later];
      Edge e{later, first, -g, Automata(), "", ""};
      e.parts.insert(nodes_[first].owner);
      e.parts.insert(nodes_[later].owner);
      e.parts.erase("");
      e.why = g > kEps ? nodes_[later].desc + " comes at least " + NumberText(g) + " s after " +
                             nodes_[first].desc + Under()
                       : "";
      edges.push_back(e);
      cases.push_back(nodes_[first].desc + " comes no later than " + nodes_[later].desc);
      const bool refuted = Split(parts, edges, cases, proof, budget);
      edges.pop_back();
      cases.pop_back();
      if (!refuted) return false;
    }
    return true;
  }

  bool Present(int v, const std::set<std::string>& parts) const {
    return nodes_[v].owner.empty() || parts.count(nodes_[v].owner);
  }

  // gap_[x * n + y]: the least travel time from node x to node y at the same or a later event.
  // Each gap is a bound of its own and 0 claims nothing, so the pairs not reached within
  // kGapBudget (many nodes: the pairs grow as their square) are left at 0: fewer splits can
  // refute, none wrongly. Static analysis runs before every solve and must stay cheap.
  void Gaps() {
    const int n = static_cast<int>(nodes_.size());
    gap_.assign(n * n, 0);
    const auto t0 = std::chrono::steady_clock::now();
    for (int x = 1; x < n; ++x) {
      if (std::chrono::steady_clock::now() - t0 > kGapBudget) return;
      for (int y = 1; y < n; ++y)
        if (x != y) {
          double g = LeastGap(ab_, nodes_[x].opts, nodes_[y].opts);
          gap_[x * n + y] = std::isinf(g) ? 0 : g;
        }
    }
  }
  static constexpr std::chrono::milliseconds kGapBudget{100};

  std::string Steps(const std::vector<Edge>& cycle) const {
    std::string s;
    double sum = 0;
    for (const auto& e : cycle) {
      sum += e.w;
      if (e.why.empty()) continue;
      s += (s.empty() ? "" : "; ") + e.why;
    }
    if (sum < 0 && !std::isinf(sum)) s += " (" + NumberText(-sum) + " s too little)";
    return s;
  }

  std::string Text(const std::vector<Leaf>& proof) const {
    std::string s = "These cannot all hold, whatever the number of events: ";
    if (proof.size() == 1 && proof[0].cases.empty()) return s + Steps(proof[0].cycle) + ".";
    s += "whichever order their events take, time runs short.";
    for (const auto& leaf : proof) {
      std::string cases;
      for (const auto& c : leaf.cases) cases += (cases.empty() ? "" : " and ") + c;
      s += " If " + cases + ": " + Steps(leaf.cycle) + ".";
    }
    return s;
  }

  // For each bound edge of the conflict: the least relaxation the network no longer refutes.
  void Hints(const std::set<std::string>& parts, std::vector<BoundHint>& out) const {
    const double res = d_.time_resolution > 0 ? d_.time_resolution : 1;
    for (int k = 0; k < static_cast<int>(edges_.size()); ++k) {
      const Edge& e = edges_[k];
      if (e.bound.empty() || !Usable(e, parts)) continue;
      const bool upper = e.bound.size() > 12 && e.bound.substr(e.bound.size() - 12) == "/upper_bound";
      // In steps of the resolution: the edge weight is upper or -lower.
      long bad = std::lround(e.w / res), good = upper ? std::lround(1e7 / res) : 0;
      if (upper ? bad >= good : bad >= 0) continue;
      if (Refuted(parts, nullptr, k, good * res)) continue;  // this bound alone cannot help
      if (!Refuted(parts, nullptr, k, bad * res)) continue;  // not on a cycle
      while (good - bad > 1) {
        long mid = bad + (good - bad) / 2;
        if (Refuted(parts, nullptr, k, mid * res)) bad = mid;
        else good = mid;
      }
      out.push_back({e.bound, upper ? good * res : -good * res});
    }
  }

  struct EpNodes {
    int s, e;
  };
  struct TcNodes {
    int a, b, order;
  };

  const Domain& d_;
  const StatePlan& sp_;
  const Abstraction& ab_;
  const std::string maint_;
  const std::vector<std::vector<double>> arr_;
  std::vector<Node> nodes_;
  std::vector<Edge> edges_;
  std::vector<EpNodes> ep_;
  std::vector<TcNodes> tc_;
  std::vector<double> gap_;
};

}  // namespace

std::optional<TimeConflict> FindTimeConflict(const Domain& d, const StatePlan& sp,
                                             const Abstraction& ab,
                                             const std::string& maintenance) {
  if (ab.only_initial) return std::nullopt;  // the single-part checks handle it
  return Network(d, sp, ab, maintenance).Run();
}

}  // namespace ctb::analysis
