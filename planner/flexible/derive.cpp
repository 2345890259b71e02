// The temporal network of a verified trajectory (flexible.h, docs/uncertainty.md).
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <tuple>

#include "planner/expr/expr_print.h"
#include "planner/flexible/flexible.h"

namespace ctb::flexible {

namespace {

using network::Link;
using network::Point;
using network::PointKind;
using network::Ticks;

// A set of automata whose transitions keep their plan order, and extra points (the marks of a
// state plan's events) ordered with them.
struct Observer {
  std::set<int> automata;
  std::vector<int> points;
  std::string why;
};

class Deriver {
 public:
  Deriver(const Trajectory& t, const Domain& d, const StatePlan& sp, long tps)
      : t_(t), d_(d), sp_(sp), tps_(tps), ms_per_tick_(1000 / tps) {}

  FlexiblePlan Run() {
    f_.tps = tps_;
    f_.rigid = Rigid(f_.rigid_reason);
    MakePoints();
    for (std::size_t a = 0; a < d_.automata.size(); ++a) Stays(static_cast<int>(a));
    Anchors();
    Orders();
    if (t_.history) PinHistory();
    return std::move(f_);
  }

 private:
  Ticks Ms(long ticks) const { return static_cast<Ticks>(ticks) * ms_per_tick_; }
  Ticks MsOf(double seconds) const { return Ms(std::lround(seconds * static_cast<double>(tps_))); }

  // Rigid order where the observers below do not see everything a rule reads.
  bool Rigid(std::string& why) const {
    if (t_.history) return (why = "a replan's history"), true;
    for (const auto& a : d_.automata)
      for (const auto& tr : a.transitions) {
        if (tr.commanded) continue;
        for (int b : tr.guard_info.commands_read)
          if (b != d_.AutomatonIndex(a.name))
            return (why = "an automatic transition of '" + a.name + "' reads a command"), true;
      }
    // A condition that reads an accepting automaton's state (seen at the event after it
    // changes), a command or a fixed stage may first hold at an event where none of the automata
    // it reads moves: its mark could not be kept by the observers.
    std::vector<const Condition*> all = {&sp_.goal, &sp_.maintenance};
    for (const auto& e : sp_.episodes) all.insert(all.end(), {&e.accepting, &e.state});
    for (const auto& q : sp_.temporals) all.insert(all.end(), {&q.event1, &q.event2});
    for (const Condition* c : all) {
      const ExprInfo& i = c->raw_info;
      if (!i.episodes_read.empty() || !i.temporals_read.empty())
        return (why = c->pointer + " reads an accepting automaton"), true;
      if (!i.commands_read.empty()) return (why = c->pointer + " reads a command"), true;
      if (i.uses_fixed) return (why = c->pointer + " reads a fixed stage"), true;
    }
    return false;
  }

  int AddPoint(PointKind kind, int event, int automaton, int transition,
               std::map<std::string, std::string> labels) {
    Point p;
    p.id = static_cast<int>(f_.net.points.size());
    p.kind = kind;
    p.labels = std::move(labels);
    f_.net.points.push_back(std::move(p));
    f_.point_event.push_back(event);
    f_.point_automaton.push_back(automaton);
    f_.point_transition.push_back(transition);
    if (event >= 0 && event < static_cast<int>(at_event_.size()) && automaton >= 0)
      at_event_[event].push_back(f_.net.points.back().id);
    return f_.net.points.back().id;
  }

  // The origin, then one point per transition in event order (automaton order within one).
  void MakePoints() {
    at_event_.assign(t_.events.size(), {});
    AddPoint(PointKind::kOrigin, 0, -1, -1, {});
    std::vector<FiredTransition> fired = t_.fired;
    std::stable_sort(fired.begin(), fired.end(), [](const auto& x, const auto& y) {
      return std::tie(x.event, x.automaton) < std::tie(y.event, y.automaton);
    });
    chain_.assign(d_.automata.size(), {});
    for (const auto& fi : fired) {
      const Automaton& a = d_.automata[fi.automaton];
      const Transition& tr = a.transitions[fi.transition];
      std::map<std::string, std::string> labels = {
          {"automaton", a.name}, {"from", a.locations[tr.from]}, {"to", a.locations[tr.to]}};
      if (tr.commanded && tr.command > 0) labels["command"] = a.commands[tr.command - 1];
      const int p = AddPoint(tr.contingent ? PointKind::kContingent : PointKind::kControllable,
                             fi.event, fi.automaton, fi.transition, std::move(labels));
      chain_[fi.automaton].push_back(p);
    }
  }

  // The origin of the links added while it lives (cut.h restates them of other plans).
  struct Source {
    Source(Deriver* d, LinkOrigin o) : d_(d), saved_(d->origin_) { d_->origin_ = std::move(o); }
    ~Source() { d_->origin_ = std::move(saved_); }
    Deriver* d_;
    LinkOrigin saved_;
  };
  static LinkOrigin Of(LinkSource s, std::optional<CutMark> from = std::nullopt,
                       std::optional<CutMark> to = std::nullopt) {
    LinkOrigin o;
    o.source = s;
    o.from_mark = from;
    o.to_mark = to;
    return o;
  }
  static CutMark MarkOf(EndpointKind k, int index) {
    CutMark m;
    m.endpoint = k;
    m.index = index;
    return m;
  }
  static CutMark GoalMark() {
    CutMark m;
    m.kind = CutMark::Kind::kGoal;
    return m;
  }

  bool AddLink(int from, int to, Ticks lb, std::optional<Ticks> ub, bool contingent,
               std::string why) {
    auto key = std::make_tuple(from, to, lb, ub.value_or(-1), ub.has_value(), contingent);
    if (!seen_.insert(key).second) return false;
    f_.origins.push_back(origin_);
    Link l;
    l.from = from;
    l.to = to;
    l.lb = lb;
    l.ub = ub;
    l.contingent = contingent;
    l.why = std::move(why);
    f_.net.links.push_back(std::move(l));
    return true;
  }

  // Two points the plan had at one event stay at one event; `why` says what needs it (a tie is the
  // derivation's, not a bound of the state plan: its why does not start with a pointer).
  void Tie(int x, int y, const std::string& why) {
    if (x == y) return;
    AddLink(x, y, 0, Ticks{0}, false, "one event in the plan, for " + why);
    f_.same_event.emplace_back(x, y);
  }

  // x no later than y. Before an automatic transition that the plan had strictly later, x stays
  // strictly earlier: an event at the very moment it is due would have to carry it.
  void Order(int x, int y, const std::string& why) {
    if (x == y) return;
    Ticks lb = 0;
    if (y > 0 && Automatic(y) && t_.events[f_.point_event[x]] < t_.events[f_.point_event[y]])
      lb = ms_per_tick_;
    if (AddLink(x, y, lb, std::nullopt, false, why) && lb > 0) f_.origins.back().strict_tick = true;
    f_.before.emplace_back(x, y);
  }

  bool Automatic(int p) const {
    const Transition& tr = d_.automata[f_.point_automaton[p]].transitions[f_.point_transition[p]];
    return !tr.commanded && !tr.controllable && !tr.contingent;
  }

  std::string TransitionName(int a, int ti) const {
    const Automaton& au = d_.automata[a];
    const Transition& tr = au.transitions[ti];
    return au.name + " " + au.locations[tr.from] + "->" + au.locations[tr.to];
  }

  bool GuardOn(const Transition& tr, int stage) const {
    return Evaluate(tr.guard, [&](const Expr& atom) {
      return atom.var_kind == VarKind::kLocation ? t_.locations[atom.target][stage]
                                                 : t_.commands[atom.target][stage];
    });
  }

  // A point at plan event k of an automaton in `among` (any point at k when none); -1 if none.
  int PointAt(int k, const std::set<int>& among) const {
    if (k <= 0) return 0;
    if (k >= static_cast<int>(at_event_.size()) || at_event_[k].empty()) return -1;
    for (int p : at_event_[k])
      if (among.count(f_.point_automaton[p])) return p;
    fallback_mark_ = true;  // nothing it reads moves there: rigid order (Orders)
    return at_event_[k].front();
  }

  // Every stay of automaton a: from its entry (a point, or the origin at time 0) to its exit
  // (the next transition's point, or the goal).
  void Stays(int a) {
    const Automaton& au = d_.automata[a];
    int entry = 0, entry_event = 0;
    const auto& chain = chain_[a];
    for (std::size_t i = 0; i <= chain.size(); ++i) {
      const int exit = i < chain.size() ? chain[i] : -1;
      const int exit_event = exit >= 0 ? f_.point_event[exit] : t_.goal_event;
      const int loc = t_.locations[a][entry_event];
      if (exit >= 0) {
        const Transition& tr = au.transitions[f_.point_transition[exit]];
        const Ticks lo = MsOf(tr.duration.lo);
        const std::optional<Ticks> hi =
            tr.duration.hi ? std::optional(MsOf(*tr.duration.hi)) : std::nullopt;
        Source src(this, Of(LinkSource::kDuration));
        AddLink(entry, exit, lo, hi, tr.contingent,
                "duration " + TransitionName(a, f_.point_transition[exit]));
      }
      for (std::size_t ti = 0; ti < au.transitions.size(); ++ti) {
        const Transition& tr = au.transitions[ti];
        if (tr.from != loc || tr.commanded) continue;
        const bool fires = exit >= 0 && f_.point_transition[exit] == static_cast<int>(ti);
        Enabled(a, static_cast<int>(ti), entry, entry_event, exit, exit_event, fires);
      }
      if (exit < 0) break;
      entry = exit;
      entry_event = exit_event;
    }
  }

  // The rules of an automatic or controllable transition `ti` of automaton a over one stay,
  // wherever its guard holds (stages entry_event .. exit_event - 1).
  void Enabled(int a, int ti, int entry, int entry_event, int exit, int exit_event, bool fires) {
    const Transition& tr = d_.automata[a].transitions[ti];
    const std::string name = TransitionName(a, ti);
    const Ticks lo = MsOf(tr.duration.lo);
    std::set<int> reads(tr.guard_info.locations_read.begin(), tr.guard_info.locations_read.end());
    for (int k = entry_event + 1; k <= exit_event; ++k) {
      if (!GuardOn(tr, k - 1)) continue;
      const int start = k - 1;  // the guard holds from the event before k ...
      while (k + 1 <= exit_event && GuardOn(tr, k)) ++k;
      const int last = k;  // ... up to event `last` (its stage before holds)
      const int last_point = last == exit_event && exit >= 0 ? exit : PointAt(last, reads);
      if (tr.controllable || tr.contingent) {
        // Its duration link bounds the stay when it fires; otherwise no stage it is enabled on
        // may last past hi. (The point at `last` follows entry in plan order: lb 0 holds.)
        if (tr.duration.hi && last_point >= 0 && !(fires && last == exit_event))
          AddLink(entry, last_point, 0, MsOf(*tr.duration.hi), false, "no overstay " + name);
        continue;
      }
      if (fires && last == exit_event) {
        Due(a, ti, entry, start, exit, lo, reads, name);
      } else if (last_point >= 0) {
        // Held without firing: the clock stays below lo until the guard stops holding.
        AddLink(entry, last_point, 0, lo - ms_per_tick_, false, "not yet due " + name);
      } else {
        if (entry > 0) Pin(entry);
      }
    }
  }

  // An automatic transition fires when due: at entry + lo (its duration the cause), or at the
  // event that made its guard true (that event the cause), as in the plan.
  void Due(int a, int ti, int entry, int start, int exit, Ticks lo, const std::set<int>& reads,
           const std::string& name) {
    const long te = t_.events[f_.point_event[exit]];
    const long tentry = t_.events[f_.point_event[entry]];
    const Ticks lo_ticks = lo / ms_per_tick_;
    if (te == tentry + lo_ticks) {
      AddLink(entry, exit, lo, lo, false, "due at its duration " + name);
      return;
    }
    const int cause = start > f_.point_event[entry] ? PointAt(start, reads) : -1;
    if (cause >= 0 && t_.events[start] == te) {
      AddLink(cause, exit, 0, Ticks{0}, false, "due when its guard holds " + name);
      f_.before.emplace_back(cause, exit);
      f_.due_after.emplace_back(cause, exit);
      return;
    }
    (void)a;
    (void)ti;
    Pin(exit);
  }

  // A point held at its plan time (what the rules here cannot free).
  void Pin(int p) {
    const Ticks at = Ms(t_.events[f_.point_event[p]]);
    AddLink(0, p, at, at, false, "fixed at its plan time");
  }

  // A replan's history is what happened, never checked against the model (a late report breaks a
  // duration, an observed jump resets a clock): its points are pinned at their times, and a link
  // between two of them is dropped (the pins say all). A link from the history to the future
  // that the verified plan itself does not meet (a stay whose clock an observation reset) says
  // nothing true either: it is dropped and its future end pinned at its planned time (sound,
  // rigid for that point). Without this, the network of a plan whose history broke a bound was
  // inconsistent.
  void PinHistory() {
    const int p = t_.history->events();
    auto hist = [&](int x) { return x == 0 || f_.point_event[x] <= p; };
    auto time = [&](int x) { return x == 0 ? Ticks{0} : Ms(t_.events[f_.point_event[x]]); };
    std::vector<Link> kept;
    std::vector<LinkOrigin> kept_origins;
    std::set<int> pin;
    for (std::size_t li = 0; li < f_.net.links.size(); ++li) {
      const Link& l = f_.net.links[li];
      if (hist(l.from) && hist(l.to)) continue;
      if (hist(l.from) != hist(l.to)) {
        const Ticks dt = time(l.to) - time(l.from);
        if (dt < l.lb || (l.ub && dt > *l.ub)) {
          pin.insert(hist(l.from) ? l.to : l.from);
          continue;
        }
      }
      kept.push_back(l);
      kept_origins.push_back(f_.origins[li]);
    }
    f_.net.links = std::move(kept);
    f_.origins = std::move(kept_origins);
    std::set<int> contingent_ends;
    for (const Link& l : f_.net.links)
      if (l.contingent) contingent_ends.insert(l.to);
    for (std::size_t x = 1; x < f_.net.points.size(); ++x) {
      const int xi = static_cast<int>(x);
      if (f_.net.points[x].kind == PointKind::kContingent && !contingent_ends.count(xi))
        f_.net.points[x].kind = PointKind::kControllable;  // its duration is a fact now, or pinned
      if (hist(xi) || pin.count(xi)) {  // not through AddLink: an equal link may have been dropped
        Link l;
        l.to = xi;
        l.lb = time(xi);
        l.ub = l.lb;
        l.why = hist(xi) ? "executed" : "pinned after the history";
        f_.net.links.push_back(std::move(l));
        f_.origins.emplace_back();
      }
    }
  }

  // A mark where nothing its condition reads moves (PointAt's fallback), for the cuts (cut.h).
  void NoteFallback(int point, const CutMark& mark, const std::set<int>& reads) {
    if (point <= 0 || reads.count(f_.point_automaton[point])) return;
    f_.fallback_marks.push_back({point, mark, std::vector<int>(reads.begin(), reads.end())});
  }

  static void AddReads(const Condition& c, std::set<int>& out) {
    out.insert(c.raw_info.locations_read.begin(), c.raw_info.locations_read.end());
    out.insert(c.raw_info.commands_read.begin(), c.raw_info.commands_read.end());
  }

  // The points marking the state plan's events, their links, and the observers they join. (A
  // condition that reads an accepting automaton's state makes the order rigid: Rigid().)
  void Anchors() {
    std::vector<std::set<int>> ep_reads, tc_reads;
    for (std::size_t p = 0; p < sp_.episodes.size(); ++p) {
      const Episode& ep = sp_.episodes[p];
      ep_reads.emplace_back();
      AddReads(ep.accepting, ep_reads.back());
      AddReads(ep.state, ep_reads.back());
      f_.episode_points.emplace_back(PointAt(t_.episodes[p].first, ep_reads.back()),
                                     PointAt(t_.episodes[p].second, ep_reads.back()));
      const int pi = static_cast<int>(p);
      NoteFallback(f_.episode_points.back().first, MarkOf(EndpointKind::kEpisodeStart, pi), ep_reads.back());
      NoteFallback(f_.episode_points.back().second, MarkOf(EndpointKind::kEpisodeEnd, pi), ep_reads.back());
    }
    for (std::size_t q = 0; q < sp_.temporals.size(); ++q) {
      const Temporal& tc = sp_.temporals[q];
      tc_reads.emplace_back();
      AddReads(tc.event1, tc_reads.back());
      AddReads(tc.event2, tc_reads.back());
      f_.temporal_points.emplace_back(PointAt(t_.temporals[q].first, tc_reads.back()),
                                      PointAt(t_.temporals[q].second, tc_reads.back()));
      const int qi = static_cast<int>(q);
      NoteFallback(f_.temporal_points.back().first, MarkOf(EndpointKind::kEvent1, qi), tc_reads.back());
      NoteFallback(f_.temporal_points.back().second, MarkOf(EndpointKind::kEvent2, qi), tc_reads.back());
    }
    for (std::size_t p = 0; p < sp_.episodes.size(); ++p) EpisodeLinks(p, ep_reads[p]);
    for (std::size_t q = 0; q < sp_.temporals.size(); ++q) TemporalLinks(q, tc_reads[q]);
    for (std::size_t q = 0; q < sp_.orders.size(); ++q) OrderLinks(q);
    SharedEvents();
    Goal();
    Observer m;
    AddReads(sp_.maintenance, m.automata);
    m.why = "/end_state/maintenance_constraint";
    condition_observers_.push_back(m);
  }

  void EpisodeLinks(std::size_t p, const std::set<int>& reads) {
    const Episode& ep = sp_.episodes[p];
    const auto [s, e] = f_.episode_points[p];
    if (s < 0 || e < 0) return;
    Observer o;
    o.automata = reads;
    o.why = "/constraints/episodes/" + PointerToken(ep.name);
    Source src(this, Of(LinkSource::kStatePlan, MarkOf(EndpointKind::kEpisodeStart, static_cast<int>(p)),
                        MarkOf(EndpointKind::kEpisodeEnd, static_cast<int>(p))));
    AddLink(s, e, MsOf(ep.lower), MsOf(ep.upper), false, o.why);
    o.points = {s, e};
    condition_observers_.push_back(o);
  }

  void TemporalLinks(std::size_t q, const std::set<int>& reads) {
    const Temporal& tc = sp_.temporals[q];
    const auto [p1, p2] = f_.temporal_points[q];
    if (p1 < 0 || p2 < 0) return;
    Observer o;
    o.automata = reads;
    o.why = "/constraints/temporal/" + PointerToken(tc.name);
    auto [k1, k2] = t_.temporals[q];
    const CutMark m1 = MarkOf(EndpointKind::kEvent1, static_cast<int>(q)),
                  m2 = MarkOf(EndpointKind::kEvent2, static_cast<int>(q));
    if (p1 == p2) {  // both at one point: nothing apart; a link keeps the pointer in the network
      Source src(this, Of(LinkSource::kTrivial));
      if (p1 > 0) AddLink(0, p1, 0, std::nullopt, false, o.why);
    } else if (k1 <= k2) {
      Source src(this, Of(LinkSource::kStatePlan, m1, m2));
      AddLink(p1, p2, MsOf(tc.lower), MsOf(tc.upper), false, o.why);
    } else {
      Source src(this, Of(LinkSource::kStatePlan, m2, m1));
      AddLink(p2, p1, MsOf(tc.lower), MsOf(tc.upper), false, o.why);
    }
    o.points = {p1, p2};
    condition_observers_.push_back(o);
  }

  // What an order's end reads: its action's automaton, or its condition's reads.
  std::set<int> EndReads(const OrderEnd& e) const {
    std::set<int> reads;
    if (e.action >= 0) reads.insert(sp_.actions[e.action].automaton);
    else AddReads(e.condition, reads);
    return reads;
  }

  // The points at which action j fires.
  std::vector<int> Firings(int j) const {
    std::vector<int> out;
    for (int p = 1; p < static_cast<int>(f_.point_event.size()); ++p)
      if (sp_.actions[j].Names(f_.point_automaton[p], f_.point_transition[p])) out.push_back(p);
    return out;
  }

  // An order (contract section 15): its two ends keep their event order (or their one event)
  // and the time between them stays within its bounds; `every`: each firing after the first end.
  void OrderLinks(std::size_t q) {
    const ::ctb::Order& ord = sp_.orders[q];
    const std::string why = ord.pointer;
    auto [k1, k2] = t_.orders[q];
    std::set<int> r1 = EndReads(ord.first), r2 = EndReads(ord.second);
    const int p1 = PointAt(k1, r1);
    NoteFallback(p1, MarkOf(EndpointKind::kOrder1, static_cast<int>(q)), r1);
    const bool every = ord.second.action >= 0 &&
                       sp_.actions[ord.second.action].occurrence == Occurrence::kEvery;
    const Ticks lb = MsOf(ord.lower);
    const std::optional<Ticks> ub = ord.upper ? std::optional(MsOf(*ord.upper)) : std::nullopt;
    Observer o;
    o.automata = r1;
    o.automata.insert(r2.begin(), r2.end());
    o.why = why;
    const int qi = static_cast<int>(q);
    // The marks of a pair's ends: the first end is O_1; the second O_2 (a firing of `every` is
    // one by its transition alone).
    auto pair = [&](int a, int b, int ka, int kb) {
      if (a < 0 || b < 0) return;
      const std::optional<CutMark> ma = MarkOf(EndpointKind::kOrder1, qi);
      const std::optional<CutMark> mb =
          every ? std::nullopt : std::optional(MarkOf(EndpointKind::kOrder2, qi));
      if (ka == kb) {
        {
          Source src(this, Of(LinkSource::kKept, ma, mb));
          Tie(a, b, why);
        }
        Source src(this, Of(LinkSource::kTrivial));
        if (a == b && a > 0) AddLink(0, a, 0, std::nullopt, false, why);  // keeps the pointer
      } else if (ka < kb) {
        Source src(this, Of(LinkSource::kKept, ma, mb));
        Order(a, b, why);
        origin_.source = LinkSource::kStatePlan;
        AddLink(a, b, lb, ub, false, why);
      } else {
        Source src(this, Of(LinkSource::kKept, mb, ma));
        Order(b, a, why);
        origin_.source = LinkSource::kStatePlan;
        AddLink(b, a, lb, ub, false, why);
      }
    };
    int p2 = p1;
    if (every) {
      for (int p : Firings(ord.second.action)) {
        pair(p1, p, k1, f_.point_event[p]);
        o.points.push_back(p);
        if (f_.point_event[p] == k2) p2 = p;
      }
      Source src(this, Of(LinkSource::kTrivial));
      if (o.points.empty() && p1 > 0) AddLink(0, p1, 0, std::nullopt, false, why);
    } else {
      p2 = PointAt(k2, r2);
      NoteFallback(p2, MarkOf(EndpointKind::kOrder2, static_cast<int>(q)), r2);
      pair(p1, p2, k1, k2);
      PinBetween(ord, k1, k2, p1, p2, why);
    }
    f_.order_points.emplace_back(p1, p2);
    o.points.insert(o.points.begin(), p1);
    if (!every) o.points.push_back(p2);
    condition_observers_.push_back(o);
  }

  // A condition end that comes after the other end is the earliest event at which it holds once
  // the lower bound has passed: an event between the two that moved past the bound would become
  // it. Every point between them keeps its time from the earlier end (sound, less flexible).
  void PinBetween(const ::ctb::Order& ord, int k1, int k2, int p1, int p2, const std::string& why) {
    if (ord.lower <= 0 || p1 < 0 || p2 < 0) return;
    const bool later_is_condition = k1 <= k2 ? ord.second.action < 0 : ord.first.action < 0;
    if (!later_is_condition) return;
    const int from = std::min(k1, k2), to = std::max(k1, k2), anchor = k1 <= k2 ? p1 : p2;
    for (int k = from + 1; k < to; ++k)
      for (int p : at_event_[k])
        if (p != anchor)
          AddLink(anchor, p, Ms(t_.events[k]) - Ms(t_.events[from]),
                  Ms(t_.events[k]) - Ms(t_.events[from]), false, why);
  }

  void SharedEvents() {
    for (const SharedEvent* evp : sp_.AllSharedEvents()) {
      const SharedEvent& ev = *evp;
      std::vector<int> pts;
      for (const auto& e : ev.endpoints) {
        if (e.kind == EndpointKind::kAction) {
          int k = -1;  // the action's one event, as the verifier finds it
          for (int p : Firings(e.index)) {
            const int pe = f_.point_event[p];
            const bool last = sp_.actions[e.index].occurrence == Occurrence::kLast;
            if (k < 0 || (last ? pe > f_.point_event[k] : pe < f_.point_event[k])) k = p;
          }
          pts.push_back(k);
          continue;
        }
        if (e.kind == EndpointKind::kOrder1 || e.kind == EndpointKind::kOrder2) {
          const auto& pr = f_.order_points[e.index];
          pts.push_back(e.kind == EndpointKind::kOrder1 ? pr.first : pr.second);
          continue;
        }
        const auto& pr = e.kind == EndpointKind::kEpisodeStart || e.kind == EndpointKind::kEpisodeEnd
                             ? f_.episode_points[e.index]
                             : f_.temporal_points[e.index];
        const bool first = e.kind == EndpointKind::kEpisodeStart || e.kind == EndpointKind::kEvent1;
        pts.push_back(first ? pr.first : pr.second);
      }
      auto mark = [](const Endpoint& e) {
        const EndpointKind k = e.kind;
        return MarkOf(k, e.index);
      };
      for (std::size_t i = 1; i < pts.size(); ++i)
        if (pts[0] >= 0 && pts[i] >= 0) {
          Source src(this, Of(LinkSource::kKept, mark(ev.endpoints[0]), mark(ev.endpoints[i])));
          Tie(pts[0], pts[i], "/constraints/event/" + PointerToken(ev.name));
        }
    }
  }

  // The goal's event is the last: every point before it; its points one event; its reads, the
  // episodes' and temporal constraints' marks keep their order with it.
  void Goal() {
    const std::string why = "/end_state/goal_constraint";
    const int g = t_.goal_event;
    Observer o;
    AddReads(sp_.goal, o.automata);
    o.why = why;
    if (g <= 0 || at_event_[g].empty()) {
      f_.goal_point = 0;
      return;
    }
    const auto& goal_points = at_event_[g];
    f_.goal_point = goal_points.front();
    {
      Source src(this, Of(LinkSource::kKept, GoalMark(), GoalMark()));
      for (std::size_t i = 1; i < goal_points.size(); ++i) Tie(goal_points[0], goal_points[i], why);
    }
    Source src(this, Of(LinkSource::kGoalLast, std::nullopt, GoalMark()));
    for (const auto& chain : chain_)
      if (!chain.empty() && f_.point_event[chain.back()] < g) Order(chain.back(), f_.goal_point, why);
    for (const auto& [s, e] : f_.episode_points)
      if (e > 0) o.points.push_back(e);
    for (const auto& [p1, p2] : f_.temporal_points)
      for (int p : {p1, p2})
        if (p > 0) o.points.push_back(p);
    for (const auto& [p1, p2] : f_.order_points)
      for (int p : {p1, p2})
        if (p > 0) o.points.push_back(p);
    o.points.push_back(f_.goal_point);
    condition_observers_.push_back(o);
  }

  // Each observer's points in plan order: one event -> one event; else the same order.
  void Orders() {
    if (fallback_mark_ && !f_.rigid) {
      f_.rigid = true;
      f_.rigid_by_plan = true;
      f_.rigid_reason = "a mark of the state plan falls where nothing its condition reads moves";
    }
    std::vector<Observer> observers = condition_observers_;
    const int na = static_cast<int>(d_.automata.size());
    for (int a = 0; a < na; ++a) observers.push_back(GuardObserver(a));
    for (const auto& o : observers) f_.observers.emplace_back(o.automata.begin(), o.automata.end());
    if (f_.rigid) {
      Observer all;
      for (int a = 0; a < na; ++a) all.automata.insert(a);
      all.why = "rigid order: " + f_.rigid_reason;
      for (auto& o : observers) all.points.insert(all.points.end(), o.points.begin(), o.points.end());
      observers = {all};
    }
    for (const Observer& o : observers) Keep(o);
  }

  Observer GuardObserver(int a) const {
    Observer o;
    o.automata.insert(a);
    for (const auto& tr : d_.automata[a].transitions) {
      o.automata.insert(tr.guard_info.locations_read.begin(), tr.guard_info.locations_read.end());
      o.automata.insert(tr.guard_info.commands_read.begin(), tr.guard_info.commands_read.end());
    }
    o.why = "guards of " + d_.automata[a].name + " read these";
    return o;
  }

  void Keep(const Observer& o) {
    std::vector<int> pts = o.points;
    for (std::size_t p = 1; p < f_.net.points.size(); ++p)
      if (o.automata.count(f_.point_automaton[p])) pts.push_back(static_cast<int>(p));
    std::sort(pts.begin(), pts.end(), [&](int x, int y) {
      return std::make_pair(f_.point_event[x], x) < std::make_pair(f_.point_event[y], y);
    });
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    for (std::size_t i = 1; i < pts.size(); ++i) {
      const int x = pts[i - 1], y = pts[i];
      if (x == 0) continue;
      Source src(this, Of(LinkSource::kKept, Membership(o, x), Membership(o, y)));
      if (f_.point_event[x] == f_.point_event[y]) Tie(x, y, o.why);
      else Order(x, y, "order kept for " + o.why);
    }
  }

  // Why point x is among observer o's: its automaton (no mark needed), or the state-plan mark it
  // is (only the goal's observer has marks of automata it does not read).
  std::optional<CutMark> Membership(const Observer& o, int x) const {
    if (o.automata.count(f_.point_automaton[x])) return std::nullopt;
    if (x == f_.goal_point) return GoalMark();
    for (std::size_t p = 0; p < f_.episode_points.size(); ++p)
      if (f_.episode_points[p].second == x) return MarkOf(EndpointKind::kEpisodeEnd, static_cast<int>(p));
    for (std::size_t q = 0; q < f_.temporal_points.size(); ++q) {
      if (f_.temporal_points[q].first == x) return MarkOf(EndpointKind::kEvent1, static_cast<int>(q));
      if (f_.temporal_points[q].second == x) return MarkOf(EndpointKind::kEvent2, static_cast<int>(q));
    }
    for (std::size_t q = 0; q < f_.order_points.size(); ++q) {
      if (f_.order_points[q].first == x) return MarkOf(EndpointKind::kOrder1, static_cast<int>(q));
      if (f_.order_points[q].second == x) return MarkOf(EndpointKind::kOrder2, static_cast<int>(q));
    }
    return MarkOf(EndpointKind::kEpisodeStart, -1);  // not reached; cut.cpp refuses index -1
  }

  const Trajectory& t_;
  const Domain& d_;
  const StatePlan& sp_;
  const long tps_;
  const Ticks ms_per_tick_;
  FlexiblePlan f_;
  std::vector<std::vector<int>> at_event_;  // points per plan event
  std::vector<std::vector<int>> chain_;     // points per automaton, in event order
  std::vector<Observer> condition_observers_;
  mutable bool fallback_mark_ = false;

  LinkOrigin origin_;  // of the links being added (Source)
  std::set<std::tuple<int, int, Ticks, Ticks, bool, bool>> seen_;
};

}  // namespace

std::optional<FlexiblePlan> DeriveNetwork(const Trajectory& t, const Domain& d, const StatePlan& sp,
                                          long tps, std::string* why_not) {
  if (tps < 1 || tps > network::kTicksPerSecond || network::kTicksPerSecond % tps != 0) {
    if (why_not) *why_not = "the domain's time_resolution is not a whole number of milliseconds";
    return std::nullopt;
  }
  return Deriver(t, d, sp, tps).Run();
}

}  // namespace ctb::flexible
