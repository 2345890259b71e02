// A JSON Schema (draft 2020-12) of the state plan of one domain, for structured output
// (`response_format: {"type": "json_schema", ...}`) and for `ctburton schema`. It says what
// JSON can say: the keys, their types, the automata of initial_state with their locations as
// enums, bounds as numbers in [0, 10^7], names as identifiers, endpoints of shared events. The
// expressions are strings; the checker still reads every answer.
#pragma once

#include "planner/model/domain.h"
#include "planner/model/json_io.h"
#include "translator/llm.h"

namespace ctb {

// The schema of a state plan for d. Deterministic (same domain, same bytes).
Json StatePlanSchema(const Domain& d);

// The response_format member sent to the endpoint for this setting; null for kNone.
Json ResponseFormatMember(ResponseFormat f, const Domain& d);

}  // namespace ctb
