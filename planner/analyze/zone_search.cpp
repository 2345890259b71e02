// The zone search of zone_reach.h: states are the automata's locations, the state plan's
// accepting automata and a zone of clock values (one clock per automaton: time since it entered
// its location; one per active episode or temporal constraint: time since it started). The
// rules, each the verifier's (planner/verify/verifier.cpp):
//   - between events time passes; it may pass beyond the moment an automatic transition whose
//     guard holds is due (clock = lo) only by ending the stage at once (zero delay);
//   - at an event at least one automaton moves, each by at most one transition whose guard holds
//     on the stage before, with its clock in [lo, hi]; an automatic transition whose guard holds
//     and whose clock reached lo must be the one its automaton takes; a controllable one whose
//     guard holds never lets its clock pass hi;
//   - the accepting automata: an episode starts at the first event its accepting constraint
//     holds, its state constraint then holds on each stage until the event that ends it, with
//     end - start in its bounds; a temporal constraint activates at the first event either
//     condition holds (both at once: accepted then, when its lower bound is 0) and is accepted at
//     a later event at which the other holds, within its bounds; the endpoints of a shared event
//     happen at one event; the end state is accepted at the first event at which the goal holds
//     and every part is accepted; the maintenance constraint holds on every stage before it.
#include <algorithm>
#include <map>
#include <optional>
#include <queue>

#include "planner/analyze/abstraction.h"
#include "planner/analyze/dbm.h"
#include "planner/analyze/earliest.h"  // RequiredLocations
#include "planner/analyze/zone_reach.h"

namespace ctb::analysis {

namespace {

// A temporal constraint's accepting automaton.
enum : int { kTcWaiting = 0, kAwait2 = 1, kAwait1 = 2, kTcAccepted = 3 };
// An episode's: 0 waiting, 1 active, 2 accepted.
enum : int { kEpWaiting = 0, kEpActive = 1, kEpAccepted = 2 };

struct Disc {
  std::vector<int> loc, ep, tc;
  std::vector<int> Key() const {
    std::vector<int> k = loc;
    k.insert(k.end(), ep.begin(), ep.end());
    k.insert(k.end(), tc.begin(), tc.end());
    return k;
  }
};

struct Sym {
  Disc s;
  Dbm z;
};

// The stages around an event: the one before (null at e[0]) and the one after, and the
// accepting automata before the event.
struct View {
  const std::vector<int>* prev;
  const std::vector<int>* next;
  const Disc* before;
};

Tv FromBool(bool b) { return b ? Tv::kTrue : Tv::kFalse; }

template <class Atom>
Tv Eval3(const Expr& e, const Atom& atom) {
  switch (e.op) {
    case Expr::Op::kTrue:
      return Tv::kTrue;
    case Expr::Op::kFalse:
      return Tv::kFalse;
    case Expr::Op::kNot:
      return Not(Eval3(e.kids[0], atom));
    case Expr::Op::kAnd:
      return And(Eval3(e.kids[0], atom), Eval3(e.kids[1], atom));
    case Expr::Op::kOr:
      return Or(Eval3(e.kids[0], atom), Eval3(e.kids[1], atom));
    case Expr::Op::kImplies:
      return Or(Not(Eval3(e.kids[0], atom)), Eval3(e.kids[1], atom));
    case Expr::Op::kIff: {
      Tv a = Eval3(e.kids[0], atom), b = Eval3(e.kids[1], atom);
      if (a == Tv::kUnknown || b == Tv::kUnknown) return Tv::kUnknown;
      return FromBool(a == b);
    }
    case Expr::Op::kAtom:
      break;
    case Expr::Op::kEvery:  // quantifiers are expanded at load: unknown if one were left
    case Expr::Op::kAny: return Tv::kUnknown;
  }
  return atom(e);
}

class Search {
 public:
  Search(const Domain& d, const StatePlan& sp, const ZoneQuestion& q, ZoneBudget& b)
      : d_(d),
        sp_(sp),
        q_(q),
        b_(b),
        na_(static_cast<int>(d.automata.size())),
        ne_(static_cast<int>(sp.episodes.size())),
        nt_(static_cast<int>(sp.temporals.size())),
        nc_(na_ + ne_ + nt_ + (q.deadline >= 0 ? 1 : 0)) {
    Prepare();
    if (q_.deadline >= 0 && q_.goal && RemainingTime::Applies(sp_)) rest_.emplace(d_, sp_);
  }

  Reach Run() {
    Disc s0{sp_.initial, std::vector<int>(ne_, kEpWaiting), std::vector<int>(nt_, kTcWaiting)};
    for (int p = 0; p < ne_; ++p)
      if (!q_.episodes[p]) s0.ep[p] = kEpAccepted;
    for (int k = 0; k < nt_; ++k)
      if (!q_.temporals[k]) s0.tc[k] = kTcAccepted;
    Dbm z(nc_);
    if (!q_.clocks_known)
      for (int a = 0; a < na_; ++a) z.Free(AC(a));
    // Event e[0]: no transition; the accepting automata read the initial stage.
    if (Monitors(View{nullptr, &sp_.initial, &s0}, s0, z)) return Reach::kRun;
    while (!open_.empty() && !spent_) {
      if (--b_.states < 0) return Reach::kUnknown;
      Sym s = std::move(const_cast<Open&>(open_.top()).s);
      open_.pop();
      if (Expand(s)) return Reach::kRun;
    }
    return spent_ ? Reach::kUnknown : Reach::kNoRun;
  }

 private:
  int AC(int a) const { return 1 + a; }
  int EC(int p) const { return 1 + na_ + p; }
  int TC(int k) const { return 1 + na_ + ne_ + k; }
  // The clock of the deadline (ZoneQuestion::deadline): time since e[0], never reset.
  int GC() const { return 1 + na_ + ne_ + nt_; }

  std::int64_t Ticks(double s) const { return std::llround(s * static_cast<double>(q_.tps)); }
  // Bounds at or beyond the largest a state plan may give read as none (the search is then an
  // over-approximation there, which keeps proofs sound and zones few).
  bool Bounded(std::int64_t hi) const { return hi < Ticks(1e7); }

  void Prepare() {
    out_.resize(na_);
    maxc_.resize(na_);
    for (int a = 0; a < na_; ++a) {
      const Automaton& au = d_.automata[a];
      out_[a].resize(au.locations.size());
      maxc_[a].assign(au.locations.size(), -1);
      for (int t = 0; t < static_cast<int>(au.transitions.size()); ++t) {
        const Transition& tr = au.transitions[t];
        out_[a][tr.from].push_back(t);
        // The clock matters in `from` when a transition reads it (a duration, or the urgency of
        // an automatic or controllable one).
        std::int64_t c = Ticks(tr.duration.lo);
        if (tr.duration.hi) c = std::max(c, Ticks(*tr.duration.hi));
        if (c > 0 || !tr.commanded) maxc_[a][tr.from] = std::max(maxc_[a][tr.from], c);
      }
    }
    GoalDistances();
  }

  // Per automaton the goal's location (a top-level conjunct "X[i+1]==L" or "X[i]==L"), and the
  // fewest transitions from each location to it.
  // With two conjuncts on one automaton (no plan meets both), the first one counts.
  void GoalDistances() {
    to_goal_.assign(na_, {});
    std::vector<std::pair<int, int>> needed;
    RequiredLocations(sp_.goal.raw, needed);
    for (auto [a, l] : needed)
      if (to_goal_[a].empty()) to_goal_[a] = Backwards(a, l);
  }

  std::vector<int> Backwards(int a, int target) const {
    const Automaton& au = d_.automata[a];
    std::vector<int> dist(au.locations.size(), 1 << 20);
    dist[target] = 0;
    for (bool grew = true; grew;) {
      grew = false;
      for (const Transition& tr : au.transitions)
        if (dist[tr.to] + 1 < dist[tr.from]) dist[tr.from] = dist[tr.to] + 1, grew = true;
    }
    return dist;
  }

  // How far a state looks from the end state: transitions to the goal's locations, and two per
  // part not yet accepted.
  int Distance(const Disc& s) const {
    int h = 0;
    for (int a = 0; a < na_; ++a)
      if (!to_goal_[a].empty()) h += std::min(to_goal_[a][s.loc[a]], 1000);
    for (int p : s.ep) h += p == kEpAccepted ? 0 : 2;
    for (int k : s.tc) h += k == kTcAccepted ? 0 : 2;
    return h;
  }

  // --- conditions ---------------------------------------------------------------------------

  Tv Accepting(const Expr& atom, const Disc& before) const {
    int state;
    if (atom.var_kind == VarKind::kEpisodeState) {
      if (!q_.episodes[atom.target]) return Tv::kUnknown;
      state = before.ep[atom.target];
    } else {
      if (!q_.temporals[atom.target]) return Tv::kUnknown;
      const int s = before.tc[atom.target];
      state = s == kTcWaiting ? 0 : s == kTcAccepted ? 2 : 1;
    }
    return FromBool((state == atom.value_code) != atom.not_equal);
  }

  // An atom of a condition: `change` reads [i] on the stage before the event.
  Tv Atom(const Expr& atom, const View& v, bool change) const {
    if (atom.var_kind == VarKind::kEpisodeState || atom.var_kind == VarKind::kTemporalState)
      return Accepting(atom, *v.before);
    if (atom.var_kind != VarKind::kLocation) return Tv::kUnknown;  // commands
    int value;
    if (atom.index.kind == IndexKind::kFixed) {
      if (atom.index.fixed != 0) return Tv::kUnknown;
      value = sp_.initial[atom.target];
    } else {
      value = (change && atom.index.kind == IndexKind::kI) ? (*v.prev)[atom.target]
                                                           : (*v.next)[atom.target];
    }
    return FromBool((value == atom.value_code) != atom.not_equal);
  }

  Tv AtEvent(const Condition& c, const View& v) const {
    const bool change = c.raw_info.IsChange();
    if (change && !v.prev) return Tv::kFalse;
    return Eval3(c.raw, [&](const Expr& a) { return Atom(a, v, change); });
  }

  // A state constraint on the stage after the event.
  Tv OnStage(const Condition& c, const View& v) const {
    return Eval3(c.raw, [&](const Expr& a) { return Atom(a, v, false); });
  }

  // A guard on the stage before an event. `cmd` (optional): per automaton the command it
  // issued on that stage when known (-1: unknown, any value).
  Tv Guard(const Transition& tr, const std::vector<int>& loc,
           const std::vector<int>* cmd = nullptr) const {
    return Eval3(tr.guard, [&](const Expr& a) {
      if (a.var_kind == VarKind::kLocation)
        return FromBool((loc[a.target] == a.value_code) != a.not_equal);
      if (a.var_kind == VarKind::kCommand && cmd && (*cmd)[a.target] >= 0)
        return FromBool(((*cmd)[a.target] == a.value_code) != a.not_equal);
      return Tv::kUnknown;
    });
  }

  // --- the stage and its time ---------------------------------------------------------------

  // Per automaton, the transitions leaving its location with their guard's value on the stage.
  struct Stage {
    std::vector<std::vector<std::pair<int, Tv>>> out;
  };

  Stage StageOf(const std::vector<int>& loc) const {
    Stage st;
    st.out.resize(na_);
    for (int a = 0; a < na_; ++a)
      for (int t : out_[a][loc[a]]) {
        Tv g = Guard(d_.automata[a].transitions[t], loc);
        if (g != Tv::kFalse) st.out[a].push_back({t, g});
      }
    return st;
  }

  bool Urgent(const Transition& tr, Tv g) const {
    return g == Tv::kTrue && !tr.commanded && !tr.controllable;
  }

  // Bounds every event must respect: a controllable transition whose guard holds has not
  // overstayed; an active part has not passed its upper bound (it could never be accepted).
  bool Limits(const Disc& s, const Stage& st, Dbm& z) const {
    for (int a = 0; a < na_; ++a)
      for (auto [t, g] : st.out[a]) {
        const Transition& tr = d_.automata[a].transitions[t];
        if (tr.controllable && g == Tv::kTrue && tr.duration.hi &&
            !z.AtMost(AC(a), Ticks(*tr.duration.hi)))
          return false;
      }
    for (int p = 0; p < ne_; ++p)
      if (s.ep[p] == kEpActive && Bounded(q_.ep_hi[p]) && !z.AtMost(EC(p), q_.ep_hi[p]))
        return false;
    for (int k = 0; k < nt_; ++k) {
      const bool active = s.tc[k] == kAwait1 || s.tc[k] == kAwait2;
      if (active && Bounded(q_.tc_hi[k]) && !z.AtMost(TC(k), q_.tc_hi[k])) return false;
    }
    // Every event of a run comes no later than its end state's acceptance.
    return q_.deadline < 0 || z.AtMost(GC(), q_.deadline);
  }

  // Constrains z to the valuations at which no automatic transition whose guard holds has
  // passed its due time; false when none is left.
  bool NothingPassedDue(const Stage& st, Dbm& z) const {
    for (int a = 0; a < na_; ++a)
      for (auto [t, g] : st.out[a]) {
        const Transition& tr = d_.automata[a].transitions[t];
        if (Urgent(tr, g) && !z.AtMost(AC(a), Ticks(tr.duration.lo))) return false;
      }
    return true;
  }

  // The zones in which the next event may happen: after a delay that passes no due automatic
  // transition, or at once.
  std::vector<Dbm> Elapse(const Sym& s, const Stage& st) {
    if (q_.deadline >= 0 && q_.whole_ticks) return ElapseTicks(s, st);
    std::vector<Dbm> out;
    Dbm later = s.z;
    later.Up();
    const bool ok = Limits(s.s, st, later) && NothingPassedDue(st, later);
    if (ok) out.push_back(later);
    Dbm now = s.z;
    if (Limits(s.s, st, now) && !(ok && later.Includes(now))) out.push_back(now);
    return out;
  }

  // The same with events at whole ticks only (every plan's are: its times are in ticks): the
  // zone stays one valuation (but for clocks no rule reads, which extrapolation frees), and the
  // next event comes after 0, 1, 2, ... ticks, up to the deadline or the first due automatic
  // transition or overstay (each later tick fails too).
  std::vector<Dbm> ElapseTicks(const Sym& s, const Stage& st) {
    std::vector<Dbm> out;
    Dbm now = s.z;
    if (Limits(s.s, st, now)) out.push_back(now);
    const std::int64_t g = s.z.Lower(GC());  // the valuation's time
    for (std::int64_t t = g + 1; t <= q_.deadline && !Spent(); ++t) {
      Dbm later = s.z;
      later.Up();
      if (!later.AtLeast(GC(), t) || !later.AtMost(GC(), t) || !Limits(s.s, st, later) ||
          !NothingPassedDue(st, later))
        break;
      out.push_back(std::move(later));
    }
    return out;
  }

  // --- the event ----------------------------------------------------------------------------

  struct Move {
    const Sym* s;
    const Stage* st;
    std::vector<int> loc;
    std::vector<int> moved;
    std::vector<int> taken;  // the transition of each automaton in `moved`
  };

  bool Expand(const Sym& s) {
    const Stage st = StageOf(s.s.loc);
    for (const Dbm& z : Elapse(s, st)) {
      Move m{&s, &st, s.s.loc, {}};
      if (Moves(m, 0, z)) return true;
    }
    return false;
  }

  // Automaton a's due automatic transitions other than `taken` have not reached lo.
  bool NotDue(const Move& m, int a, int taken, Dbm& z) const {
    for (auto [t, g] : m.st->out[a]) {
      const Transition& tr = d_.automata[a].transitions[t];
      if (t != taken && Urgent(tr, g) && !z.Below(AC(a), Ticks(tr.duration.lo))) return false;
    }
    return true;
  }

  // One expansion may branch much (every subset of the automata moves): the deadline is read
  // every 256 branches, and once passed every search loop unwinds (Run says kUnknown).
  bool Spent() {
    if (!spent_ && ++polls_ % 256 == 0 &&
        (std::chrono::steady_clock::now() > b_.deadline || (b_.cancel && b_.cancel->load())))
      spent_ = true;
    return spent_;
  }

  bool Moves(Move& m, int a, const Dbm& z) {
    if (Spent()) return false;
    if (a == na_) return m.moved.empty() ? false : Fire(m, z);
    Dbm stay = z;
    if (NotDue(m, a, -1, stay) && Moves(m, a + 1, stay)) return true;
    const int from = m.loc[a];
    for (auto [t, g] : m.st->out[a]) {
      const Transition& tr = d_.automata[a].transitions[t];
      Dbm go = z;
      if (!go.AtLeast(AC(a), Ticks(tr.duration.lo))) continue;
      if (tr.duration.hi && !go.AtMost(AC(a), Ticks(*tr.duration.hi))) continue;
      if (!NotDue(m, a, t, go)) continue;
      m.loc[a] = tr.to;
      m.moved.push_back(a);
      m.taken.push_back(t);
      const bool run = Moves(m, a + 1, go);
      m.moved.pop_back();
      m.taken.pop_back();
      m.loc[a] = from;
      if (run) return true;
    }
    return false;
  }

  // An automaton that takes a transition whose guard requires one command of its own issued
  // that command on the stage before: the guards of this event that read it must hold with it.
  bool CommandsAgree(const Move& m) const {
    std::vector<int> cmd(na_, -1);
    bool any = false;
    for (std::size_t k = 0; k < m.moved.size(); ++k) {
      const Transition& tr = d_.automata[m.moved[k]].transitions[m.taken[k]];
      if (tr.commanded && tr.command > 0) cmd[m.moved[k]] = tr.command, any = true;
    }
    if (!any) return true;
    for (std::size_t k = 0; k < m.moved.size(); ++k) {
      const Transition& tr = d_.automata[m.moved[k]].transitions[m.taken[k]];
      if (!tr.guard_info.commands_read.empty() && Guard(tr, m.s->s.loc, &cmd) == Tv::kFalse) return false;
    }
    return true;
  }

  bool Fire(const Move& m, Dbm z) {
    if (!CommandsAgree(m)) return false;
    for (int a : m.moved) z.Reset(AC(a));
    return Monitors(View{&m.s->s.loc, &m.loc, &m.s->s}, m.s->s, z);
  }

  // --- the accepting automata ---------------------------------------------------------------

  // Endpoints happening at the event: [0, 2 ne) episodes' start and end, then temporal
  // constraints' event 1 and event 2.
  struct Step {
    View v;
    Disc next;
    std::vector<char> at;
  };

  // Every way the accepting automata may take the event; true when one accepts the end state.
  bool Monitors(const View& v, const Disc& before, const Dbm& z) {
    Step st{v, before, std::vector<char>(2 * (ne_ + nt_), 0)};
    st.next.loc = *v.next;
    return Slot(st, 0, z);
  }

  bool Slot(Step& st, int k, const Dbm& z) {
    if (Spent()) return false;
    if (k == ne_ + nt_) return Finish(st, z);
    if (k < ne_) return EpisodeSlot(st, k, z);
    return TemporalSlot(st, k - ne_, z);
  }

  // Sets the part's state and endpoints, goes on to the next slot, and undoes.
  bool Go(Step& st, int k, int state, std::initializer_list<int> ends, const Dbm& z) {
    int& cell = k < ne_ ? st.next.ep[k] : st.next.tc[k - ne_];
    const int old = cell;
    cell = state;
    for (int e : ends) st.at[e] = 1;
    const bool run = Slot(st, k + 1, z);
    for (int e : ends) st.at[e] = 0;
    cell = old;
    return run;
  }

  bool EpisodeSlot(Step& st, int p, const Dbm& z) {
    const Episode& ep = sp_.episodes[p];
    const int s = st.v.before->ep[p];
    if (s == kEpWaiting) {
      const Tv acc = AtEvent(ep.accepting, st.v);
      if (acc != Tv::kFalse && OnStage(ep.state, st.v) != Tv::kFalse) {
        Dbm started = z;
        started.Reset(EC(p));
        if (Go(st, p, kEpActive, {2 * p}, started)) return true;
      }
      return acc != Tv::kTrue && Slot(st, p + 1, z);
    }
    if (s == kEpActive) {
      Dbm end = z;
      if (end.AtLeast(EC(p), q_.ep_lo[p]) && end.AtMost(EC(p), q_.ep_hi[p]) &&
          Go(st, p, kEpAccepted, {2 * p + 1}, end))
        return true;
      return OnStage(ep.state, st.v) != Tv::kFalse && Slot(st, p + 1, z);
    }
    return Slot(st, p + 1, z);
  }

  bool TemporalSlot(Step& st, int q, const Dbm& z) {
    const Temporal& tc = sp_.temporals[q];
    const int k = ne_ + q, e1 = 2 * k, e2 = 2 * k + 1;
    const int s = st.v.before->tc[q];
    if (s == kTcAccepted) return Slot(st, k + 1, z);
    const Tv h1 = AtEvent(tc.event1, st.v), h2 = AtEvent(tc.event2, st.v);
    if (s == kTcWaiting) {
      Dbm started = z;
      started.Reset(TC(q));
      if (h1 != Tv::kFalse && h2 != Tv::kFalse && q_.tc_lo[q] == 0 &&
          Go(st, k, kTcAccepted, {e1, e2}, z))
        return true;
      if (h1 != Tv::kFalse && h2 != Tv::kTrue && Go(st, k, kAwait2, {e1}, started)) return true;
      if (h2 != Tv::kFalse && h1 != Tv::kTrue && Go(st, k, kAwait1, {e2}, started)) return true;
      return h1 != Tv::kTrue && h2 != Tv::kTrue && Slot(st, k + 1, z);
    }
    const Tv other = s == kAwait2 ? h2 : h1;
    Dbm end = z;
    if (other != Tv::kFalse && end.AtLeast(TC(q), q_.tc_lo[q]) && end.AtMost(TC(q), q_.tc_hi[q]) &&
        Go(st, k, kTcAccepted, {s == kAwait2 ? e2 : e1}, end))
      return true;
    return Slot(st, k + 1, z);
  }

  int EndpointSlot(const Endpoint& e) const {
    switch (e.kind) {
      case EndpointKind::kEpisodeStart:
        return 2 * e.index;
      case EndpointKind::kEpisodeEnd:
        return 2 * e.index + 1;
      case EndpointKind::kEvent1:
        return 2 * (ne_ + e.index);
      case EndpointKind::kEvent2:
        return 2 * (ne_ + e.index) + 1;
    }
    return 0;
  }

  bool Kept(const Endpoint& e) const {
    const bool ep = e.kind == EndpointKind::kEpisodeStart || e.kind == EndpointKind::kEpisodeEnd;
    return ep ? q_.episodes[e.index] : q_.temporals[e.index];
  }

  // Every shared event's endpoints (of the parts kept) happen all at this event or none.
  bool SharedEventsHold(const Step& st) const {
    for (std::size_t g = 0; g < sp_.events.size(); ++g) {
      if (!q_.events[g]) continue;
      int kept = 0, here = 0;
      for (const Endpoint& e : sp_.events[g].endpoints)
        if (Kept(e)) ++kept, here += st.at[EndpointSlot(e)];
      if (kept >= 2 && here != 0 && here != kept) return false;
    }
    return true;
  }

  bool Finish(const Step& st, Dbm z) {
    if (!SharedEventsHold(st)) return false;
    bool all = true;
    for (int s : st.next.ep) all = all && s == kEpAccepted;
    for (int s : st.next.tc) all = all && s == kTcAccepted;
    if (all && (!q_.goal || AtEvent(sp_.goal, st.v) != Tv::kFalse)) return true;
    if (q_.maintenance && OnStage(sp_.maintenance, st.v) == Tv::kFalse) return false;
    Push(st.next, std::move(z));
    return false;
  }

  // Clocks no rule reads any more are freed; the others keep their largest constant.
  std::vector<std::int64_t> MaxConstants(const Disc& s) const {
    std::vector<std::int64_t> m(1 + nc_, -1);
    if (q_.deadline >= 0) m[GC()] = q_.deadline;
    for (int a = 0; a < na_; ++a) m[AC(a)] = maxc_[a][s.loc[a]];
    for (int p = 0; p < ne_; ++p)
      if (s.ep[p] == kEpActive) m[EC(p)] = Bounded(q_.ep_hi[p]) ? q_.ep_hi[p] : q_.ep_lo[p];
    for (int k = 0; k < nt_; ++k)
      if (s.tc[k] == kAwait1 || s.tc[k] == kAwait2)
        m[TC(k)] = Bounded(q_.tc_hi[k]) ? q_.tc_hi[k] : q_.tc_lo[k];
    return m;
  }

  // Zones kept (each n x n bounds): at most about 32 MB of them per search, whatever the number
  // of clocks; beyond, no proof.
  long MaxKept() const {
    const long n = 1 + nc_;
    return std::max(1000L, 4000000L / (n * n));
  }

  // With a deadline: a state whose rest of the run cannot reach the goal in time (earliest.h,
  // RemainingTime, from each automaton's location and the longest time it may have spent
  // there) is not kept.
  bool TooLate(const Disc& s, const Dbm& z) const {
    if (!rest_) return false;
    std::vector<long> since(na_);
    for (int a = 0; a < na_; ++a) {
      const std::int64_t up = z.Upper(AC(a));
      since[a] = up >= Dbm::kInfinity ? (1L << 40) : static_cast<long>(up);
    }
    const long now = static_cast<long>(z.Lower(GC()));
    std::vector<long> key(s.loc.begin(), s.loc.end());
    key.insert(key.end(), since.begin(), since.end());
    if (rest_memo_.size() > 4 * static_cast<std::size_t>(MaxKept())) rest_memo_.clear();
    auto [it, fresh] = rest_memo_.try_emplace(std::move(key), 0);
    if (fresh) it->second = rest_->Goal(s.loc, since);
    return now + it->second > q_.deadline;
  }

  void Push(const Disc& s, Dbm z) {
    z.Extrapolate(MaxConstants(s));
    if (z.Empty()) return;
    if (pushed_ >= MaxKept()) {
      spent_ = true;
      return;
    }
    auto& seen = passed_[s.Key()];
    for (const Dbm& o : seen)
      if (o.Includes(z)) return;
    if (TooLate(s, z)) return;
    seen.erase(
        std::remove_if(seen.begin(), seen.end(), [&](const Dbm& o) { return z.Includes(o); }),
        seen.end());
    seen.push_back(z);
    open_.push(Open{Distance(s), ++pushed_, Sym{s, std::move(z)}});
  }

  const Domain& d_;
  const StatePlan& sp_;
  const ZoneQuestion& q_;
  ZoneBudget& b_;
  const int na_, ne_, nt_;
  const int nc_;  // clocks besides the reference
  // With a deadline, on a goal and maintenance constraint alone: the pruning rule of TooLate.
  std::optional<RemainingTime> rest_;
  mutable std::map<std::vector<long>, long> rest_memo_;  // locations and times there -> rest
  std::vector<std::vector<std::vector<int>>> out_;  // [a][location] -> transitions
  std::vector<std::vector<std::int64_t>> maxc_;     // [a][location]: largest constant, -1 none
  std::map<std::vector<int>, std::vector<Dbm>> passed_;
  // The states to expand, nearest the end state first (the newest among equals): a plan is
  // usually found at once, and a proof expands every state whatever the order.
  struct Open {
    int h;
    long seq;
    Sym s;
    bool operator<(const Open& o) const { return h != o.h ? h > o.h : seq < o.seq; }
  };
  std::priority_queue<Open> open_;
  long pushed_ = 0;
  std::vector<std::vector<int>> to_goal_;  // [a][location]: transitions to the goal's location
  long polls_ = 0;
  bool spent_ = false;
};

}  // namespace

Reach SearchZones(const Domain& d, const StatePlan& sp, const ZoneQuestion& q, ZoneBudget& budget) {
  return Search(d, sp, q, budget).Run();
}

}  // namespace ctb::analysis
