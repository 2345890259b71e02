#include "planner/model/number_text.h"
#include "planner/analyze/analyze.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "planner/analyze/abstraction.h"
#include "planner/analyze/time_network.h"
#include "planner/analyze/zone_reach.h"
#include "planner/model/error.h"

namespace ctb {

using namespace analysis;  // NOLINT: the abstraction is this file's vocabulary

namespace {

std::string EpisodePointer(const Episode& e) { return "/constraints/episodes/" + PointerToken(e.name); }
std::string TemporalPointer(const Temporal& t) { return "/constraints/temporal/" + PointerToken(t.name); }
std::string EventPointer(const SharedEvent& e) { return "/constraints/event/" + PointerToken(e.name); }

// A reason in words why a condition cannot hold, from its top-level conjunction: a change no
// transition allows, or a location out of reach. Empty when no single atom pair explains it.
std::string WhyNever(const Domain& d, const Abstraction& ab, const Condition& c,
                     const std::vector<std::vector<char>>* allowed) {
  std::vector<const Expr*> atoms;
  std::vector<const Expr*> stack{&c.raw};
  while (!stack.empty()) {
    const Expr* e = stack.back();
    stack.pop_back();
    if (e->op == Expr::Op::kAnd) {
      stack.push_back(&e->kids[1]);
      stack.push_back(&e->kids[0]);
    } else if (e->op == Expr::Op::kAtom && e->var_kind == VarKind::kLocation && !e->not_equal &&
               e->index.kind != IndexKind::kFixed) {
      atoms.push_back(e);
    }
  }
  const bool change = c.raw_info.IsChange();
  for (const Expr* x : atoms) {
    const Automaton& au = d.automata[x->target];
    if (change && x->index.kind == IndexKind::kI) {
      for (const Expr* y : atoms) {
        if (y->target != x->target || y->index.kind != IndexKind::kIPlus1) continue;
        if (x->value_code == y->value_code) continue;
        bool exists = false;
        for (const auto& tr : au.transitions)
          exists = exists || (tr.from == x->value_code && tr.to == y->value_code);
        if (!exists)
          return "no transition takes " + au.name + " from " + au.locations[x->value_code] +
                 " to " + au.locations[y->value_code];
      }
    }
    if (!ab.reach[x->target][x->value_code]) {
      std::string why = au.name + " cannot reach " + au.locations[x->value_code] + " from " +
                        au.locations[ab.init[x->target]];
      return allowed ? why + " while the maintenance constraint holds" : why;
    }
  }
  return "";
}

class Checker {
 public:
  Checker(const Domain& d, const StatePlan& sp, const AnalysisOptions& o) : d_(d), sp_(sp), o_(o) {}

  std::vector<StaticConflict> Run() {
    Abstraction plain = Build(d_, sp_, nullptr);
    Singles(plain, nullptr, {});
    SharedEvents(plain);
    Network(plain, "");
    if (sp_.maintenance.expr.op != Expr::Op::kTrue) {
      auto allowed = Allowed();
      Abstraction m = Build(d_, sp_, &allowed);
      if (m.only_initial) {
        Add({"never_holds", {sp_.goal.pointer, sp_.maintenance.pointer},
             "The maintenance constraint fails in the initial state, so the goal would have to "
             "hold at once, and it does not.",
             std::nullopt, {}},
            !MayHold(m, {AtEvent(sp_.goal)}));
      }
      Singles(m, &allowed, sp_.maintenance.pointer);
      Network(m, sp_.maintenance.pointer);
    }
    if (out_.empty() && o_.zones) Zones();
    if (o_.zones)
      for (auto& c : out_) Sharpen(c);
    return std::move(out_);
  }

 private:
  // The locations each automaton may occupy on a stage where the maintenance constraint holds.
  std::vector<std::vector<char>> Allowed() const {
    std::vector<std::vector<Opt>> all(d_.automata.size());
    for (std::size_t a = 0; a < d_.automata.size(); ++a)
      for (int l = 0; l < static_cast<int>(d_.automata[a].locations.size()); ++l)
        all[a].push_back({l, l});
    std::vector<Term> terms{OnStage(sp_.maintenance)};
    SatSearch s(sp_.initial, all, terms);
    std::vector<std::vector<char>> allowed(d_.automata.size());
    for (std::size_t a = 0; a < d_.automata.size(); ++a)
      allowed[a].assign(d_.automata[a].locations.size(), 1);
    for (int a : s.order())
      for (int l = 0; l < static_cast<int>(all[a].size()); ++l) allowed[a][l] = s.Run(a, l);
    return allowed;
  }

  // The time network's conflict (time_network.h), when there is one.
  void Network(const Abstraction& ab, const std::string& maint) {
    if (!o_.time_network) return;
    auto tc = FindTimeConflict(d_, sp_, ab, maint);
    if (!tc) return;
    StaticConflict c{"time_network", tc->parts, tc->text, std::nullopt, tc->hints};
    if (!c.hints.empty()) c.hint = c.hints.front();
    Add(std::move(c), true);
  }

  // The zone search's conflict (zone_reach.h): the runs themselves, for what the abstraction
  // above cannot see (events no part names, transitions an automaton must take).
  void Zones() {
    auto z = FindZoneConflict(d_, sp_, o_.clocks_at_zero);
    if (!z) return;
    StaticConflict c{"zones", z->parts, z->text, std::nullopt, z->hints};
    if (!c.hints.empty()) c.hint = c.hints.front();
    Add(std::move(c), true);
  }

  // A hint of the other checks may be below the least value that works (the time network sees
  // only the state plan's events); the zone search's, on the same parts, replaces it when higher.
  void Sharpen(StaticConflict& c) const {
    if (c.kind == "zones" || c.hints.empty()) return;
    for (const BoundHint& z : FindZoneHints(d_, sp_, c.parts, o_.clocks_at_zero))
      for (BoundHint& h : c.hints) {
        if (h.pointer != z.pointer) continue;
        const bool upper = h.pointer.ends_with("/upper_bound");
        h.value = upper ? std::max(h.value, z.value) : std::min(h.value, z.value);
      }
    if (c.hint)
      for (const BoundHint& h : c.hints)
        if (h.pointer == c.hint->pointer) c.hint = h;
  }

  // Adds c when `found`, unless a conflict already found uses a subset of its parts.
  void Add(StaticConflict c, bool found) {
    if (!found) return;
    std::set<std::string> mine(c.parts.begin(), c.parts.end());
    for (const auto& o : out_) {
      bool subset = true;
      for (const auto& p : o.parts) subset = subset && mine.count(p);
      if (subset) return;
    }
    out_.push_back(std::move(c));
  }

  // Checks of one part each (with the maintenance constraint as a second part when given).
  void Singles(const Abstraction& ab, const std::vector<std::vector<char>>* allowed,
               const std::string& maint) {
    auto parts = [&](const std::string& p) {
      std::vector<std::string> v{p};
      if (!maint.empty()) v.push_back(maint);
      return v;
    };
    const std::string under = maint.empty() ? "" : " while the maintenance constraint holds";
    auto reason = [&](const Condition& c) {
      std::string why = WhyNever(d_, ab, c, allowed);
      return why.empty() ? "" : ": " + why;
    };
    if (sp_.goal.expr.op != Expr::Op::kTrue)
      Add({"never_holds", parts(sp_.goal.pointer),
           "The goal can never be reached" + under + reason(sp_.goal) + ".", std::nullopt, {}},
          !MayHold(ab, {AtEvent(sp_.goal)}));
    for (const auto& ep : sp_.episodes) {
      const std::string p = EpisodePointer(ep);
      if (!MayHold(ab, {AtEvent(ep.accepting)})) {
        Add({"never_holds", parts(p),
             "Episode " + ep.name + " can never start" + under + reason(ep.accepting) + ".",
             std::nullopt, {}}, true);
      } else if (!MayHold(ab, {AtEvent(ep.accepting), OnStage(ep.state)})) {
        Add({"never_holds", parts(p),
             "Episode " + ep.name + " can never start: its state constraint cannot hold when its "
             "accepting constraint does" + under + ".", std::nullopt, {}}, true);
      } else if (ab.only_initial) {
        Add({"never_holds", parts(p),
             "Episode " + ep.name + " needs an event after the start, but the maintenance "
             "constraint fails in the initial state.", std::nullopt, {}}, true);
      }
    }
    for (const auto& tc : sp_.temporals) {
      const std::string p = TemporalPointer(tc);
      bool e1 = MayHold(ab, {AtEvent(tc.event1)}), e2 = MayHold(ab, {AtEvent(tc.event2)});
      if (!e1 || !e2) {
        const Condition& c = e1 ? tc.event2 : tc.event1;
        Add({"never_holds", parts(p),
             "Temporal constraint " + tc.name + " can never be met: its " +
                 (e1 ? "second" : "first") + " event can never happen" + under + reason(c) + ".",
             std::nullopt, {}}, true);
        continue;
      }
      // Deadline: the least time between an event of one condition and a later one of the other.
      auto p1 = Project(ab, {AtEvent(tc.event1)}), p2 = Project(ab, {AtEvent(tc.event2)});
      double gap = std::min(LeastGap(ab, p1, p2), LeastGap(ab, p2, p1));
      if (MayHold(ab, {AtEvent(tc.event1), AtEvent(tc.event2)})) gap = 0;
      if (gap > tc.upper + 1e-9) {
        Add({"deadline", parts(p),
             "Temporal constraint " + tc.name + " allows at most " + NumberText(tc.upper) +
                 " s between its two events, but the automata need at least " + NumberText(gap) +
                 " s to get from one to the other" + under + ".",
             BoundHint{p + "/upper_bound", gap}, {BoundHint{p + "/upper_bound", gap}}}, true);
      }
    }
  }

  // Endpoints that must share one event but whose conditions cannot hold together.
  void SharedEvents(const Abstraction& ab) {
    for (const auto& ev : sp_.events) {
      // Per endpoint: the terms that hold at its event, and the part that owns it.
      struct End {
        std::vector<Term> terms;
        std::string part;
        std::string text;
      };
      std::vector<End> ends;
      std::map<std::string, std::set<EndpointKind>> kinds;
      for (const auto& e : ev.endpoints) {
        End x;
        x.text = e.text;
        switch (e.kind) {
          case EndpointKind::kEpisodeStart: {
            const Episode& ep = sp_.episodes[e.index];
            x.terms = {AtEvent(ep.accepting), OnStage(ep.state)};
            x.part = EpisodePointer(ep);
            break;
          }
          case EndpointKind::kEpisodeEnd:
            x.part = EpisodePointer(sp_.episodes[e.index]);
            break;
          case EndpointKind::kEvent1:
            x.terms = {AtEvent(sp_.temporals[e.index].event1)};
            x.part = TemporalPointer(sp_.temporals[e.index]);
            break;
          case EndpointKind::kEvent2:
            x.terms = {AtEvent(sp_.temporals[e.index].event2)};
            x.part = TemporalPointer(sp_.temporals[e.index]);
            break;
        }
        kinds[x.part].insert(e.kind);
        ends.push_back(std::move(x));
      }
      const std::string evp = EventPointer(ev);
      // An episode cannot start and end at one event.
      bool done = false;
      for (const auto& ep : sp_.episodes) {
        auto it = kinds.find(EpisodePointer(ep));
        if (it != kinds.end() && it->second.count(EndpointKind::kEpisodeStart) &&
            it->second.count(EndpointKind::kEpisodeEnd)) {
          Add({"shared_event", {evp, it->first},
               "Shared event " + ev.name + " puts the start and the end of episode " + ep.name +
                   " on one event, but an episode ends at a later event than it starts.",
               std::nullopt, {}}, true);
          done = true;
        }
      }
      if (done) continue;
      auto holds = [&](const std::vector<int>& keep) {
        std::vector<Term> terms;
        for (int k : keep) terms.insert(terms.end(), ends[k].terms.begin(), ends[k].terms.end());
        return MayHold(ab, terms);
      };
      std::vector<int> keep;
      for (int k = 0; k < static_cast<int>(ends.size()); ++k) keep.push_back(k);
      if (holds(keep)) continue;
      // Deletion filter over the endpoints: a smallest set that still cannot hold together.
      for (int k = static_cast<int>(ends.size()) - 1; k >= 0; --k) {
        std::vector<int> rest;
        for (int x : keep)
          if (x != k) rest.push_back(x);
        if (!holds(rest)) keep = rest;
      }
      std::vector<std::string> parts{evp};
      std::string names;
      for (int k : keep) {
        if (std::find(parts.begin(), parts.end(), ends[k].part) == parts.end())
          parts.push_back(ends[k].part);
        names += (names.empty() ? "" : " and ") + ends[k].text;
      }
      Add({"shared_event", parts,
           "Shared event " + ev.name + " puts " + names +
               " on one event, but their conditions cannot hold at the same time.",
           std::nullopt, {}}, true);
    }
  }

  const Domain& d_;
  const StatePlan& sp_;
  const AnalysisOptions o_;
  std::vector<StaticConflict> out_;
};

}  // namespace

std::vector<StaticConflict> FindStaticConflicts(const Domain& d, const StatePlan& sp,
                                                const AnalysisOptions& o) {
  auto out = Checker(d, sp, o).Run();
  std::stable_sort(out.begin(), out.end(), [](const StaticConflict& a, const StaticConflict& b) {
    return a.parts.size() < b.parts.size();
  });
  return out;
}

std::optional<StaticConflict> FindStaticConflict(const Domain& d, const StatePlan& sp,
                                                 const AnalysisOptions& o) {
  auto all = FindStaticConflicts(d, sp, o);
  if (all.empty()) return std::nullopt;
  return all.front();
}

std::optional<double> ShortestTime(const Domain& d, const StatePlan& sp, int a, int from, int to) {
  Abstraction ab = Build(d, sp, nullptr);
  double v = ab.Dist(a, from, to);
  if (std::isinf(v)) return std::nullopt;
  return v;
}

}  // namespace ctb
