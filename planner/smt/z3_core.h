// Unsatisfiable cores with z3 (issue 20): which parts of a state plan cannot hold together.
//
// The model of one horizon (z3_engine.h) is built once with an assumption literal per
// switchable part; each part's constraints hold only under its literal (dropped as the
// explanation drops parts: planner/explain/explain.h). A check under a subset of the literals
// asks whether a plan with at most `horizon` events has those parts; z3 keeps what it learnt
// from one check to the next. An unsatisfiable check yields a core (the literals it used),
// which a deletion filter minimises: a part is left out for good when the rest is still
// unsatisfiable, and kept when the rest has a plan.
//
// Never throws; z3 failures are kError with a clean message. Thread-safe: each call has its own
// z3 context.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "planner/encode/encoder.h"
#include "planner/smt/z3_engine.h"

namespace ctb::smt {

// A part that may be left out. Parts not listed always hold.
struct CorePart {
  enum class Kind { kGoal, kMaintenance, kEpisode, kTemporal, kEvent };
  Kind kind = Kind::kGoal;
  int index = 0;  // into the state plan's episodes, temporals or events
};

struct CoreOptions {
  Z3Limits limits;  // on_solution is not used
  // All parts together are known to have no plan at this horizon (a solve's proof): the filter
  // starts from them without a check.
  bool known_infeasible = false;
  // Subsets (sorted indices) known to have a plan: no subset of one is checked.
  std::vector<std::vector<int>> feasible;
  // Tried on each subset (indices into the parts, sorted) before z3: a subset of it that is
  // known infeasible (static analysis), or nullopt. May be empty.
  std::function<std::optional<std::vector<int>>(const std::vector<int>& subset)> known_core;
};

struct CoreResult {
  // kInfeasible: `core` has no plan with at most horizon events; kFeasible: all parts together
  // have one (no core); kUnknown: the time limit or cancellation came first.
  enum class Status { kInfeasible, kFeasible, kUnknown, kError };
  Status status = Status::kError;
  std::vector<int> core;        // indices into the parts, sorted
  bool minimal = false;         // without any one part of `core`, a plan exists
  std::vector<int> consistent;  // the largest subset of the core shown to have a plan
  // Every subset shown to have a plan (sorted indices): no subset of one needs a check.
  std::vector<std::vector<int>> feasible;
  int checks = 0;  // z3 checks
  long elapsed_ms = 0;
  long build_ms = 0;
  std::string error;
};

// spec: the whole state plan at one horizon (spec.d, spec.sp, spec.info set; the objective is
// irrelevant). parts: the switchable parts.
CoreResult FindCoreWithZ3(const ModelSpec& spec, const std::vector<CorePart>& parts,
                          const CoreOptions& options);

}  // namespace ctb::smt
