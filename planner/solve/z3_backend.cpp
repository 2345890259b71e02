// The z3 engine behind the backend interface: RunRequest in, RunResult out.
#include "planner/smt/z3_engine.h"
#include "planner/solve/backend.h"

namespace ctb {

namespace {

RunResult::Status Convert(smt::Z3Result::Status s) {
  switch (s) {
    case smt::Z3Result::Status::kOptimal: return RunResult::Status::kOptimal;
    case smt::Z3Result::Status::kFeasible: return RunResult::Status::kFeasible;
    case smt::Z3Result::Status::kInfeasible: return RunResult::Status::kInfeasible;
    case smt::Z3Result::Status::kUnknown: return RunResult::Status::kUnknown;
    case smt::Z3Result::Status::kCancelled: return RunResult::Status::kCancelled;
    case smt::Z3Result::Status::kError: return RunResult::Status::kError;
  }
  return RunResult::Status::kError;
}

}  // namespace

RunResult Z3Backend::Run(const RunRequest& req) {
  RunResult r;
  r.engine = Name();
  if (!req.spec) {
    r.error = "the z3 engine needs the problem (RunRequest::spec)";
    return r;
  }
  smt::Z3Limits limits{std::max(1L, req.time_limit_ms), req.cancel, req.on_solution};
  smt::Z3Result z = smt::SolveWithZ3(*req.spec, limits);
  r.status = Convert(z.status);
  r.best = std::move(z.best);
  r.solutions = z.solutions;
  r.elapsed_ms = z.elapsed_ms;
  r.first_solution_ms = z.first_solution_ms;
  r.error = std::move(z.error);
  r.statistics = {{"z3BuildMs", z.build_ms}, {"z3Variables", z.variables}};
  return r;
}

SolverBackend& Z3EngineBackend() {
  static Z3Backend backend;
  return backend;
}

}  // namespace ctb
