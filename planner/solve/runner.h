// Runs `minizinc --solver gecode` on a model and a JSON data file as a child process.
//
// Contract: the child gets argv (no shell), its own temporary directory as cwd and TMPDIR,
// stdin from /dev/null; stdout (one JSON object per line, --json-stream) and stderr (bounded)
// are drained as they come; intermediate solutions reach the callback in order. At the time
// limit (plus a grace period for minizinc's own --time-limit to act) the child gets SIGTERM, then
// SIGKILL; any process still running in the job's directory (fzn-gecode) is killed too. The
// child is always reaped and the directory removed. Never throws; an unusable setup is a
// RunResult with status kError and a clean message. Thread-safe: each call is independent.
//
// A child that dies from a signal it was not sent by us (killed by an operator, the OOM killer,
// a crash) is kError with the signal named, and logged; never kUnknown. The child's address space
// is capped (RLIMIT_AS, inherited by the solver minizinc starts); running out of it is kError
// with out_of_memory set.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>

#include "planner/encode/encoder.h"
#include "planner/model/json_io.h"

namespace ctb {

struct RunRequest {
  std::string model;
  Json data;
  long time_limit_ms = 10000;
  std::string minizinc = "minizinc";  // executable (PATH lookup)
  std::string solver = "gecode";
  int threads = 1;
  // Called with the "json" output of every solution as it arrives (anytime use).
  std::function<void(const Json& solution)> on_solution;
  // Checked every 50 ms; when it becomes true the child is stopped as at the time limit.
  const std::atomic<bool>* cancel = nullptr;
  // Address-space ceiling of the child in MiB (0: none): SolveOptions::memory_limit_mb.
  long memory_limit_mb = 0;
  // The same model as data, for engines that build it from the checked trees (z3); MiniZinc
  // ignores it. Not owned; nullptr when the caller has only text.
  const ModelSpec* spec = nullptr;
};

struct RunResult {
  enum class Status { kOptimal, kFeasible, kInfeasible, kUnknown, kCancelled, kError };
  Status status = Status::kError;
  std::optional<Json> best;   // last solution's "json" output
  int solutions = 0;
  long elapsed_ms = 0;
  long first_solution_ms = -1;
  std::string error;          // clean, one line; never raw solver text
  std::string solver_stderr;  // bounded (16 KiB), for logs only
  Json statistics = Json::object();
  bool killed = false;        // the child had to be signalled
  int signal = 0;             // the signal that ended the child, when not one we sent
  bool out_of_memory = false; // the child hit its memory ceiling
  std::string engine;         // the backend's Name(), set by the portfolio
};

const char* RunStatusName(RunResult::Status s);

RunResult RunMiniZinc(const RunRequest& req);

// True when `minizinc --version` runs (for readiness checks).
bool MiniZincAvailable(const std::string& minizinc = "minizinc");

}  // namespace ctb
