#include "planner/model/elapsed.h"
#include "planner/solve/controllable.h"

#include <chrono>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "planner/flexible/cut.h"
#include "planner/model/trajectory.h"
#include "planner/solve/flexible_answer.h"

namespace ctb::solve {

namespace {

using Clock = std::chrono::steady_clock;


Error InternalError(std::string message) {
  Error e;
  e.code = ErrorCode::kInternal;
  e.message = std::move(message);
  return e;
}

struct Search {
  const Domain& d;
  const StatePlan& sp;
  const SolveOptions& o;
  const FixedSolve& fixed;
};

// The change a relaxation makes, as the explanation's `changes` (a state-plan bound) or none (a
// duration of the action model).
Json Changes(const Json& r) {
  const std::string kind = r.value("kind", ""), why = r.value("why", "");
  if (kind == "later_upper_bound" && why.rfind("/constraints/", 0) == 0)
    return Json::array({{{"pointer", why + "/upper_bound"}, {"value", r["to"]}}});
  if (kind == "earlier_lower_bound" && why.rfind("/constraints/", 0) == 0)
    return Json::array({{{"pointer", why + "/lower_bound"}, {"value", r["to"]}}});
  return Json::array();
}

// How large a relaxation's change is, to keep the least of those that change one bound the same
// way: the distance from the bound as written.
double Size(const Json& r) {
  const Json& from = r["from"];
  const Json& to = r["to"];
  if (from.is_number() && to.is_number()) return std::fabs(to.get<double>() - from.get<double>());
  if (from.is_array() && to.is_array() && from.size() == 2 && to.size() == 2)
    return std::fabs(to[0].get<double>() - from[0].get<double>()) +
           std::fabs(to[1].get<double>() - from[1].get<double>());
  return 0;
}

// The relaxations of every plan the search cut: each was computed exactly on its plan's network
// and checked there (flexible_answer.cpp), and that plan, with the change, is a plan of the asked
// kind: with a looser bound it stays valid, and with a narrower duration its network (a strategy
// for every outcome of the narrower range) is again one whose every schedule is valid. Of those
// that change one bound the same way, the least.
Json MergedRelaxations(const Json& candidates) {
  std::map<std::string, Json> best;
  std::vector<std::string> order;
  for (const Json& r : candidates) {
    std::string side;
    if (r["to"].is_array() && r["from"].is_array())
      side = r["to"][0] == r["from"][0] ? "above" : "below";
    const std::string key = r.value("why", "") + "|" + r.value("kind", "") + "|" + side;
    auto it = best.find(key);
    if (it == best.end()) {
      order.push_back(key);
      best[key] = r;
    } else if (Size(r) < Size(it->second)) {
      it->second = r;
    }
  }
  Json out = Json::array();
  for (const auto& k : order) {
    Json r = best[k];
    r["changes"] = Changes(r);
    out.push_back(std::move(r));
  }
  return out;
}

// The answer when every plan within the horizon was cut: infeasible, for the asked kind.
void NothingLeft(SolveResult& doc, const Search& s, const Json& conflicts, const Json& candidates,
                 int cuts, Clock::time_point t0) {
  const Controllability asked = Asked(s.d, s.o);
  const char* kind = asked == Controllability::kStrong ? "strongly" : "dynamically";
  doc.status = Termination::kInfeasible;
  doc.scope = InfeasibleScope::kMaxHorizon;
  doc.message = std::string("no plan within the horizon is ") + kind +
                   " controllable: every plan the search found broke on a conflict of its uncertain "
                   "durations (" + std::to_string(cuts) + " cut)";
  Json c = {{"asked", ControllabilityName(asked)}, {"met", false},
            {"search", {{"plans_cut", cuts}, {"proven", true}, {"ms", MsSince(t0)}}},
            {"conflicts", conflicts}};
  // Each makes a cut plan dynamically controllable: offered when that is what was asked.
  c["relaxations"] =
      asked == Controllability::kStrong ? Json::array() : MergedRelaxations(candidates);
  doc.controllability = std::move(c);
}

// One round of the search: the best plan the cuts leave, its network checked (AddFlexibility).
// After the first round a plan is first looked for briefly: a plan found then that is not of the
// asked kind is cut at once, without the proof that it was the best (cutting it is sound whatever
// it is). A plan of the asked kind, or none, is looked for again with the whole time left, so
// that `optimal` and `infeasible` keep their meaning.
struct Round {
  std::variant<SolveResult, Error> answer;
  FlexibleOutcome outcome;
  bool checked = false;  // a verified plan whose network was derived and checked
};

class Searcher {
 public:
  explicit Searcher(const Search& s) : s_(s), current_(s.sp) {}

  std::variant<SolveResult, Error> Run() {
    for (int cuts = 0;; ++cuts) {
      Round r = Solve(cuts > 0);
      SolveResult* doc = std::get_if<SolveResult>(&r.answer);
      if (!doc && first_) return Fallback(cuts, "the solver failed: " + std::get<Error>(r.answer).message);
      if (!doc) return std::move(r.answer);
      if (!r.checked) return Unplanned(std::move(r.answer), cuts);
      for (const PlanCut& cut : current_.cuts)
        if (flexible::CutMatches(cut, plan_, s_.sp))
          return InternalError("the search among plans found a plan it had cut");
      if (!doc->controllability) doc->controllability = Json::object();
      Json& c = *doc->controllability;
      const bool unmet = !r.outcome.met;
      const bool again = unmet && !r.outcome.conflict.empty() && r.outcome.plan;
      std::optional<PlanCut> cut;
      std::string stop = "the plan is dynamically but not strongly controllable: no conflict to cut";
      if (again) {
        conflicts_.push_back(c.value("conflict", Json::array()));
        for (const auto& rx : c.value("relaxations", Json::array())) candidates_.push_back(rx);
        // A risk bound accepts plans by their times, which a cut does not restate: no search.
        if (s_.o.risk_bound) stop = "a risk bound was given";
        else if (cuts >= s_.o.max_plan_cuts) stop = "the search may cut " + std::to_string(cuts) + " plans";
        else if (Left() <= 0) stop = "time";
        else cut = flexible::CutFromConflict(*r.outcome.plan, plan_, r.outcome.conflict, &stop);
        if (cut && !flexible::CutMatches(*cut, plan_, s_.sp)) {
          cut.reset();
          stop = "its cut does not hold the plan it came from";
        }
      }
      if (!cut) {
        if (unmet && cuts > 0 && first_) return Fallback(cuts, stop);
        if (cuts > 0 || unmet) {
          Json search = {{"plans_cut", cuts}, {"ms", MsSince(t0_)}};
          if (unmet) search["stopped"] = stop;
          c["search"] = std::move(search);
        }
        if (s_.o.plan_out) *s_.o.plan_out = std::move(plan_);
        return std::move(r.answer);
      }
      if (cuts == 0) first_ = Kept{*doc, plan_};
      current_.cuts.push_back(std::move(*cut));
    }
  }

 private:
  static constexpr long kQuickMs = 1000;

  long Left() const { return s_.o.time_limit_ms - MsSince(t0_); }

  Round Solve(bool quick_first) {
    SolveOptions o = s_.o;
    o.plan_out = &plan_;
    o.time_limit_ms = std::max(1L, Left());
    if (quick_first) o.on_progress = nullptr;  // the plans of a cut search are not the answer's
    if (quick_first && o.time_limit_ms > 2 * kQuickMs) {
      SolveOptions quick = o;
      quick.time_limit_ms = kQuickMs;
      Round r = Check(s_.fixed(s_.d, current_, quick), quick);
      const SolveResult* doc = std::get_if<SolveResult>(&r.answer);
      if (!doc || Proven(doc->status) || (r.checked && !r.outcome.met)) return r;
      o.time_limit_ms = std::max(1L, Left());
    }
    return Check(s_.fixed(s_.d, current_, o), o);
  }

  Round Check(std::variant<SolveResult, Error> answer, const SolveOptions& o) {
    Round r{std::move(answer), {}, false};
    SolveResult* doc = std::get_if<SolveResult>(&r.answer);
    if (!doc || !doc->verified() || !o.derive_network) return r;
    r.outcome = AddFlexibility(*doc, plan_, s_.d, s_.sp, o);
    r.checked = true;
    return r;
  }

  // No plan (or no network asked for): after cuts, infeasible means none of the asked kind.
  std::variant<SolveResult, Error> Unplanned(std::variant<SolveResult, Error> answer, int cuts) {
    SolveResult& doc = std::get<SolveResult>(answer);
    const bool verified = doc.verified();
    if (cuts > 0 && doc.status == Termination::kInfeasible) {
      NothingLeft(doc, s_, conflicts_, candidates_, cuts, t0_);
    } else if (cuts > 0 && first_) {
      return Fallback(cuts, "time");
    }
    if (verified && s_.o.plan_out) *s_.o.plan_out = std::move(plan_);
    return answer;
  }

  // The search ended without a plan of the asked kind and without a proof that none exists: the
  // answer is the best plan found (the first), unknown, with what the search did.
  std::variant<SolveResult, Error> Fallback(int cuts, const std::string& stop) {
    SolveResult doc = std::move(first_->answer);
    if (!doc.controllability) doc.controllability = Json::object();
    Json& c = *doc.controllability;
    c["search"] = {{"plans_cut", cuts}, {"ms", MsSince(t0_)}, {"stopped", stop}};
    c["conflicts"] = conflicts_;
    doc.message = (doc.message.empty() ? std::string("the plan found is not of the asked kind")
                                       : doc.message) +
                     "; the search among plans cut it and " + std::to_string(cuts - 1) +
                     " more that were not either, then stopped (" + stop + "): this is the first";
    if (s_.o.plan_out) *s_.o.plan_out = std::move(first_->plan);
    return doc;
  }

  struct Kept {
    SolveResult answer;
    Trajectory plan;
  };
  std::optional<Kept> first_;  // the first plan, not of the asked kind

  const Search& s_;
  const Clock::time_point t0_ = Clock::now();
  StatePlan current_;
  Trajectory plan_;
  Json conflicts_ = Json::array(), candidates_ = Json::array();
};

std::variant<SolveResult, Error> Run(const Search& s) { return Searcher(s).Run(); }

}  // namespace

std::variant<SolveResult, Error> SolveControllable(const Domain& d, const StatePlan& sp,
                                                   const SolveOptions& o, const FixedSolve& fixed) {
  return Run(Search{d, sp, o, fixed});
}

}  // namespace ctb::solve
