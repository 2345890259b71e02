// Solving one model with z3: build the terms, find plans by satisfiability with a tightening
// bound, hand a stalled search to z3's optimizer, until the time limit or cancellation interrupts
// the context.
#include "planner/model/elapsed.h"
#include "planner/smt/z3_engine.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "planner/smt/z3_model.h"
#include "planner/smt/z3_watchdog.h"

namespace ctb::smt {

namespace {

using Clock = std::chrono::steady_clock;

long Value(const z3::model& mod, const z3::expr& v) {
  int64_t out = 0;
  mod.eval(v, true).is_numeral_i64(out);
  return static_cast<long>(out);
}

Json Row(const z3::model& mod, const Exprs& vars) {
  Json row = Json::array();
  for (const auto& v : vars) row.push_back(Value(mod, v));
  return row;
}

bool Holds(const z3::model& mod, const z3::expr& b) { return mod.eval(b, true).is_true(); }

// The index of the one-hot literal that holds (fallback when none does).
int OneHot(const z3::model& mod, const Exprs& xs, int none) {
  for (std::size_t i = 0; i < xs.size(); ++i)
    if (Holds(mod, xs[i])) return static_cast<int>(i);
  return none;
}

int OrderValue(const z3::model& mod, const OrderVar& v) {
  int n = 0;
  for (const auto& gt : v.gt) n += Holds(mod, gt) ? 1 : 0;
  return n;
}

Json Orders(const z3::model& mod, const std::vector<OrderVar>& vs) {
  Json row = Json::array();
  for (const auto& v : vs) row.push_back(OrderValue(mod, v));
  return row;
}

// L, U (one value per stage) or X (the global transition id per event, 0 for none).
Json Discrete(const Model& m, const z3::model& mod, const Exprs3& table, bool transitions) {
  Json rows = Json::array();
  for (std::size_t a = 0; a < table.size(); ++a) {
    Json row = Json::array();
    for (const auto& xs : table[a]) {
      int v = OneHot(mod, xs, -1);
      if (transitions) v = v < 0 ? 0 : m.info.transitions_of[a][v];
      row.push_back(v);
    }
    rows.push_back(row);
  }
  return rows;
}

// The solution in the shape of the MiniZinc model's JSON output (what ExtractTrajectory reads).
Json SolutionJson(const Model& m, const z3::model& mod) {
  Json n = Json::array();
  for (const auto& r : m.N) n.push_back(Row(mod, r));
  Json s = {{"e", Row(mod, m.e)},
            {"L", Discrete(m, mod, m.loc, false)},
            {"X", Discrete(m, mod, m.fire, true)},
            {"N", n},
            {"U", Discrete(m, mod, m.cmd, false)},
            {"g", OrderValue(mod, m.g)},
            {"cost", Value(mod, m.cost)},
            {"makespan", Value(mod, m.makespan)},
            {"objective", Value(mod, m.objective)},
            {"_objective", Value(mod, m.objective)}};  // as minizinc --output-objective
  if (!m.ep_s.empty()) {
    s["EP_S"] = Orders(mod, m.ep_s);
    s["EP_E"] = Orders(mod, m.ep_e);
  }
  if (!m.tc_1.empty()) {
    s["TC_1"] = Orders(mod, m.tc_1);
    s["TC_2"] = Orders(mod, m.tc_2);
  }
  return s;
}

bool Cancelled(const Z3Limits& limits) { return limits.cancel && limits.cancel->load(); }

unsigned TimeLeft(const Z3Limits& limits, Clock::time_point t0) {
  return static_cast<unsigned>(std::max(1L, limits.time_limit_ms - MsSince(t0)));
}

// True when every constraint holds in mod (a best-so-far model read after an interrupt is used
// only then).
bool Satisfies(const Model& m, const z3::model& mod) {
  for (unsigned i = 0; i < m.constraints.size(); ++i)
    if (!mod.eval(m.constraints[i], true).is_true()) return false;
  return true;
}

void Keep(const Model& m, const z3::model& mod, const Z3Limits& limits, Clock::time_point t0,
          Z3Result& r) {
  Json sol = SolutionJson(m, mod);
  if (r.best && (*r.best)["objective"].get<long>() <= sol["objective"].get<long>()) return;
  r.best = sol;
  if (r.solutions++ == 0) r.first_solution_ms = MsSince(t0);
  if (limits.on_solution) limits.on_solution(sol);
}

// After a plan: z3's optimizer on the model with "objective < best". It closed
// search_rescue 3 robots (makespan) in 12 to 45 s where repeated checks with a tightening bound
// gave no proof in 40 to 60 s (z3's times vary much from run to run). sat: its model is
// optimal; unsat: the first plan is. No intermediate plans are reported during this phase.
void Optimize(Model& m, const Z3Limits& limits, Clock::time_point t0, Z3Result& r) {
  z3::optimize o(m.z);
  for (unsigned i = 0; i < m.constraints.size(); ++i) o.add(m.constraints[i]);
  o.add(m.objective < m.Val((*r.best)["objective"].get<long>()));
  o.minimize(m.objective);
  z3::params p(m.z);
  p.set("timeout", TimeLeft(limits, t0));
  o.set(p);
  z3::check_result c = o.check();
  if (c != z3::unknown) {
    if (c == z3::sat) Keep(m, o.get_model(), limits, t0, r);
    r.status = Z3Result::Status::kOptimal;
    return;
  }
  try {  // the best plan found before the interrupt, if z3 has one and it is a plan
    z3::model mod = o.get_model();
    if (Satisfies(m, mod)) Keep(m, mod, limits, t0, r);
  } catch (const z3::exception&) {
  }
  r.status = Cancelled(limits) ? Z3Result::Status::kCancelled : Z3Result::Status::kFeasible;
}

// Plans by satisfiability with a tightening bound while each check is quick (every plan is
// reported at once; unsat after a plan is a proof); when a check stalls past the budget (a fifth
// of the time, at least a second), the optimizer takes over from the best plan.
void Search(Model& m, z3::solver& s, const Z3Limits& limits, Clock::time_point t0,
            Z3Result& r) {
  const Clock::time_point deadline = t0 + std::chrono::milliseconds(limits.time_limit_ms);
  Watchdog dog(m.z, deadline, limits.cancel);
  const long budget = std::max(1000L, (limits.time_limit_ms - MsSince(t0)) / 5);
  const Clock::time_point hand_over = Clock::now() + std::chrono::milliseconds(budget);
  while (!Cancelled(limits) && !dog.Fired()) {
    const bool loop = r.solutions == 0 || Clock::now() < hand_over;
    if (!loop) return Optimize(m, limits, t0, r);
    const long until_hand_over =
        std::chrono::duration_cast<std::chrono::milliseconds>(hand_over - Clock::now()).count();
    unsigned timeout = TimeLeft(limits, t0);
    if (r.solutions > 0) timeout = std::min<unsigned>(timeout, std::max(1L, until_hand_over));
    z3::params p(m.z);
    p.set("timeout", timeout);
    s.set(p);
    z3::check_result c = s.check();
    if (c == z3::unsat) {
      r.status = r.solutions > 0 ? Z3Result::Status::kOptimal : Z3Result::Status::kInfeasible;
      return;
    }
    if (c != z3::sat && r.solutions == 0) break;  // interrupted, or z3 gave up, before any plan
    if (c != z3::sat) continue;  // a stalled check: the optimizer next, unless interrupted
    Keep(m, s.get_model(), limits, t0, r);
    s.add(m.objective < m.Val((*r.best)["objective"].get<long>()));
  }
  if (Cancelled(limits))
    r.status = Z3Result::Status::kCancelled;
  else
    r.status = r.solutions > 0 ? Z3Result::Status::kFeasible : Z3Result::Status::kUnknown;
}

}  // namespace

Z3Result SolveWithZ3(const ModelSpec& spec, const Z3Limits& limits) {
  Z3Result r;
  const Clock::time_point t0 = Clock::now();
  if (!spec.d || !spec.sp || !spec.info) {
    r.error = "the z3 engine needs the problem, not only a model text";
    return r;
  }
  try {
    z3::context z;
    Model m(z, spec);
    AddAutomata(m);
    AddStatePlan(m);
    AddObjective(m);
    z3::solver s(z);
    s.add(m.constraints);
    r.build_ms = MsSince(t0);
    r.variables = m.declared;
    Search(m, s, limits, t0, r);
  } catch (const z3::exception& ex) {
    if (std::string(ex.msg()) == "canceled") {
      // Interrupted (a cancel, the deadline) outside a check: while a plan was kept or its bound
      // added. What was found stands, as after an interrupted check (found by the -j4 stress run:
      // a plan meeting the bound set the cancel, and the answer was an error instead of it).
      r.status = Cancelled(limits)  ? Z3Result::Status::kCancelled
                 : r.solutions > 0 ? Z3Result::Status::kFeasible
                                   : Z3Result::Status::kUnknown;
    } else {
      r = Z3Result{};
      r.error = std::string("z3 failed: ") + ex.msg();
    }
  } catch (const std::exception& ex) {
    r = Z3Result{};
    r.error = std::string("z3 engine failed: ") + ex.what();
  }
  r.elapsed_ms = MsSince(t0);
  return r;
}

}  // namespace ctb::smt
