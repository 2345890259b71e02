// Resolves the names of a parsed expression against a domain and the state plan's accepting
// automata, and enforces where each kind of index may appear.
#pragma once

#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "planner/model/domain.h"
#include "planner/expr/expr.h"
#include "planner/expr/expr_info.h"
#include "planner/expr/normalize.h"
#include "planner/expr/quantify.h"

namespace ctb {

// Names visible to an expression.
struct Scope {
  const Domain* domain = nullptr;
  std::vector<std::string> episodes;   // epAcceptAutomatonTraj_<name>
  std::vector<std::string> temporals;  // temporalAcceptConstraint_Traj_<name>
  // The longest text ParseChecked accepts (guards a template expanded may be longer than what
  // a user may write; their expansion has its own bound, templates.h).
  std::size_t max_length = kMaxExprLength;
  // The node budget the quantifiers of the whole document share (quantify.h); when null, each
  // expression has a budget of its own.
  QuantifierBudget* budget = nullptr;
  // The domain's automata by name (AutomatonIndex is a linear scan: with 1,000 automata, checking
  // their guards took most of a domain's loading); optional, must match `domain` when given.
  const std::unordered_map<std::string, int>* automaton_index = nullptr;
};

// The automata of d by name, for Scope::automaton_index.
std::unordered_map<std::string, int> AutomatonIndexOf(const Domain& d);

enum class ExprContext {
  kGuard,      // a transition guard: only [i], only domain variables
  kCondition,  // a state-plan condition: [i], [i+1], fixed stages (with a warning)
};

// Checks e in place (filling var_kind, target, value_code), after expanding its quantifiers over
// the domain's templates (Domain::templates) and integer ranges. Errors and warnings go to diags
// at `pointer` with the character offset of the offending token (in a quantifier's body, the
// message names the variables' values; one error per place in the text). Returns true when e is
// valid; e then holds no quantifier.
bool CheckExpr(Expr& e, const Scope& scope, ExprContext ctx, const std::string& pointer,
               Diagnostics& diags, ExprInfo* info = nullptr);

// Parse + CheckExpr. A parse error is reported at pointer with its offset.
std::optional<Expr> ParseChecked(const std::string& text, const Scope& scope, ExprContext ctx,
                                 const std::string& pointer, Diagnostics& diags,
                                 ExprInfo* info = nullptr);

// The names of accepting-automaton states in the order of their codes.
const std::vector<std::string>& EpisodeStateNames();   // epWaiting, epActive, epAccepted, epFailed
const std::vector<std::string>& TemporalStateNames();  // tempWaiting, ...
extern const char* const kEpisodeVarPrefix;            // "epAcceptAutomatonTraj_"
extern const char* const kTemporalVarPrefix;           // "temporalAcceptConstraint_Traj_"

// The value names of every variable of a domain and a state plan's accepting automata, for
// Normalize. Holds its own tables; keep it alive while the returned function is used.
class DomainValueNames {
 public:
  explicit DomainValueNames(const Domain& d);
  ValueNames Function() const;

 private:
  const Domain& d_;
  std::vector<std::vector<std::string>> commands_;  // "(no command)" at code 0
};

// The candidate closest to `word` by edit distance, or "" when none is close enough.
std::string NearestName(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace ctb
