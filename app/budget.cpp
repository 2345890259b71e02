#include "app/budget.h"

#include <algorithm>

namespace ctb::app {

namespace {

Error Over(const std::string& pointer, const char* limit, long value, long actual,
           const std::string& what) {
  std::string msg = what + ": " + std::to_string(actual) + ", over the server's limit of " +
                    std::to_string(value) + " (" + limit + ")";
  return Error{ErrorCode::kTooLarge, "the model is larger than this server accepts: " + msg,
               {{pointer.empty() ? "/" : pointer, std::nullopt, msg}},
               Limit{limit, value, actual}};
}

// Every string (keys too) within the per-string and total limits; the first offender is named.
std::optional<Error> Strings(const Json& j, const ModelBudget& b, const std::string& ptr,
                             long& total) {
  auto one = [&](const std::string& s, const std::string& where) -> std::optional<Error> {
    const long n = static_cast<long>(s.size());
    if (n > b.max_string_bytes) return Over(where, "max_string_bytes", b.max_string_bytes, n, "string bytes");
    total += n;
    if (total > b.max_string_total)
      return Over(where, "max_string_total", b.max_string_total, total, "string bytes in the request so far");
    return std::nullopt;
  };
  if (j.is_string()) return one(j.get_ref<const std::string&>(), ptr);
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string child = ptr + "/" + PointerToken(it.key());
      if (auto e = one(it.key(), child)) return e;
      if (auto e = Strings(it.value(), b, child, total)) return e;
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i)
      if (auto e = Strings(j[i], b, ptr + "/" + std::to_string(i), total)) return e;
  }
  return std::nullopt;
}

}  // namespace

Json LimitJson(const Limit& l) {
  return {{"name", l.name}, {"value", l.value}, {"actual", l.actual}};
}

long StringBytes(const Json& j) {
  long n = 0;
  if (j.is_string()) return static_cast<long>(j.get_ref<const std::string&>().size());
  if (j.is_object())
    for (auto it = j.begin(); it != j.end(); ++it) n += static_cast<long>(it.key().size()) + StringBytes(it.value());
  else if (j.is_array())
    for (const auto& v : j) n += StringBytes(v);
  return n;
}

std::optional<Error> CheckActionModel(const Json& model, const ModelBudget& b,
                                      const std::string& pointer) {
  if (!model.is_object()) return std::nullopt;
  auto automata = model.find("automata");
  if (automata != model.end() && automata->is_array()) {
    const long k = static_cast<long>(automata->size());
    if (k > b.max_automata)
      return Over(pointer + "/automata", "max_automata", b.max_automata, k, "automata");
    long locations = 0, transitions = 0, largest = 0;
    for (long i = 0; i < k; ++i) {
      const Json& a = (*automata)[i];
      if (!a.is_object()) continue;
      const std::string at = pointer + "/automata/" + std::to_string(i);
      if (auto l = a.find("locations"); l != a.end() && l->is_array()) {
        const long n = static_cast<long>(l->size());
        if (n > b.max_locations_per_automaton)
          return Over(at + "/locations", "max_locations_per_automaton", b.max_locations_per_automaton, n,
                      "locations in one automaton");
        locations += n;
        largest = std::max(largest, n);
        if (locations > b.max_locations_total)
          return Over(at + "/locations", "max_locations_total", b.max_locations_total, locations,
                      "locations in all automata so far");
      }
      if (auto t = a.find("transitions"); t != a.end() && t->is_array()) {
        transitions += static_cast<long>(t->size());
        if (transitions > b.max_transitions)
          return Over(at + "/transitions", "max_transitions", b.max_transitions, transitions,
                      "transitions in all automata so far");
      }
    }
    // (K + 1)(L + 1)^2 < 65 * 257^2: no overflow in long with the limits above checked first.
    const long cells = (k + 1) * (largest + 1) * (largest + 1);
    if (cells > b.max_table_cells)
      return Over(pointer + "/automata", "max_table_cells", b.max_table_cells, cells,
                  "derived table cells, (automata + 1) x (largest automaton's locations + 1)^2");
  }
  long total = 0;
  return Strings(model, b, pointer, total);
}

std::optional<Error> CheckExpandedDomain(const Domain& d, const ModelBudget& b,
                                         const std::string& pointer) {
  const std::string at = pointer + "/automata";
  const char* after = " after expanding templates";
  const long k = static_cast<long>(d.automata.size());
  if (k > b.max_automata) return Over(at, "max_automata", b.max_automata, k, std::string("automata") + after);
  long locations = 0, transitions = 0, largest = 0;
  for (const auto& a : d.automata) {
    const long n = static_cast<long>(a.locations.size());
    if (n > b.max_locations_per_automaton)
      return Over(at, "max_locations_per_automaton", b.max_locations_per_automaton, n,
                  "locations in automaton '" + a.name + "'" + after);
    largest = std::max(largest, n);
    locations += n;
    transitions += static_cast<long>(a.transitions.size());
  }
  if (locations > b.max_locations_total)
    return Over(at, "max_locations_total", b.max_locations_total, locations, std::string("locations") + after);
  if (transitions > b.max_transitions)
    return Over(at, "max_transitions", b.max_transitions, transitions, std::string("transitions") + after);
  const long cells = (k + 1) * (largest + 1) * (largest + 1);
  if (cells > b.max_table_cells)
    return Over(at, "max_table_cells", b.max_table_cells, cells,
                std::string("derived table cells, (automata + 1) x (largest automaton's locations + 1)^2") + after);
  return std::nullopt;
}

std::optional<Error> CheckStatePlan(const Json& plan, const ModelBudget& b,
                                    const std::string& pointer, long string_total) {
  if (!plan.is_object()) return std::nullopt;
  if (auto c = plan.find("constraints"); c != plan.end() && c->is_object()) {
    long n = 0;
    // Action events (contract section 15) count like constraints: each one can add a model part.
    for (const char* kind : {"episodes", "temporal", "event", "actions", "sequence", "forbidden"}) {
      auto k = c->find(kind);
      if (k == c->end() || !(k->is_object() || k->is_array())) continue;
      n += static_cast<long>(k->size());
      if (std::string(kind) == "event")
        for (const auto& e : *k)
          if (e.is_array()) n += static_cast<long>(e.size());
      if (n > b.max_constraints)
        return Over(pointer + "/constraints/" + kind, "max_constraints", b.max_constraints, n,
                    "constraints (episodes, temporal, events and their endpoints, actions, "
                    "sequence and forbidden entries) so far");
    }
  }
  return Strings(plan, b, pointer, string_total);
}

}  // namespace ctb::app
