#include "planner/explain/explain.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <thread>

#include "planner/analyze/analyze.h"
#include "planner/encode/encoder.h"
#include "planner/explain/summary.h"
#include "planner/smt/z3_core.h"
#include "planner/solve/cancel_watch.h"

namespace ctb {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kMaxBound = 1e7;

// Splits "/a/b/c" into its tokens (state-plan names are identifiers: no escapes needed).
std::vector<std::string> Tokens(const std::string& pointer) {
  std::vector<std::string> out;
  std::size_t k = 0;
  while (k < pointer.size() && pointer[k] == '/') {
    std::size_t next = pointer.find('/', k + 1);
    out.push_back(pointer.substr(k + 1, next == std::string::npos ? std::string::npos : next - k - 1));
    if (next == std::string::npos) break;
    k = next;
  }
  return out;
}

// Drops one part from a state plan's JSON (see explain.h). False when the pointer names none.
bool DropPart(Json& j, const std::string& pointer) {
  auto t = Tokens(pointer);
  if (t.size() == 2 && t[0] == "constraints" && (t[1] == "sequence" || t[1] == "forbidden")) {
    j["constraints"].erase(t[1]);
    return true;
  }
  if (t.size() == 2 && t[0] == "end_state" &&
      (t[1] == "goal_constraint" || t[1] == "maintenance_constraint")) {
    j["end_state"][t[1]] = "true";
    return true;
  }
  if (t.size() != 3 || t[0] != "constraints") return false;
  Json& group = j["constraints"][t[1]];
  if (!group.is_object() || !group.contains(t[2])) return false;
  group.erase(t[2]);
  if (t[1] == "event") return true;
  // Endpoints that name the dropped episode or temporal constraint go with it.
  const std::set<std::string> kinds = t[1] == "episodes" ? std::set<std::string>{"start", "end"}
                                                          : std::set<std::string>{"event1", "event2"};
  Json& events = j["constraints"]["event"];
  if (!events.is_object()) return true;
  std::vector<std::string> empty;
  for (auto& [name, list] : events.items()) {
    Json kept = Json::array();
    for (const auto& e : list) {
      std::string s = e.get<std::string>();
      auto dot = s.rfind('.');
      bool mine = dot != std::string::npos && s.substr(0, dot) == t[2] && kinds.count(s.substr(dot + 1));
      if (!mine) kept.push_back(e);
    }
    list = kept;
    if (list.size() < 2) empty.push_back(name);
  }
  for (const auto& n : empty) events.erase(n);
  return true;
}

bool SetBound(Json& j, const std::string& pointer, double value) {
  auto t = Tokens(pointer);
  if (t.size() != 4 || t[0] != "constraints" || (t[3] != "lower_bound" && t[3] != "upper_bound"))
    return false;
  Json& group = j["constraints"][t[1]];
  if (!group.is_object() || !group.contains(t[2])) return false;
  group[t[2]][t[3]] = value;
  return true;
}

std::string PartName(const std::string& pointer) {
  auto t = Tokens(pointer);
  if (t.size() == 2 && t[0] == "constraints") return t[1] == "sequence" ? "the sequence" : "the forbidden actions";
  if (t.size() == 2) return t[1] == "goal_constraint" ? "the goal" : "the maintenance constraint";
  if (t.size() == 3) {
    if (t[1] == "episodes") return "episode " + t[2];
    if (t[1] == "temporal") return "temporal constraint " + t[2];
    return "shared event " + t[2];
  }
  return pointer;
}

// Whole seconds print as integers.
Json Number(double v) {
  if (std::fabs(v - std::round(v)) < 1e-9 && std::fabs(v) < 1e15) return Json(std::llround(v));
  return Json(v);
}

// kCannotDrop: the reduced plan does not load (another part's condition names a dropped part).
enum class Verdict { kFeasible, kInfeasible, kUnknown, kCannotDrop };

class Explainer {
 public:
  Explainer(const Domain& d, const StatePlan& sp, const SolveOptions& so, const ExplainOptions& eo)
      : d_(d), sp_(sp), so_(so), eo_(eo), base_(StatePlanToJson(sp, d)),
        deadline_(Clock::now() + std::chrono::milliseconds(eo.time_limit_ms)),
        summary_(SummarizeStatePlan(d, sp)) {
    so_.objective = Objective::kCost;
    so_.model_out.clear();
    if (sp.goal.expr.op != Expr::Op::kTrue)
      parts_.push_back(sp.goal.pointer);
    if (sp.maintenance.expr.op != Expr::Op::kTrue) parts_.push_back(sp.maintenance.pointer);
    for (const auto& e : sp.episodes) parts_.push_back("/constraints/episodes/" + e.name);
    for (const auto& t : sp.temporals) parts_.push_back("/constraints/temporal/" + t.name);
    for (const auto& o : sp.orders)
      if (!o.name.empty()) parts_.push_back("/constraints/temporal/" + o.name);
    if (!sp.sequence.empty()) parts_.push_back("/constraints/sequence");
    if (!sp.forbidden.empty()) parts_.push_back("/constraints/forbidden");
    for (const SharedEvent* e : sp.AllSharedEvents()) parts_.push_back("/constraints/event/" + e->name);
  }

  // Static analysis of a plan, unless the caller turned it off (then every proof is a solver's).
  std::optional<StaticConflict> Static(const StatePlan& sp) const {
    if (!so_.static_analysis) return std::nullopt;
    return FindStaticConflict(d_, sp);
  }

  Explanation Run() {
    const auto t0 = Clock::now();
    Explanation out;
    std::optional<StaticConflict> stat = Static(sp_);
    std::vector<std::string> set = stat ? stat->parts : parts_;
    bool from_static = stat.has_value();
    bool proven = true;
    std::vector<std::string> consistent;
    const bool filter = set.size() > 1 || !from_static;
    // Quick pass: plans come fast (the first-plan engine), proofs do not. Each set without one
    // part is checked with a short limit; the parts whose removal leaves a plan are needed.
    if (filter) {
      const long cap = eo_.relaxation_check_ms;
      for (const std::string& p : set) {
        // A static conflict is usually minimal: the whole plan without p, when feasible, shows
        // the rest feasible too (it keeps more) and is the relaxation "drop p" at once.
        if (from_static && set.size() > 1) CheckParts(Without(p), cap);
        auto rest = Minus(set, p);
        if (!rest.empty()) CheckParts(rest, cap);
      }
    }
    // The parts left undecided need proofs. Static analysis could not explain: a minimised
    // unsatisfiable core from z3 (which may also leave parts undecided), then the filter.
    // z3 does not read actions (contract section 15): no core from it then.
    const bool from_core = !from_static && filter && Undecided(set) && !sp_.HasActionRules() &&
                           CoreFromZ3(set, proven);
    // Deletion filter: drop each part that the rest can do without.
    if (!from_core && filter) {
      for (const std::string& p : std::vector<std::string>(set)) {
        auto rest = Minus(set, p);
        Verdict v = rest.empty() ? Verdict::kFeasible : CheckParts(rest);
        if (v == Verdict::kInfeasible) {
          set = rest;
        } else if (v == Verdict::kUnknown) {
          proven = false;
        }
      }
    }
    for (const auto& f : feasible_)  // the largest set shown feasible, for "unknown"
      if (f.size() > consistent.size()) consistent = f;
    if (set.empty() || (!from_static && set == parts_ && parts_.empty())) {
      out.status = ExplanationStatus::kUnknown;
      return Finish(out, t0);
    }
    std::string text;
    if (from_static && set == stat->parts) {
      text = stat->text;
    } else {
      text = set.size() == 1 ? "This cannot be met (no plan with at most " + Horizon() +
                                   " events): "
                             : "These cannot all be met together (no plan with at most " +
                                   Horizon() + " events): ";
      std::vector<std::string> s;
      for (const auto& p : set) s.push_back(SummaryOf(p));
      for (std::size_t k = 0; k < s.size(); ++k) text += (k ? " " : "") + s[k];
    }
    out.conflicts.push_back({set, text, Json()});
    out.status = proven ? ExplanationStatus::kMinimal : ExplanationStatus::kUnknown;
    if (!proven) out.consistent = consistent;
    route_ = from_static ? "static analysis"
             : from_core && z3_checks_ > 0 ? "z3 core"
                                            : "deletion filter";
    conflict_ms_ = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count();
    Relax(set, stat, out.relaxations);
    return Finish(out, t0);
  }

 private:
  Explanation Finish(Explanation& out, Clock::time_point t0) {
    out.stats = {
        {"solver_calls", calls_},
        {"ms", std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count()}};
    if (!route_.empty()) {
      out.stats["conflict_by"] = route_;
      out.stats["conflict_ms"] = conflict_ms_;
    }
    if (z3_checks_ >= 0) out.stats["z3_checks"] = z3_checks_;
    return std::move(out);
  }

  std::string Horizon() const {
    return std::to_string(so_.horizon ? *so_.horizon : so_.max_horizon);
  }

  std::string SummaryOf(const std::string& pointer) const {
    for (const auto& s : summary_)
      if (s["pointer"] == pointer) return s["text"].get<std::string>();
    return PartName(pointer) + ".";
  }

  // The parts a reduced plan cannot drop alone (another part's condition names them).
  bool Droppable(const std::string& p) const {
    Diagnostics diags;
    return LoadStatePlan(Only(Without(p)), d_, diags).has_value();
  }

  // A minimised unsatisfiable core of the z3 model at the solve's horizon (planner/smt/
  // z3_core.h) within `set` (the whole plan, which the solve proved infeasible at that horizon):
  // one model with a literal per part that may be dropped, static analysis and the sets known
  // feasible tried on each subset first, half the remaining time. True when the core is shown
  // minimal; else `set` is the core reached (infeasible), and the filter goes on from it. Does
  // not apply (false, nothing changed) to replanning, a substituted engine, or parts whose
  // removal would make a command private (a different model).
  bool CoreFromZ3(std::vector<std::string>& set, bool& proven) {
    if (!eo_.z3_cores || so_.history || so_.backend || set != parts_) return false;
    std::vector<std::string> fixed, switched;
    for (const auto& p : parts_) (Droppable(p) ? switched : fixed).push_back(p);
    if (switched.empty()) return false;
    Diagnostics diags;
    auto least = LoadStatePlan(Only(fixed), d_, diags);
    const ProblemInfo info = ctb::Analyze(d_, sp_);
    if (!least || ctb::Analyze(d_, *least).command_public != info.command_public) return false;
    std::vector<smt::CorePart> parts;
    for (const auto& p : switched) parts.push_back(CorePartOf(p));
    EncodeOptions eo;
    eo.horizon = so_.horizon ? *so_.horizon : so_.max_horizon;
    eo.objective = Objective::kCost;
    eo.redundant = so_.redundant;
    const ModelSpec spec{&d_, &sp_, &info, eo};
    auto pointers = [&](const std::vector<int>& idx) {
      std::vector<std::string> out = fixed;
      for (int i : idx) out.push_back(switched[i]);
      return out;
    };
    smt::CoreOptions co;
    co.limits.time_limit_ms = std::max(1L, Remaining() / 2);
    co.limits.cancel = so_.cancel;
    co.known_infeasible = true;
    auto indices = [&](const std::vector<std::string>& ptrs) {
      std::vector<int> idx;
      for (const auto& p : ptrs) {
        auto it = std::find(switched.begin(), switched.end(), p);
        if (it != switched.end()) idx.push_back(static_cast<int>(it - switched.begin()));
      }
      std::sort(idx.begin(), idx.end());
      return idx;
    };
    for (const auto& f : feasible_) co.feasible.push_back(indices(f));
    // A set already shown infeasible (the quick pass), or static analysis of the subset.
    co.known_core = [&](const std::vector<int>& on) -> std::optional<std::vector<int>> {
      std::vector<std::string> ptrs = pointers(on);
      std::sort(ptrs.begin(), ptrs.end());
      for (const auto& f : infeasible_)
        if (std::includes(ptrs.begin(), ptrs.end(), f.begin(), f.end())) return indices(f);
      Diagnostics dg;
      auto sp = LoadStatePlan(Only(ptrs), d_, dg);
      if (!sp) return std::nullopt;
      auto c = Static(*sp);
      if (!c) return std::nullopt;
      return indices(c->parts);
    };
    smt::CoreResult r = smt::FindCoreWithZ3(spec, parts, co);
    z3_checks_ = r.checks;
    for (const auto& f : r.feasible) {  // every set shown to have a plan answers for its subsets
      auto ptrs = pointers(f);
      std::sort(ptrs.begin(), ptrs.end());
      feasible_.push_back(ptrs);
    }
    if (r.status != smt::CoreResult::Status::kInfeasible) return false;
    set = pointers(r.core);
    if (!r.minimal) return false;
    proven = true;
    return true;
  }

  smt::CorePart CorePartOf(const std::string& pointer) const {
    auto t = Tokens(pointer);
    using Kind = smt::CorePart::Kind;
    if (t.size() == 2) return {t[1] == "goal_constraint" ? Kind::kGoal : Kind::kMaintenance, 0};
    auto index = [&](const auto& list) {
      for (std::size_t i = 0; i < list.size(); ++i)
        if (list[i].name == t[2]) return static_cast<int>(i);
      return -1;
    };
    if (t[1] == "episodes") return {Kind::kEpisode, index(sp_.episodes)};
    if (t[1] == "temporal") return {Kind::kTemporal, index(sp_.temporals)};
    return {Kind::kEvent, index(sp_.events)};
  }

  // The state plan's JSON with only `keep` of the parts.
  Json Only(const std::vector<std::string>& keep) const {
    Json j = base_;
    for (const auto& p : parts_)
      if (std::find(keep.begin(), keep.end(), p) == keep.end()) DropPart(j, p);
    return j;
  }

  long Remaining() const {
    return std::chrono::duration_cast<std::chrono::milliseconds>(deadline_ - Clock::now()).count();
  }

  std::vector<std::string> Without(const std::string& p) const {
    std::vector<std::string> out;
    for (const auto& x : parts_)
      if (x != p) out.push_back(x);
    return out;
  }

  static std::vector<std::string> Minus(const std::vector<std::string>& set, const std::string& p) {
    std::vector<std::string> rest;
    for (const auto& x : set)
      if (x != p) rest.push_back(x);
    return rest;
  }

  // What is known of a set of parts without a solve: a plan for a set of parts, cut at the first
  // event at which a subset and the goal are met, is a plan for the subset, so every subset of
  // a feasible set is feasible; every superset of an infeasible set is infeasible.
  Verdict Known(const std::vector<std::string>& keep) const {
    std::vector<std::string> sorted = keep;
    std::sort(sorted.begin(), sorted.end());
    for (const auto& f : feasible_)
      if (std::includes(f.begin(), f.end(), sorted.begin(), sorted.end())) return Verdict::kFeasible;
    for (const auto& f : infeasible_)
      if (std::includes(sorted.begin(), sorted.end(), f.begin(), f.end()))
        return Verdict::kInfeasible;
    return Verdict::kUnknown;
  }

  // Whether some part's removal from `set` is not yet known to leave a plan.
  bool Undecided(const std::vector<std::string>& set) const {
    for (const auto& p : set) {
      auto rest = Minus(set, p);
      if (!rest.empty() && Known(rest) != Verdict::kFeasible) return true;
    }
    return false;
  }

  // The state plan with only `keep` of the parts (bounds as given), checked once (Known first;
  // cap_ms as in Check).
  Verdict CheckParts(const std::vector<std::string>& keep, long cap_ms = 0) {
    Verdict known = Known(keep);
    if (known != Verdict::kUnknown) return known;
    std::vector<std::string> sorted = keep;
    std::sort(sorted.begin(), sorted.end());
    Verdict v = Check(Only(keep), nullptr, cap_ms);
    if (v == Verdict::kFeasible) feasible_.push_back(sorted);
    if (v == Verdict::kInfeasible) infeasible_.push_back(sorted);
    return v;
  }

  // A feasible probe's plan, with the state plan it was found for.
  struct Witness {
    Trajectory plan;
    std::optional<StatePlan> sp;
    long tps = 1;
  };

  // Solves a state plan given as JSON. `witness` receives the plan when feasible. With
  // cap_ms > 0 the solve stops after that long (kUnknown unless a plan was found).
  Verdict Check(const Json& j, Witness* witness = nullptr, long cap_ms = 0) {
    Diagnostics diags;
    auto sp = LoadStatePlan(j, d_, diags);
    if (!sp) return Verdict::kCannotDrop;  // a part others name: cannot be dropped alone
    if (Static(*sp)) return Verdict::kInfeasible;
    long left = Remaining();
    if (left < 50 || (so_.cancel && so_.cancel->load())) return Verdict::kUnknown;
    SolveOptions o = so_;
    o.time_limit_ms = cap_ms > 0 ? std::min(left, cap_ms) : left;
    o.derive_network = false;  // a probe: its plan is a witness at most, never an answer
    ++calls_;
    // Feasibility needs one verified plan, not an optimum: without a witness to return, the
    // solve stops at the first plan it keeps (whole problems report each plan; the parts of a
    // split one do not, and are solved to the end). The caller's cancel still applies.
    std::atomic<bool> stop{false}, found{false};
    std::optional<CancelWatch> watch;
    if (!witness) {
      o.cancel = &stop;
      o.on_progress = [&](const SolveProgress&) {
        found = true;
        stop = true;
      };
      o.decompose = false;
      // One Gecode strategy: measured faster to a first plan than two sharing the cores
      // (bench/results/impossible.md).
      if (o.search == "portfolio") o.search = "g_first";
      watch.emplace(stop, [this] { return so_.cancel && so_.cancel->load(); },
                    std::chrono::milliseconds(20));
    }
    auto r = Solve(d_, *sp, o);
    if (watch) watch->Stop();
    if (found.load()) return Verdict::kFeasible;
    auto* t = std::get_if<SolveResult>(&r);
    if (!t) return Verdict::kUnknown;
    if (t->status == Termination::kInfeasible) return Verdict::kInfeasible;
    if (t->status == Termination::kOptimal || t->status == Termination::kFeasible) {
      if (witness && t->plan) *witness = Witness{std::move(*t->plan), std::move(sp), t->ticks_per_second};
      return Verdict::kFeasible;
    }
    return Verdict::kUnknown;
  }

  struct Candidate {
    Json changes;
    std::string text;
    double size;  // relative change; drops rank after every bound change
  };

  // The realized time between a temporal constraint's events or an episode's ends.
  static std::optional<double> Realized(const Witness& w, const std::string& group,
                                        const std::string& name) {
    const Trajectory& t = w.plan;
    if (!w.sp) return std::nullopt;
    const int g = t.goal_event;
    auto at = [&](int k) -> std::optional<double> {
      if (k < 0 || k > g || k >= static_cast<int>(t.events.size())) return std::nullopt;
      return static_cast<double>(t.events[k]) / static_cast<double>(w.tps);
    };
    auto between = [&](std::pair<int, int> ks, bool absolute) -> std::optional<double> {
      auto a = at(ks.first), b = at(ks.second);
      if (!a || !b) return std::nullopt;
      return absolute ? std::fabs(*b - *a) : *b - *a;
    };
    if (group == "temporal") {
      for (std::size_t q = 0; q < w.sp->temporals.size() && q < t.temporals.size(); ++q)
        if (w.sp->temporals[q].name == name) return between(t.temporals[q], true);
      for (std::size_t q = 0; q < w.sp->orders.size() && q < t.orders.size(); ++q)
        if (!w.sp->orders[q].name.empty() && w.sp->orders[q].name == name)
          return between(t.orders[q], true);
      return std::nullopt;
    }
    for (std::size_t p = 0; p < w.sp->episodes.size() && p < t.episodes.size(); ++p)
      if (w.sp->episodes[p].name == name) return between(t.episodes[p], false);
    return std::nullopt;
  }

  // The least move of one bound of `pointer` (a temporal constraint or episode) that makes the
  // whole plan feasible: raising the upper bound or lowering the lower bound.
  void BoundCandidate(const std::string& pointer, bool upper, std::optional<double> hint,
                      std::vector<Candidate>& out) {
    auto t = Tokens(pointer);
    if (t.size() != 3 || (t[1] != "temporal" && t[1] != "episodes")) return;
    const Json& part = base_["constraints"][t[1]][t[2]];
    // An order's bounds may be absent or null (0 and none, contract section 15).
    const Json& jlo = part.contains("lower_bound") ? part["lower_bound"] : Json();
    const Json& jhi = part.contains("upper_bound") ? part["upper_bound"] : Json();
    const double lo = jlo.is_number() ? jlo.get<double>() : 0;
    const double hi = jhi.is_number() ? jhi.get<double>() : kMaxBound;
    const double res = d_.time_resolution;
    const std::string bp = pointer + (upper ? "/upper_bound" : "/lower_bound");
    auto with = [&](double v) {
      Json j = base_;
      SetBound(j, bp, v);
      if (upper && v < lo) SetBound(j, pointer + "/lower_bound", v);
      return j;
    };
    if (upper ? hi >= kMaxBound : lo <= 0) return;
    // A witness with the bound out of the way gives a feasible value.
    // Checks of relaxed bounds need a plan, not a proof: each stops after relaxation_check_ms.
    const long cap = eo_.relaxation_check_ms;
    std::optional<double> good;
    if (hint && (upper ? *hint > hi : *hint < lo)) {
      if (Check(with(*hint), nullptr, cap) == Verdict::kFeasible) good = *hint;
    }
    if (!good) {
      Witness w;
      if (Check(with(upper ? kMaxBound : 0), &w, cap) != Verdict::kFeasible) return;
      auto v = Realized(w, t[1], t[2]);
      if (!v) return;
      good = upper ? std::max(*v, hi + res) : std::min(*v, lo - res);
      good = std::round(*good / res) * res;
    }
    // Binary search between the failing bound and the good value, in steps of the resolution.
    long bad_steps = std::lround((upper ? hi : lo) / res), good_steps = std::lround(*good / res);
    bool exact = true;
    const auto search_end = Clock::now() + std::chrono::milliseconds(eo_.relaxation_search_ms);
    while (std::labs(good_steps - bad_steps) > 1) {
      if (Clock::now() >= search_end) {
        exact = false;
        break;
      }
      long mid = (good_steps + bad_steps) / 2;
      Verdict v = Check(with(mid * res), nullptr, cap);
      if (v == Verdict::kFeasible) good_steps = mid;
      else if (v == Verdict::kInfeasible) bad_steps = mid;
      else {
        exact = false;
        break;
      }
    }
    const double value = good_steps * res, old = upper ? hi : lo;
    Json changes = Json::array({{{"pointer", bp}, {"value", Number(value)}}});
    if (upper && value < lo) changes.push_back({{"pointer", pointer + "/lower_bound"}, {"value", Number(value)}});
    relaxable_.insert(pointer);
    std::string text = upper ? "Allow " + SecondsText(value) + " s instead of " + SecondsText(old) +
                                   " s for " + PartName(pointer) + "."
                             : "Accept " + SecondsText(value) + " s instead of at least " +
                                   SecondsText(old) + " s for " + PartName(pointer) + ".";
    if (!exact)
      text += " (A smaller change may also work; the search for the least one was cut short.)";
    out.push_back({changes, text, std::fabs(value - old) / std::max(old, res)});
  }

  void Relax(const std::vector<std::string>& set, const std::optional<StaticConflict>& stat,
             std::vector<ExplanationRelaxation>& out) {
    std::vector<Candidate> cands;
    // The static check's least values (the bounds it no longer refutes) when it found the set.
    auto hint_for = [&](const std::string& bound) -> std::optional<double> {
      if (!stat) return std::nullopt;
      for (const auto& h : stat->hints)
        if (h.pointer == bound) return h.value;
      return std::nullopt;
    };
    for (const auto& p : set) {
      BoundCandidate(p, true, hint_for(p + "/upper_bound"), cands);
      BoundCandidate(p, false, hint_for(p + "/lower_bound"), cands);
    }
    for (const auto& p : set) {
      Json j = base_;
      if (!DropPart(j, p)) continue;
      // Dropping a part relaxes it further than any bound change: when one of its bounds could
      // be relaxed, the plan without it is feasible too (a plan for the relaxed bound, cut at the
      // first event at which the rest is met, is a plan for the rest). Else solve.
      if (relaxable_.count(p) || CheckParts(Without(p)) == Verdict::kFeasible)
        cands.push_back({Json::array({{{"pointer", p}, {"value", nullptr}}}),
                         "Drop " + PartName(p) + ".", 1e9 + cands.size()});
    }
    std::stable_sort(cands.begin(), cands.end(),
                     [](const Candidate& a, const Candidate& b) { return a.size < b.size; });
    for (std::size_t k = 0; k < cands.size() && static_cast<int>(k) < eo_.max_relaxations; ++k)
      out.push_back({cands[k].changes, cands[k].text});
  }

  const Domain& d_;
  const StatePlan& sp_;
  SolveOptions so_;
  const ExplainOptions eo_;
  const Json base_;
  const Clock::time_point deadline_;
  const Json summary_;
  std::vector<std::string> parts_;
  std::set<std::string> relaxable_;  // parts with a bound relaxation shown feasible
  std::vector<std::vector<std::string>> feasible_;  // sets of parts shown feasible (sorted)
  std::vector<std::vector<std::string>> infeasible_;  // sets shown infeasible (sorted)
  int calls_ = 0;
  int z3_checks_ = -1;  // -1: the z3 core route did not run
  std::string route_;   // what found the conflict
  long conflict_ms_ = 0;  // until the conflict was known (then the relaxations)
};

}  // namespace

Explanation Explain(const Domain& d, const StatePlan& sp, const SolveOptions& so,
                    const ExplainOptions& eo) {
  try {
    return Explainer(d, sp, so, eo).Run();
  } catch (const std::exception& e) {  // never across the library boundary
    Explanation out;
    out.error = e.what();
    return out;
  }
}

namespace {

// The pointer a conflict link's `why` names: the state plan's part, or the part a tie of the
// derivation serves ("one event in the plan, for /end_state/goal_constraint"); "" for a duration.
std::string WhyPointer(const std::string& why) {
  if (why.rfind("/", 0) == 0) return why;
  const auto at = why.find(", for /");
  if (at != std::string::npos && why.rfind("one event in the plan", 0) == 0) return why.substr(at + 6);
  const auto kept = why.find("order kept for /");
  if (kept != std::string::npos) return why.substr(kept + 15);
  return "";
}

// The explanation of an answer that no plan of the asked kind of controllability exists
// (solve/controllable.cpp): each conflict the search learned, in words, and the relaxations it
// checked by planning again.
Explanation ControllabilityExplanation(const Json& c) {
  Explanation out;
  out.status = ExplanationStatus::kControllability;
  std::set<std::string> texts;
  for (const Json& links : c.value("conflicts", Json::array())) {
    std::vector<std::string> durations, rules;
    std::set<std::string> pointers;
    for (const Json& l : links) {
      const std::string why = l.value("why", "");
      if (l.value("kind", "") == "contingent") {
        durations.push_back(why.substr(why.rfind("duration ", 0) == 0 ? 9 : 0) + " (" +
                            l["lb"].dump() + " to " + l["ub"].dump() + " s)");
        continue;
      }
      const std::string p = WhyPointer(why);
      if (!p.empty() && pointers.insert(p).second) rules.push_back(PartName(p));
    }
    std::string text = "Some outcome of the uncertain durations";
    for (std::size_t i = 0; i < durations.size(); ++i)
      text += (i == 0 ? " of " : i + 1 == durations.size() ? " and " : ", ") + durations[i];
    text += " breaks ";
    if (rules.empty()) text += "the order the plan needs";
    for (std::size_t i = 0; i < rules.size(); ++i)
      text += (i == 0 ? "" : i + 1 == rules.size() ? " and " : ", ") + rules[i];
    text += ", whatever is decided as they happen.";
    if (!texts.insert(text).second) continue;
    out.conflicts.push_back({std::vector<std::string>(pointers.begin(), pointers.end()), text, Json()});
  }
  for (const Json& r : c.value("relaxations", Json::array()))
    out.relaxations.push_back({r.value("changes", Json::array()), r.value("text", "")});
  out.stats = {{"conflict_by", "controllability search"},
               {"ms", c.value("search", Json::object()).value("ms", 0)}};
  return out;
}

}  // namespace

void AnnotateAnswer(const Domain& d, const StatePlan& sp, const SolveOptions& so,
                    SolveResult& answer) {
  answer.summary = SummarizeStatePlan(d, sp);
  if (answer.status != Termination::kInfeasible) return;
  const Json c = answer.controllability.value_or(Json::object());
  if (c.value("search", Json::object()).value("proven", false)) {
    answer.explanation = ControllabilityExplanation(c);
  } else {
    ExplainOptions eo;
    eo.time_limit_ms = so.time_limit_ms;
    answer.explanation = Explain(d, sp, so, eo);
  }
}

std::string DialogueNote(const SolveResult& answer) {
  if (!answer.explanation) return "";
  const Explanation& ex = *answer.explanation;
  std::string note = "(planner) No plan meets this state plan.";
  for (const auto& c : ex.conflicts)
    note += " Conflict: " + c.text + " (parts: " + Json(c.constraints).dump() + ")";
  if (!ex.relaxations.empty()) {
    note += " Each of these changes would make it possible:";
    for (const auto& r : ex.relaxations) note += " " + r.text + " " + r.changes.dump() + ";";
  }
  return note;
}

std::optional<StatePlan> ApplyChanges(const Domain& d, const StatePlan& sp, const Json& changes,
                                      Diagnostics& diags) {
  Json j = StatePlanToJson(sp, d);
  if (!changes.is_array()) {
    diags.Error("", "changes must be an array");
    return std::nullopt;
  }
  for (const auto& c : changes) {
    if (!c.is_object() || !c.contains("pointer") || !c["pointer"].is_string() || !c.contains("value")) {
      diags.Error("", "a change needs \"pointer\" and \"value\"");
      return std::nullopt;
    }
    const std::string p = c["pointer"];
    bool ok = c["value"].is_null() ? DropPart(j, p)
                                   : c["value"].is_number() && SetBound(j, p, c["value"].get<double>());
    if (!ok) {
      diags.Error(p, "no state-plan part or bound at this pointer");
      return std::nullopt;
    }
  }
  return LoadStatePlan(j, d, diags);
}

}  // namespace ctb
