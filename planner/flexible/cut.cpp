#include "planner/flexible/cut.h"

#include <algorithm>
#include <climits>
#include <functional>
#include <map>

#include "planner/model/plan_cut.h"
#include "planner/network/check.h"

namespace ctb::flexible {

namespace {

constexpr int kNone = INT_MAX;  // no such event (the model's H+1)
constexpr std::size_t kMaxLoops = 2;

// Builds the cut of one conflict, link by link (cut.h).
class CutBuilder {
 public:
  CutBuilder(const FlexiblePlan& f) : f_(f) {}

  bool Add(int li, network::Link& restated, std::string& why_not) {
    const network::Link& l = f_.net.links[li];
    const LinkOrigin& o = f_.origins[li];
    switch (o.source) {
      case LinkSource::kOther:
        why_not = "its conflict has a link no other plan is known to share (" + l.why + ")";
        return false;
      case LinkSource::kTrivial: return true;
      case LinkSource::kDuration:
        // A duration that only orders (controllable, [0, inf)): its automaton's transitions in
        // between keep that order in any plan, so the two in that order suffice.
        if (!l.contingent && l.lb == 0 && !l.ub) {
          if (l.from > 0) Order(l.from, l.to);
          else Point(l.to);
        } else if (l.from == 0) {
          cut_.first.push_back(Point(l.to));
        } else {
          cut_.next.emplace_back(Point(l.from), Point(l.to));
        }
        return true;
      case LinkSource::kKept:
      case LinkSource::kGoalLast:
        if (f_.rigid_by_plan && !SharedObserver(l.from, l.to)) needs_rigid_ = true;
        if (o.strict_tick) restated.lb = 0;
        if (o.source == LinkSource::kGoalLast) cut_.last.push_back(Point(l.from));
        [[fallthrough]];
      case LinkSource::kStatePlan:
        if (!Mark(o.from_mark, l.from) || !Mark(o.to_mark, l.to)) {
          why_not = "a point of its conflict is not a mark the search can state";
          return false;
        }
        Order(l.from, l.to);
        return true;
    }
    return false;
  }

  // A rigid order kept between points no observer reads together holds in another plan only
  // when that plan's order is rigid too: the cut must restate a mark that makes it so.
  bool Complete(std::string& why_not) {
    if (needs_rigid_ && !rigid_restated_ && !f_.fallback_marks.empty()) {
      const auto& fb = f_.fallback_marks.front();  // restated, it makes the other plan rigid
      CutMark mk = fb.mark;
      mk.point = Point(fb.point);
      cut_.marks.push_back(mk);
      Quiet(fb);
    }
    if (needs_rigid_ && !rigid_restated_) {
      why_not = "its order is rigid because of where its own events fall";
      return false;
    }
    return true;
  }

  PlanCut Take() { return std::move(cut_); }

 private:
  // Rigid order because of this plan's marks: another plan keeps the order of two points when
  // an observer it has without rigid order reads both their automata (the marks are not needed).
  bool SharedObserver(int x, int y) const {
    if (x == 0 || y == 0) return false;
    const int ax = f_.point_automaton[x], ay = f_.point_automaton[y];
    for (const auto& o : f_.observers)
      if (std::count(o.begin(), o.end(), ax) && std::count(o.begin(), o.end(), ay)) return true;
    return false;
  }

 private:
  int Point(int np) {
    auto it = index_.find(np);
    if (it != index_.end()) return it->second;
    CutPoint p;
    if (np > 0) {
      p.automaton = f_.point_automaton[np];
      p.transition = f_.point_transition[np];
    }
    cut_.points.push_back(p);
    return index_[np] = static_cast<int>(cut_.points.size()) - 1;
  }

  // The mark's event in another plan holds no transition of what its condition reads: there too
  // the mark falls back, and that plan's order is rigid.
  void Quiet(const FlexiblePlan::FallbackMark& fb) {
    for (int b : fb.reads) cut_.quiet.emplace_back(Point(fb.point), b);
    rigid_restated_ = true;
  }

  bool Mark(const std::optional<CutMark>& m, int np) {
    if (!m) return true;
    if (m->kind == CutMark::Kind::kEndpoint && m->index < 0) return false;
    // A mark where nothing its condition reads moves: another plan's mark at that event is tied
    // to this point only when nothing it reads moves there either (then its order is rigid too).
    for (const auto& fb : f_.fallback_marks)
      if (fb.point == np && m->kind == CutMark::Kind::kEndpoint && fb.mark.endpoint == m->endpoint &&
          fb.mark.index == m->index)
        Quiet(fb);
    CutMark mk = *m;
    mk.point = Point(np);
    cut_.marks.push_back(mk);
    return true;
  }

  void Order(int x, int y) {
    const int ex = f_.point_event[x], ey = f_.point_event[y];
    if (ex == ey) cut_.same.emplace_back(Point(x), Point(y));
    else if (ex < ey) cut_.before.emplace_back(Point(x), Point(y));
    else cut_.before.emplace_back(Point(y), Point(x));
  }

  const FlexiblePlan& f_;
  PlanCut cut_;
  bool needs_rigid_ = false, rigid_restated_ = false;
  std::map<int, int> index_;  // network point -> cut point
};

// What a trajectory says of the events a cut reads.
class TrajectoryEvents {
 public:
  TrajectoryEvents(const Trajectory& t, const StatePlan& sp) : t_(t), sp_(sp) {
    std::size_t na = t.locations.size();
    fired_.assign(na, {});
    for (const auto& fi : t.fired) fired_[fi.automaton][fi.event] = fi.transition;
  }
  int Goal() const { return t_.goal_event; }
  int Fires(int a, int k) const {
    auto it = fired_[a].find(k);
    return it == fired_[a].end() ? -1 : it->second;
  }
  int Prev(int a, int k) const {  // a's last transition at or before k; 0 when none
    auto it = fired_[a].upper_bound(k);
    return it == fired_[a].begin() ? 0 : std::prev(it)->first;
  }
  int Next(int a, int k) const {  // a's first transition after k; kNone when none
    auto it = fired_[a].upper_bound(k);
    return it == fired_[a].end() ? kNone : it->first;
  }
  int Mark(const CutMark& m) const {
    if (m.kind == CutMark::Kind::kGoal) return t_.goal_event;
    const auto i = static_cast<std::size_t>(m.index);
    switch (m.endpoint) {
      case EndpointKind::kEpisodeStart: return t_.episodes.at(i).first;
      case EndpointKind::kEpisodeEnd: return t_.episodes.at(i).second;
      case EndpointKind::kEvent1: return t_.temporals.at(i).first;
      case EndpointKind::kEvent2: return t_.temporals.at(i).second;
      case EndpointKind::kOrder1: return t_.orders.at(i).first;
      case EndpointKind::kOrder2: return t_.orders.at(i).second;
      case EndpointKind::kAction: return ActionAt(m.index);
    }
    return kNone;
  }

 private:
  int ActionAt(int j) const {  // its first firing (its last for occurrence last), as AK
    const ::ctb::ActionEvent& act = sp_.actions.at(static_cast<std::size_t>(j));
    int k = kNone;
    for (const auto& fi : t_.fired)
      if (act.Names(fi.automaton, fi.transition)) {
        if (act.occurrence == Occurrence::kLast || k == kNone) k = fi.event;
      }
    return k;
  }

  const Trajectory& t_;
  const StatePlan& sp_;
  std::vector<std::map<int, int>> fired_;  // per automaton: event -> transition
};

// Every literal of the cut (encode_state_plan.cpp CutConstraint) with the classes' events `ev`.
bool Holds(const PlanCut& cut, const CutShape& s, const std::vector<int>& ev,
           const TrajectoryEvents& te) {
  auto E = [&](int p) { return ev[s.class_of[p]]; };
  for (std::size_t p = 0; p < cut.points.size(); ++p) {
    const CutPoint& pt = cut.points[p];
    const int e = E(static_cast<int>(p));
    if (pt.automaton < 0 ? e != 0 : (e < 1 || e == kNone || te.Fires(pt.automaton, e) != pt.transition))
      return false;
  }
  for (const CutMark& m : cut.marks)
    if (E(m.point) != te.Mark(m)) return false;
  for (auto [x, y] : cut.before)
    if (!(E(x) < E(y))) return false;
  for (auto [x, b] : cut.quiet)
    if (te.Fires(b, E(x)) != -1) return false;
  for (auto [x, y] : DistinctPairs(cut))
    if (E(x) == E(y)) return false;
  for (auto [x, y] : cut.next)
    if (E(y) != te.Next(cut.points[y].automaton, E(x))) return false;
  for (int y : cut.first)
    if (te.Prev(cut.points[y].automaton, std::max(E(y), 1) - 1) != 0) return false;
  for (int x : cut.last)
    if (te.Next(cut.points[x].automaton, E(x)) != kNone) return false;
  return true;
}

}  // namespace

std::optional<PlanCut> CutFromConflict(const FlexiblePlan& f, const Trajectory& plan,
                                       const std::vector<int>& conflict, std::string* why_not) {
  std::string why;
  auto fail = [&](std::string w) -> std::optional<PlanCut> {
    if (why_not) *why_not = std::move(w);
    return std::nullopt;
  };
  if (f.origins.size() != f.net.links.size() || conflict.empty() || plan.history)
    return fail("no conflict to learn from");
  CutBuilder b(f);
  network::Network sub = f.net;
  sub.links.clear();
  for (int li : conflict) {
    network::Link restated = f.net.links[li];
    if (!b.Add(li, restated, why)) return fail(why);
    sub.links.push_back(restated);
  }
  if (!b.Complete(why)) return fail(why);
  PlanCut cut = b.Take();
  // A contingent point whose own link is not in the conflict is the planner's in the sub-network
  // (a strategy for the whole network gives one for it: sound).
  std::vector<bool> has_link(sub.points.size(), false);
  for (const auto& l : sub.links)
    if (l.contingent) has_link[l.to] = true;
  for (std::size_t p = 0; p < sub.points.size(); ++p)
    if (sub.points[p].kind == network::PointKind::kContingent && !has_link[p])
      sub.points[p].kind = network::PointKind::kControllable;
  if (network::IsDynamicallyControllable(sub))
    return fail("its conflict does not stand without the ticks that order automatic transitions");
  if (ShapeOf(cut).loops.size() > kMaxLoops) return fail("its conflict has too many free events");
  return cut;
}

bool CutMatches(const PlanCut& cut, const Trajectory& t, const StatePlan& sp) {
  const CutShape s = ShapeOf(cut);
  const TrajectoryEvents te(t, sp);
  std::vector<int> ev(s.pins.size(), kNone);
  // The classes in order; a loop class tries every event of the plan.
  std::function<bool(std::size_t)> assign = [&](std::size_t i) -> bool {
    if (i == s.order.size()) return Holds(cut, s, ev, te);
    const int k = s.order[i];
    const CutPin& p = s.pins[k];
    switch (p.kind) {
      case CutPin::Kind::kLoop:
        for (int e = 1; e <= te.Goal(); ++e) {
          ev[k] = e;
          if (assign(i + 1)) return true;
        }
        return false;
      case CutPin::Kind::kOrigin: ev[k] = 0; break;
      case CutPin::Kind::kMark: ev[k] = te.Mark(cut.marks[p.mark]); break;
      case CutPin::Kind::kGoal: ev[k] = te.Goal(); break;
      case CutPin::Kind::kAfter:
        ev[k] = ev[p.from_class] == kNone ? kNone : te.Next(p.automaton, ev[p.from_class]);
        break;
      case CutPin::Kind::kBefore:
        ev[k] = ev[p.from_class] == kNone ? kNone : te.Prev(p.automaton, std::max(ev[p.from_class], 1) - 1);
        break;
    }
    return assign(i + 1);
  };
  return assign(0);
}

}  // namespace ctb::flexible
