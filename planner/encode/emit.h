// Internal to the encoder: what the emitters (encode_*.cpp) share. Not a public header.
#pragma once

#include <string>

#include "planner/encode/encoder.h"

namespace ctb {
namespace encode {

struct Context {
  const Domain& d;
  const StatePlan& sp;
  const ProblemInfo& info;
  const EncodeOptions& opts;
  std::string& out;
  int H;
  // The first event the model's rules apply to: "0", or "P" after a fixed history.
  std::string K0() const { return opts.history ? "P" : "0"; }
};

// How the stage of a domain variable is chosen when printing a condition.
enum class CondMode {
  kEvent,  // at event k: [i] -> stage k-1, [i+1] -> stage k (change); both -> k (state)
  kStage,  // on stage k: [i] and [i+1] -> stage k
  kGuard,  // guard on stage k: [i] -> k
};

// Prints e for the comprehension variable `k`, following the contract's "when a condition
// holds" rules. For kEvent and a change condition the result is false at k = 0.
std::string PrintCondition(const Context& c, const Expr& e, const ExprInfo& info, CondMode mode);

void EmitHeader(const Context& c);
void EmitAutomata(const Context& c);
void EmitStatePlan(const Context& c);
// Symmetry breaking (encode_symmetry.cpp): nothing when there is no orbit or it does not apply.
void EmitSymmetry(const Context& c);
void EmitObjectiveAndSearch(const Context& c, Encoding& enc);
// Replanning (encode_history.cpp): the fixed history, keep "started", and its data.
void EmitHistory(const Context& c);
void AddHistoryData(const Context& c, Json& data);
// The search annotation of the model (encode_objective.cpp).
std::string TimeOrderSearch(const Context& c);
// Replanning, keep "min_change": the changes against the previous plan, minimised.
std::string MinChangeSolve(const Context& c);

}  // namespace encode
}  // namespace ctb
