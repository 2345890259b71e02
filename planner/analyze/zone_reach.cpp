// The zone search's conflicts (zone_reach.h): the search of zone_search.cpp on the whole plan,
// a deletion filter over its parts, and per bound of the parts the least value it no longer
// refutes (a binary search; refutation is monotone: a tighter bound keeps fewer runs).
#include "planner/model/number_text.h"
#include "planner/analyze/zone_reach.h"

#include <algorithm>
#include <cmath>

#include "planner/model/error.h"

namespace ctb::analysis {

namespace {

using SteadyClock = std::chrono::steady_clock;

// Per analysis: the searches together stop after this long or this many symbolic states. A
// proof on the shipped cases takes a few hundred states; a plan is usually found in fewer.
constexpr std::chrono::milliseconds kTimeBudget{100};
constexpr long kStateBudget = 60000;

// A part of the state plan the search can drop: its pointer and where its flag is.
struct Part {
  std::string pointer;
  char* flag;
};

std::vector<Part> Parts(const StatePlan& sp, ZoneQuestion& q) {
  std::vector<Part> out;
  for (std::size_t g = 0; g < sp.events.size(); ++g)
    out.push_back({"/constraints/event/" + PointerToken(sp.events[g].name), &q.events[g]});
  for (std::size_t k = 0; k < sp.temporals.size(); ++k)
    out.push_back({"/constraints/temporal/" + PointerToken(sp.temporals[k].name), &q.temporals[k]});
  for (std::size_t p = 0; p < sp.episodes.size(); ++p)
    out.push_back({"/constraints/episodes/" + PointerToken(sp.episodes[p].name), &q.episodes[p]});
  return out;
}

class Conflict {
 public:
  Conflict(const Domain& d, const StatePlan& sp, bool clocks_known)
      : d_(d),
        sp_(sp),
        q_(WholePlan(d, sp, clocks_known)),
        budget_{kStateBudget, SteadyClock::now() + kTimeBudget} {}

  // Keeps only the parts named (pointers); the goal and maintenance constraint likewise.
  void Keep(const std::vector<std::string>& parts) {
    auto in = [&](const std::string& p) {
      return std::find(parts.begin(), parts.end(), p) != parts.end();
    };
    for (Part& p : Parts(sp_, q_)) *p.flag = in(p.pointer);
    q_.goal = in(sp_.goal.pointer);
    q_.maintenance = in(sp_.maintenance.pointer);
  }

  std::vector<BoundHint> HintsOnly() {
    std::vector<BoundHint> out;
    if (Refuted(q_)) Hints(out);
    return out;
  }

  std::optional<ZoneConflict> Run() {
    if (SearchZones(d_, sp_, q_, budget_) != Reach::kNoRun) return std::nullopt;
    Minimise();
    ZoneConflict out;
    out.parts = Pointers();
    Hints(out.hints);
    out.text = Text(out.hints);
    return out;
  }

 private:
  bool Refuted(const ZoneQuestion& q) { return SearchZones(d_, sp_, q, budget_) == Reach::kNoRun; }

  // Deletion filter: each part whose removal the search still refutes goes.
  void Minimise() {
    for (Part& p : Parts(sp_, q_)) {
      *p.flag = 0;
      if (!Refuted(q_)) *p.flag = 1;
    }
    if (q_.goal && sp_.goal.expr.op != Expr::Op::kTrue) {
      q_.goal = false;
      if (!Refuted(q_)) q_.goal = true;
    }
    if (q_.maintenance && sp_.maintenance.expr.op != Expr::Op::kTrue) {
      q_.maintenance = false;
      if (!Refuted(q_)) q_.maintenance = true;
    }
  }

  std::vector<std::string> Pointers() {
    std::vector<std::string> out;
    if (q_.goal && sp_.goal.expr.op != Expr::Op::kTrue) out.push_back(sp_.goal.pointer);
    for (const Part& p : Parts(sp_, q_))
      if (*p.flag) out.push_back(p.pointer);
    if (q_.maintenance && sp_.maintenance.expr.op != Expr::Op::kTrue)
      out.push_back(sp_.maintenance.pointer);
    return out;
  }

  // The least value of `bound` (ticks) the search no longer refutes, between `bad` (refuted)
  // and `good`; nullopt when `good` is refuted too.
  std::optional<std::int64_t> Least(std::int64_t& bound, std::int64_t bad, std::int64_t good) {
    const std::int64_t keep = bound;
    bound = good;
    const bool helps = !Refuted(q_);
    if (helps)
      NarrowRefuted(bad, good, [&](std::int64_t v) {
        bound = v;
        return Refuted(q_);
      });
    bound = keep;
    if (!helps) return std::nullopt;
    return good;
  }

  void Hint(std::vector<BoundHint>& out, const std::string& part, std::int64_t& lo,
            std::int64_t& hi) {
    const std::int64_t none = std::llround(1e7 * static_cast<double>(q_.tps));
    const double tps = static_cast<double>(q_.tps);
    if (hi < none)
      if (auto v = Least(hi, hi, none)) out.push_back({part + "/upper_bound", *v / tps});
    if (lo > 0)
      if (auto v = Least(lo, lo, 0)) out.push_back({part + "/lower_bound", *v / tps});
  }

  void Hints(std::vector<BoundHint>& out) {
    for (std::size_t k = 0; k < sp_.temporals.size(); ++k)
      if (q_.temporals[k])
        Hint(out, "/constraints/temporal/" + PointerToken(sp_.temporals[k].name), q_.tc_lo[k],
             q_.tc_hi[k]);
    for (std::size_t p = 0; p < sp_.episodes.size(); ++p)
      if (q_.episodes[p])
        Hint(out, "/constraints/episodes/" + PointerToken(sp_.episodes[p].name), q_.ep_lo[p],
             q_.ep_hi[p]);
  }

  std::string Text(const std::vector<BoundHint>& hints) const {
    std::string s =
        "These cannot all hold, whatever the number of events: no run of the automata meets "
        "them together (every run was followed, with the automata's timing, until it broke one "
        "of them)";
    std::string needs;
    for (const auto& h : hints) {
      const std::string& p = h.pointer;
      const bool upper = p.size() > 12 && p.compare(p.size() - 12, 12, "/upper_bound") == 0;
      const std::string part = p.substr(0, p.rfind('/'));
      const std::string name = part.substr(part.rfind('/') + 1);
      const std::string kind =
          part.find("/episodes/") != std::string::npos ? "episode " : "temporal constraint ";
      needs += (needs.empty() ? "" : "; ") + kind + name + " would need " +
               (upper ? "at least " : "at most ") + NumberText(h.value) + " s as its " +
               (upper ? "upper" : "lower") + " bound";
    }
    return needs.empty() ? s + "." : s + ": " + needs + ".";
  }

  const Domain& d_;
  const StatePlan& sp_;
  ZoneQuestion q_;
  ZoneBudget budget_;
};

}  // namespace

ZoneQuestion WholePlan(const Domain& d, const StatePlan& sp, bool clocks_known) {
  ZoneQuestion q;
  q.tps = std::max(1L, std::lround(1.0 / d.time_resolution));
  auto ticks = [&](double s) { return std::llround(s * static_cast<double>(q.tps)); };
  q.clocks_known = clocks_known;
  q.episodes.assign(sp.episodes.size(), 1);
  q.temporals.assign(sp.temporals.size(), 1);
  q.events.assign(sp.events.size(), 1);
  for (const auto& ep : sp.episodes)
    q.ep_lo.push_back(ticks(ep.lower)), q.ep_hi.push_back(ticks(ep.upper));
  for (const auto& tc : sp.temporals)
    q.tc_lo.push_back(ticks(tc.lower)), q.tc_hi.push_back(ticks(tc.upper));
  return q;
}

void NarrowRefuted(std::int64_t& bad, std::int64_t& good,
                   const std::function<bool(std::int64_t)>& refuted,
                   const std::function<bool()>& more) {
  while (std::llabs(good - bad) > 1 && (!more || more())) {
    const std::int64_t mid = bad + (good - bad) / 2;
    if (refuted(mid))
      bad = mid;
    else
      good = mid;
  }
}

std::optional<ZoneConflict> FindZoneConflict(const Domain& d, const StatePlan& sp,
                                             bool clocks_known) {
  if (d.automata.size() > kMaxZoneAutomata) return std::nullopt;
  return Conflict(d, sp, clocks_known).Run();
}

std::vector<BoundHint> FindZoneHints(const Domain& d, const StatePlan& sp,
                                     const std::vector<std::string>& parts, bool clocks_known) {
  if (d.automata.size() > kMaxZoneAutomata) return {};
  Conflict c(d, sp, clocks_known);
  c.Keep(parts);
  return c.HintsOnly();
}

}  // namespace ctb::analysis
