// z3 as a second solving engine (issue 9): for one horizon, the model that Encode() prints as
// MiniZinc (planner/encode/encoder.h) is built as z3 terms straight from the checked syntax
// trees, and solved by satisfiability calls with a tightening bound, then z3's optimizer.
//
// Contract: the same EncodeOptions give the same set of solutions and the same objective as the
// MiniZinc model (docs/encoding.md, "A second engine: z3"); each solution is the JSON object the
// MiniZinc model outputs ("e", "L", "U", "X", "N", "g", "EP_S", "EP_E", "TC_1", "TC_2",
// "objective", "_objective"), so ExtractTrajectory and the portfolio read it unchanged. Never
// throws; z3 failures are kError with a clean message. Thread-safe: each call has its own z3
// context.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>

#include "planner/encode/encoder.h"
#include "planner/model/json_io.h"

namespace ctb::smt {

struct Z3Limits {
  long time_limit_ms = 10000;
  // Polled every 20 ms; when it becomes true the search is interrupted.
  const std::atomic<bool>* cancel = nullptr;
  // Called with each improving solution, in order, on the calling thread.
  std::function<void(const Json& solution)> on_solution;
};

struct Z3Result {
  enum class Status { kOptimal, kFeasible, kInfeasible, kUnknown, kCancelled, kError };
  Status status = Status::kError;
  std::optional<Json> best;   // the last (best) solution
  int solutions = 0;
  long elapsed_ms = 0;
  long first_solution_ms = -1;
  long build_ms = 0;          // building the terms
  long variables = 0;         // integer and Boolean constants declared
  std::string error;          // one clean line
};

// Solves the model described by spec (spec.d, spec.sp and spec.info must be set). kOptimal:
// the best solution is proven optimal among this model's solutions; kInfeasible: the model has
// none (with spec.opts.better_than: none better).
Z3Result SolveWithZ3(const ModelSpec& spec, const Z3Limits& limits);

}  // namespace ctb::smt
