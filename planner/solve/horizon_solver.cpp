#include "planner/solve/horizon_solver.h"

#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <future>

#include <spdlog/spdlog.h>

#include "planner/encode/encoder.h"
#include "planner/encode/extract.h"
#include "planner/solve/backend.h"
#include "planner/analyze/bounds.h"
#include "planner/solve/engines.h"
#include "planner/verify/verify.h"

namespace ctb::solve {

class Solver {
 public:
  Solver(const Domain& d, const StatePlan& sp, const SolveOptions& o,
         const std::optional<Plan>& incumbent = std::nullopt)
      : d_(d), sp_(sp), o_(o), info_(Analyze(d, sp)),
        objective_(o.objective.value_or(sp.objective)),
        bounds_(o.bounds ? *o.bounds : LowerBounds(d, sp, CostBoundsFor(objective_))),
        t0_(Clock::now()), best_(incumbent) {
    if (o.history) {  // replanning: the future starts at `now`; the history's cost is spent
      info_.time_offset = o.history->now;
      for (const auto& f : o.history->fired)
        history_cost_ += d.automata[f.automaton].transitions[f.transition].cost;
    }
    // Interchangeable automata, ordered in every Gecode model (never after a fixed history).
    if (o.symmetry && !o.history) info_.symmetries = FindSymmetries(d, sp);
    if (best_) {
      horizon_ = best_->traj.goal_event;
      found_by_ = {Method::kHeuristic, ""};
    }
  }

  // Proves that no plan strictly better than p exists with at most max_horizon events (over the
  // runs these options allow), or finds one.
  Refutation RefuteBetter(const Plan& p) {
    if (o_.horizon) return Outcome2Refutation(Attempt(*o_.horizon, p));
    Outcome r = Attempt(std::min(EventsForBetter(p), o_.max_horizon), p);
    return Outcome2Refutation(r);
  }

  Core Stats() const { return error_ ? Fail() : Finish(Termination::kUnknown); }

  Core Run() {
    // An incumbent that meets a bound every plan obeys is optimal at once.
    if (best_ && MeetsLowerBound(*best_)) return Proved(Termination::kOptimal, {Method::kLowerBound, ""});
    if (o_.horizon) {
      // With an incumbent, "infeasible" here means: nothing better at this horizon.
      auto r = Attempt(*o_.horizon, best_);
      if (error_) return Fail();
      if (best_ && MeetsLowerBound(*best_)) return Proved(Termination::kOptimal, {Method::kLowerBound, ""});
      if (r == Outcome::kOptimal || (r == Outcome::kInfeasible && best_))
        return Proved(Termination::kOptimal, ByEngine(decider_));
      if (r == Outcome::kInfeasible) return Proved(Termination::kInfeasible, ByEngine(decider_));
      return Finish(best_ ? Termination::kFeasible : Termination::kUnknown);
    }
    // Grow the horizon until a plan (better than the incumbent, if any) exists.
    int h = std::max(LowerBound(), std::min(o_.first_horizon, o_.max_horizon));
    Outcome r = Outcome::kInfeasible;
    while (h <= o_.max_horizon) {
      r = Attempt(h, best_);
      if (error_) return Fail();
      if (r != Outcome::kInfeasible) break;
      // A model with horizon h holds every plan with at most h events, so doubling loses
      // nothing; the last try is max_horizon itself, which proves infeasibility (or, with an
      // incumbent, that nothing better exists; for cost, a better plan has few events).
      if (h >= o_.max_horizon) break;
      if (best_ && h >= std::min(EventsForBetter(*best_), o_.max_horizon)) break;
      h = std::min(o_.max_horizon, std::max(h + 1, 2 * h));
    }
    if (!best_) {
      if (r == Outcome::kInfeasible) return Proved(Termination::kInfeasible, ByEngine(decider_));
      return Finish(Termination::kUnknown);
    }
    if (MeetsLowerBound(*best_)) return Proved(Termination::kOptimal, {Method::kLowerBound, ""});
    if (r == Outcome::kInfeasible) return Proved(Termination::kOptimal, ByEngine(decider_));  // the incumbent
    if (r != Outcome::kOptimal) return Finish(Termination::kFeasible);
    // A plan that meets a bound every plan obeys is optimal whatever the number of events.
    if (MeetsLowerBound(*best_)) return Proved(Termination::kOptimal, {Method::kLowerBound, ""});
    // Close optimality over every plan with at most max_horizon events. The horizon doubles on
    // the way: a better plan found at a smaller horizon (a smaller model) may meet the bound and
    // end the search. Invariant: no plan better than best_ has at most `closed` events.
    for (int closed = horizon_;;) {
      const int need = std::min(EventsForBetter(*best_), o_.max_horizon);
      if (need <= closed) return Proved(Termination::kOptimal, ByEngine(decider_));
      const int next = std::min(need, std::max(closed + 1, 2 * closed));
      r = Attempt(next, best_);
      if (error_) return Fail();
      if (MeetsLowerBound(*best_)) return Proved(Termination::kOptimal, {Method::kLowerBound, ""});
      if (r != Outcome::kOptimal && r != Outcome::kInfeasible) return Finish(Termination::kFeasible);
      closed = next;
    }
  }

 private:
  enum class Outcome { kOptimal, kFeasible, kInfeasible, kUnknown };

  Refutation Outcome2Refutation(Outcome r) const {
    if (error_) return Refutation::kUnknown;
    if (r == Outcome::kInfeasible) return Refutation::kRefuted;
    if (best_) return Refutation::kBetterExists;
    return Refutation::kUnknown;
  }

  SolverBackend& Backend() const { return o_.backend ? *o_.backend : DefaultBackend(); }

  // The first horizon: no plan has fewer events (analyze/bounds.h).
  int LowerBound() const { return static_cast<int>(std::min<long>(bounds_.events, o_.max_horizon)); }

  // The most events a strictly better plan can have: each event carries a transition of cost
  // >= min_cost. Without a positive min_cost, or for makespan, max_horizon.
  // With idle events (relaxed runs), a better plan may also have one idle event per episode or
  // temporal endpoint: other idle events can be dropped without changing what holds.
  int EventsForBetter(const Plan& than) const {
    if (objective_ == Objective::kMakespan || info_.min_cost <= 0) return o_.max_horizon;
    long budget = objective_ == Objective::kCost ? than.cost - 1 : than.cost;
    long events = (budget - history_cost_) / info_.min_cost;
    if (o_.history) events += o_.history->events();
    if (o_.idle_events) events += 2 * static_cast<long>(sp_.episodes.size() + sp_.temporals.size());
    return static_cast<int>(std::min<long>(o_.max_horizon, events));
  }

  // The bound a strictly better plan must beat, in the units of a model with horizon h.
  std::optional<long> BetterThan(int h, const std::optional<Plan>& than) const {
    if (!than) return std::nullopt;
    auto [cost_factor, makespan_factor] = ObjectiveFactors(objective_, info_.TimeBound(h));
    return than->cost * cost_factor + than->makespan * makespan_factor;
  }

  // The proven lower bound in the units of a model with horizon h. Under cost_then_makespan the
  // makespan part bounds only plans of the least cost (bounds.h): capped at the model's time
  // bound, a plan that costs more (objective >= (cost + 1) * (time bound + 1)) stays above it.
  long AtLeast(int h) const {
    const long time_bound = info_.TimeBound(h);
    auto [cost_factor, makespan_factor] = ObjectiveFactors(objective_, time_bound);
    return bounds_.cost * cost_factor + std::min(bounds_.makespan_ticks, time_bound) * makespan_factor;
  }

  // One member of the portfolio: an engine (engines.h) and its backend.
  struct Member {
    const Engine* engine;
    SolverBackend* backend;
  };

  // A search that names an engine: it alone; "portfolio" (and an engine that cannot take the
  // problem, engines.h Takes: z3 with a history or action rules): the first `portfolio` members
  // of the table that can.
  std::vector<Member> Members() const {
    SolverBackend& gecode = Backend();
    const Engine* alone = FindEngine(o_.search);
    const bool history = o_.history != nullptr, rules = sp_.HasActionRules();
    if (alone && Takes(*alone, history, rules)) return {{alone, &BackendOf(*alone, gecode)}};
    std::vector<Member> all;
    for (const auto& e : Engines())
      if (e.in_portfolio && Takes(e, history, rules)) all.push_back({&e, &BackendOf(e, gecode)});
    all.resize(std::min<std::size_t>(all.size(), std::max(1, o_.portfolio)));
    return all;
  }

  static bool Definitive(const RunResult& r) {
    return r.status == RunResult::Status::kOptimal || r.status == RunResult::Status::kInfeasible ||
           r.status == RunResult::Status::kError;
  }

  // Runs every strategy at horizon h at once; the first definitive answer (proof or error)
  // stops the others. Returns the runs in strategy order.
  std::vector<RunResult> RunPortfolio(int h, const std::optional<Plan>& better) {
    std::vector<Member> members = Members();
    std::vector<RunRequest> reqs(members.size());
    std::vector<ModelSpec> specs(members.size());
    std::atomic<bool> stop{false};
    long remaining = o_.time_limit_ms - MsSince(t0_);
    for (std::size_t i = 0; i < members.size(); ++i) {
      const bool own_model = !members[i].engine->reads_model_text;
      EncodeOptions eo;
      eo.horizon = h;
      eo.objective = objective_;
      eo.search = members[i].engine->model_strategy;
      eo.redundant = o_.redundant;
      eo.symmetry = o_.symmetry;
      eo.better_than = BetterThan(h, better);
      eo.at_least = AtLeast(h);
      eo.idle_events = o_.idle_events;
      eo.history = o_.history.get();
      if (i == 0 || !own_model) {  // z3 builds its own; the first text is kept for reports
        Encoding enc = Encode(d_, sp_, info_, eo);
        if (i == 0) {
          last_model_ = enc.model;
          last_data_ = enc.data;
          WriteModelOut();
        }
        if (!own_model) {
          reqs[i].model = std::move(enc.model);
          reqs[i].data = std::move(enc.data);
        }
      }
      specs[i] = ModelSpec{&d_, &sp_, &info_, eo};
      if (own_model) reqs[i].spec = &specs[i];
      reqs[i].time_limit_ms = remaining;
      reqs[i].minizinc = o_.minizinc;
      reqs[i].memory_limit_mb = o_.memory_limit_mb;
      reqs[i].threads = o_.threads;
      reqs[i].cancel = &stop;
      // A plan that meets the proven bound is optimal: stop every run at once (the verifier
      // still checks it in Attempt).
      reqs[i].on_solution = [&stop, at_least = AtLeast(h)](const Json& s) {
        auto it = s.find("_objective");
        if (it != s.end() && it->is_number_integer() && it->get<long>() <= at_least) stop = true;
      };
    }
    // The first strategy starts at once; the others only when it has not decided within
    // portfolio_delay_ms, so easy problems do not pay for a second flattening.
    std::vector<std::future<RunResult>> futures;
    std::vector<std::optional<RunResult>> done(reqs.size());
    std::size_t finished = 0;
    const auto started = Clock::now();
    auto launch = [&](std::size_t i) {
      futures.push_back(std::async(std::launch::async, [&members, &reqs, i] {
        RunResult r = members[i].backend->Run(reqs[i]);
        r.engine = members[i].backend->Name();
        return r;
      }));
    };
    launch(0);
    while (finished < futures.size() || futures.size() < reqs.size()) {
      if (futures.size() < reqs.size() && !stop &&
          std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - started).count() >=
              o_.portfolio_delay_ms) {
        reqs[futures.size()].time_limit_ms =
            std::max(1L, o_.time_limit_ms - MsSince(t0_));
        launch(futures.size());
      }
      for (std::size_t i = 0; i < futures.size(); ++i) {
        if (done[i] || futures[i].wait_for(std::chrono::milliseconds(10)) != std::future_status::ready)
          continue;
        done[i] = futures[i].get();
        ++finished;
        if (Definitive(*done[i])) stop = true;
      }
      if (o_.cancel && o_.cancel->load()) stop = true;
      if (stop && finished == futures.size()) break;
    }
    std::vector<RunResult> out;
    for (auto& r : done)
      if (r) out.push_back(std::move(*r));
    runs_ += static_cast<int>(out.size());
    return out;
  }

  Outcome Attempt(int h, const std::optional<Plan>& better) {
    if (o_.time_limit_ms - MsSince(t0_) <= 0) return Outcome::kUnknown;
    const long started = MsSince(t0_);
    std::vector<RunResult> runs = RunPortfolio(h, better);
    // Statistics from the first strategy's model (they all flatten the same constraints).
    const RunResult& r0 = runs[0];
    if (r0.statistics.contains("flatTime") && r0.statistics["flatTime"].is_number())
      compile_ms_ += std::lround(r0.statistics["flatTime"].get<double>() * 1000);
    if (r0.statistics.contains("flatIntVars") && r0.statistics["flatIntVars"].is_number())
      variables_ = r0.statistics["flatIntVars"].get<long>() + r0.statistics.value("flatBoolVars", 0L);
    if (r0.statistics.contains("z3BuildMs")) {
      compile_ms_ += r0.statistics.value("z3BuildMs", 0L);
      variables_ = r0.statistics.value("z3Variables", 0L);
    }
    for (const auto& r : runs)
      if (first_solution_ms_ < 0 && r.first_solution_ms >= 0)
        first_solution_ms_ = started + r.first_solution_ms;
    if (o_.cancel && o_.cancel->load()) {
      error_ = Error{ErrorCode::kUnavailable, "solve cancelled", {}};
      return Outcome::kUnknown;
    }
    const RunResult* decided = nullptr;
    for (const auto& r : runs)
      if (Definitive(r) && !decided) decided = &r;
    if (decided && decided->status == RunResult::Status::kError) {
      // The raw solver text goes to the log only, never to clients.
      spdlog::error("{}", Json(fmt::format("solver failure at horizon {}: {}; stderr: {}", h, decided->error,
                    decided->solver_stderr)).dump(-1, ' ', false, Json::error_handler_t::replace));
      // A solver that hit its memory ceiling is the service's limit, not a bug: 503, retry
      // later or with a smaller problem.
      error_ = decided->out_of_memory
                   ? Error{ErrorCode::kUnavailable,
                           "the solver ran out of memory at horizon " + std::to_string(h) +
                               " (its memory ceiling); try a smaller max_horizon or problem",
                           {}}
                   : Error{ErrorCode::kInternal, "solver failure: " + decided->error, {}};
      return Outcome::kUnknown;
    }
    // Keep the best verified solution of any run.
    for (const auto& r : runs) {
      if (!r.best) continue;
      std::string why;
      auto traj = ExtractTrajectory(*r.best, d_, sp_, h, why);
      if (!traj) {
        error_ = Error{ErrorCode::kInternal, "cannot read the solver's answer: " + why, {}};
        return Outcome::kUnknown;
      }
      traj->history = o_.history;
      auto problems = VerifyTrajectory(*traj, d_, sp_, info_.ticks_per_second, o_.idle_events);
      if (!problems.empty()) {
        std::string where = SaveFailedModel();
        spdlog::error("{}", Json(fmt::format("plan failed verification ({} problem(s), first: {}); model kept at {}",
                      problems.size(), problems[0], where)).dump());
        Error e{ErrorCode::kInternal,
                "internal error: the solver's plan failed independent verification (model "
                "kept at " + where + ")", {}};
        for (const auto& p : problems) e.details.push_back({"", std::nullopt, p});
        error_ = e;
        return Outcome::kUnknown;
      }
      Plan p{*traj, TrajectoryCost(*traj, d_), traj->events.back()};
      if (!best_ || Better(p, *best_)) {
        best_ = p;
        horizon_ = h;
        found_by_ = ByEngine(r.engine);
        if (!decided) AddEngine(engine_, r.engine);
        if (o_.on_progress)
          o_.on_progress({{objective_, p.cost, p.makespan, info_.ticks_per_second},
                          BoundValue(bounds_, objective_, info_.ticks_per_second), h, MsSince(t0_),
                          ByEngine(r.engine)});
      }
    }
    if (decided) {
      AddEngine(engine_, decided->engine);
      decider_ = decided->engine;
    }
    if (best_ && horizon_ == h && MeetsLowerBound(*best_)) return Outcome::kOptimal;
    if (decided) return decided->status == RunResult::Status::kOptimal ? Outcome::kOptimal
                                                                        : Outcome::kInfeasible;
    for (const auto& r : runs)
      if (r.status == RunResult::Status::kFeasible) return Outcome::kFeasible;
    return Outcome::kUnknown;
  }

  bool MeetsLowerBound(const Plan& p) const {
    return MeetsLowerBounds(bounds_, objective_, p.cost, p.makespan);
  }

  bool Better(const Plan& a, const Plan& b) const { return BetterPlan(objective_, a, b); }

  void WriteModelOut() const {
    if (o_.model_out.empty()) return;
    std::ofstream(o_.model_out) << last_model_;
    std::ofstream(o_.model_out + ".json") << last_data_.dump(1) << "\n";
  }

  // Keeps the model of a plan that failed verification, for the bug report: in a directory of
  // its own (mkdtemp: unpredictable, never shared between jobs), at most 4 MiB of model text.
  std::string SaveFailedModel() const {
    const char* base = std::getenv("TMPDIR");
    std::string templ = std::string(base && *base ? base : "/tmp") + "/ctburton-unverified-XXXXXX";
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    if (!mkdtemp(buf.data())) return "(not kept: cannot create a directory)";
    std::string dir(buf.data());
    constexpr std::size_t kMaxKept = 4u << 20;
    std::ofstream(dir + "/model.mzn") << last_model_.substr(0, kMaxKept);
    std::string data = last_data_.dump(-1, ' ', false, Json::error_handler_t::replace);
    std::ofstream(dir + "/model.json") << data.substr(0, kMaxKept) << "\n";
    return dir;
  }

  Core Finish(Termination status) const {
    Core c;
    c.status = status;
    c.best = best_;
    c.horizon = horizon_;
    c.runs = runs_;
    c.compile_ms = compile_ms_;
    c.variables = variables_;
    c.first_solution_ms = first_solution_ms_;
    c.engine = engine_;
    c.found_by = best_ ? found_by_ : Credit{};
    return c;
  }
  Core Proved(Termination status, Credit by) const {
    Core c = Finish(status);
    c.proved_by = by;
    return c;
  }
  Core Fail() const {
    Core c = Finish(Termination::kUnknown);
    c.error = error_;
    return c;
  }

  const Domain& d_;
  const StatePlan& sp_;
  const SolveOptions& o_;
  ProblemInfo info_;
  Objective objective_;
  ObjectiveBounds bounds_;
  Clock::time_point t0_;
  std::optional<Plan> best_;
  int horizon_ = 0;
  long history_cost_ = 0;
  std::optional<Error> error_;
  std::string last_model_;
  Json last_data_;
  int runs_ = 0;
  long compile_ms_ = 0;
  long variables_ = 0;
  long first_solution_ms_ = -1;
  std::string engine_;
  Credit found_by_;       // what found best_
  std::string decider_;   // the engine of the last definitive run
};

Core SolveOneModel(const Domain& d, const StatePlan& sp, const SolveOptions& o,
                   const std::optional<Plan>& incumbent) {
  return Solver(d, sp, o, incumbent).Run();
}

Refutation RefuteBetter(const Domain& d, const StatePlan& sp, const SolveOptions& o,
                        const Plan& than, Core& stats) {
  Solver s(d, sp, o);
  Refutation r = s.RefuteBetter(than);
  stats = s.Stats();
  return r;
}

void AddEngine(std::string& engines, const std::string& name) {
  if (name.empty()) return;
  std::size_t from = 0;
  while (from <= engines.size()) {
    std::size_t to = engines.find('+', from);
    if (to == std::string::npos) to = engines.size();
    if (engines.compare(from, to - from, name) == 0) return;
    from = to + 1;
  }
  engines += (engines.empty() ? "" : "+") + name;
}

bool BetterPlan(Objective objective, const Plan& a, const Plan& b) {
  switch (objective) {
    case Objective::kCost: return a.cost < b.cost;
    case Objective::kMakespan: return a.makespan < b.makespan;
    case Objective::kCostThenMakespan:
      return a.cost < b.cost || (a.cost == b.cost && a.makespan < b.makespan);
  }
  return false;
}

}  // namespace ctb::solve

namespace ctb {

SolverBackend& DefaultBackend() {
  static MiniZincBackend backend;
  return backend;
}

}  // namespace ctb
