// The model-size budget of one request, checked on the raw JSON before the loader, the checker,
// the encoder or the solver touch it, so an oversized model costs milliseconds, not gigabytes.
//
// What it bounds (each limit in ServerConfig, safe defaults here):
//  - automata, locations per automaton and in all, transitions;
//  - the encoder's derived tables: (automata + 1) x (largest automaton's locations + 1)^2 cells;
//  - episodes + temporal + event constraints (and event endpoints);
//  - every string (an expression or a name) and all strings together, which also bounds the
//    "did you mean" work of the checker (unknown names x candidates).
// Over budget: an Error with code kTooLarge (413) whose detail is the JSON pointer of the part that
// exceeds the limit, and whose `limit` holds the limit's name, value and the actual figure. Never
// throws; input of the wrong shape is left to the loader to report.
#pragma once

#include <optional>
#include <string>

#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/json_io.h"

namespace ctb::app {

struct ModelBudget {
  long max_automata = 64;
  long max_locations_per_automaton = 256;
  long max_locations_total = 2048;
  long max_transitions = 8192;
  long max_table_cells = 2000000;
  long max_constraints = 256;
  long max_string_bytes = 4096;
  long max_string_total = 65536;
};

// {"name", "value", "actual"}: how the HTTP and gRPC front ends show an Error's limit.
Json LimitJson(const Limit& l);

// `pointer` is where the JSON sits in the request ("/action_model", "/state_plan").
std::optional<Error> CheckActionModel(const Json& model, const ModelBudget& b,
                                      const std::string& pointer);
// The same limits on the model as loaded, templates expanded (a template's parameters can make a
// short document a large model); counts only, the strings were checked as written. The detail's
// pointer is `pointer`/automata; the message says "after expanding templates".
std::optional<Error> CheckExpandedDomain(const Domain& d, const ModelBudget& b,
                                         const std::string& pointer);
// `string_total` carries the string bytes already counted (the inline action model's) so the
// total bound covers both parts of one request.
std::optional<Error> CheckStatePlan(const Json& plan, const ModelBudget& b,
                                    const std::string& pointer, long string_total = 0);

// String bytes in a JSON value (keys and values), for the caller's running total.
long StringBytes(const Json& j);

}  // namespace ctb::app
