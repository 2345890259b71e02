// Solving one model with z3: build the terms, then check, keep the model, demand a strictly
// better objective and check again until unsat (optimal) or the time limit / cancellation.
#include "planner/smt/z3_engine.h"

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "planner/smt/z3_model.h"

namespace ctb::smt {

namespace {

using Clock = std::chrono::steady_clock;

long MsSince(Clock::time_point t0) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count();
}

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

// Interrupts the context at the deadline or on cancellation, every 20 ms until stopped (an
// interrupt that arrives between two checks could otherwise be lost).
class Watchdog {
 public:
  Watchdog(z3::context& z, Clock::time_point deadline, const std::atomic<bool>* cancel)
      : z_(z), deadline_(deadline), cancel_(cancel), thread_([this] { Loop(); }) {}
  ~Watchdog() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  bool Fired() const { return fired_.load(); }

 private:
  void Loop() {
    std::unique_lock<std::mutex> lock(mu_);
    while (!stop_) {
      cv_.wait_for(lock, std::chrono::milliseconds(20));
      if (stop_) break;
      if (Clock::now() >= deadline_ || (cancel_ && cancel_->load())) {
        fired_ = true;
        z_.interrupt();
      }
    }
  }

  z3::context& z_;
  Clock::time_point deadline_;
  const std::atomic<bool>* cancel_;
  std::mutex mu_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::atomic<bool> fired_{false};
  std::thread thread_;
};

bool Cancelled(const Z3Limits& limits) { return limits.cancel && limits.cancel->load(); }

void Search(Model& m, z3::solver& s, const Z3Limits& limits, Clock::time_point t0,
            Z3Result& r) {
  const Clock::time_point deadline = t0 + std::chrono::milliseconds(limits.time_limit_ms);
  Watchdog dog(m.z, deadline, limits.cancel);
  while (true) {
    const long left = limits.time_limit_ms - MsSince(t0);
    if (left <= 0 || Cancelled(limits) || dog.Fired()) break;
    z3::params p(m.z);
    p.set("timeout", static_cast<unsigned>(left));
    s.set(p);
    z3::check_result c = s.check();
    if (c == z3::unsat) {
      r.status = r.solutions > 0 ? Z3Result::Status::kOptimal : Z3Result::Status::kInfeasible;
      return;
    }
    if (c != z3::sat) break;
    z3::model mod = s.get_model();
    Json sol = SolutionJson(m, mod);
    r.best = sol;
    if (r.solutions++ == 0) r.first_solution_ms = MsSince(t0);
    if (limits.on_solution) limits.on_solution(sol);
    s.add(m.objective < m.Val(sol["objective"].get<long>()));
  }
  if (Cancelled(limits)) r.status = Z3Result::Status::kCancelled;
  else r.status = r.solutions > 0 ? Z3Result::Status::kFeasible : Z3Result::Status::kUnknown;
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
    r = Z3Result{};
    r.error = std::string("z3 failed: ") + ex.msg();
  } catch (const std::exception& ex) {
    r = Z3Result{};
    r.error = std::string("z3 engine failed: ") + ex.what();
  }
  r.elapsed_ms = MsSince(t0);
  return r;
}

}  // namespace ctb::smt
