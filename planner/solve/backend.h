// The solver-backend interface: what the planner's horizon growth, optimality closing, split and
// portfolio call to solve one model. The default runs `minizinc --solver gecode`
// (runner.h); tests substitute fakes to exercise the planner's logic fast, and a second engine
// can be added behind the same interface.
#pragma once

#include "planner/solve/runner.h"

namespace ctb {

class SolverBackend {
 public:
  virtual ~SolverBackend() = default;
  // A short name for statistics ("gecode").
  virtual const char* Name() const = 0;
  // Solves one model. Must be thread-safe (portfolio runs call it at once) and never throw;
  // honours req.time_limit_ms and req.cancel.
  virtual RunResult Run(const RunRequest& req) = 0;
};

// MiniZinc with Gecode as a child process (RunMiniZinc).
class MiniZincBackend : public SolverBackend {
 public:
  const char* Name() const override { return "gecode"; }
  RunResult Run(const RunRequest& req) override { return RunMiniZinc(req); }
};

// z3 in-process (planner/smt): builds the model from req.spec, which it needs (kError without);
// ignores req.model, req.data and the MiniZinc settings. Reports kOptimal only for a proof at
// the model's horizon, kInfeasible for unsat; no memory ceiling (req.memory_limit_mb is not
// applied: z3's limit is process-wide).
class Z3Backend : public SolverBackend {
 public:
  const char* Name() const override { return "z3"; }
  RunResult Run(const RunRequest& req) override;
};

// The process-wide MiniZinc backend.
SolverBackend& DefaultBackend();
// The process-wide z3 backend.
SolverBackend& Z3EngineBackend();

}  // namespace ctb
