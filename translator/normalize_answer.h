// Normalisations of a parsed LLM answer that need no judgement (docs/translator.md): wrappers
// and double-encoded JSON unwrapped, other logic operators read as the expression language's,
// numeric strings and durations with a unit read as seconds. Each change is a warning with the
// JSON pointer of the value it changed. What needs judgement is left for the checker and the
// repair loop.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/json_io.h"

namespace ctb {

// The state plan in an answer, normalised; notes receive one warning per change. Never throws.
Json NormalizeAnswer(Json answer, const Domain& d, std::vector<Diagnostic>& notes);

// A condition with `&&`, `∧`, `and`, `AND` read as `/\`, `||`, `∨`, `or`, `OR` as `\/`, `¬`,
// `!` and `NOT` as `not`, `≠` as `!=`. Words that are names in the domain are kept. `changes`
// receives a description of each kind of change ("'&&' read as '/\'").
std::string NormalizeOperators(const std::string& text, const Domain& d,
                               std::vector<std::string>& changes);

// Seconds in "30", "30 s", "90s", "1.5 h", "30 min", "2 hours", "500 ms"; nullopt for anything
// else (a bare "m" is ambiguous and not read).
std::optional<double> ParseDuration(const std::string& text);

}  // namespace ctb
