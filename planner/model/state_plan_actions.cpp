#include "planner/model/state_plan_actions.h"

#include <algorithm>
#include <cmath>
#include <queue>

namespace ctb {

const char* OccurrenceName(Occurrence o) {
  switch (o) {
    case Occurrence::kFirst: return "first";
    case Occurrence::kLast: return "last";
    case Occurrence::kEvery: return "every";
  }
  return "first";
}

bool ActionEvent::Names(int a, int transition) const {
  return a == automaton && std::find(transitions.begin(), transitions.end(), transition) != transitions.end();
}

std::vector<const SharedEvent*> StatePlan::AllSharedEvents() const {
  std::vector<const SharedEvent*> out;
  for (const auto& ev : events) out.push_back(&ev);
  for (const auto& ev : action_events) out.push_back(&ev);
  return out;
}

namespace actions {

namespace {

std::string DidYouMean(const std::string& word, const std::vector<std::string>& names) {
  std::string best = NearestName(word, names);
  return best.empty() ? "" : " (did you mean '" + best + "'?)";
}

std::vector<std::string> ActionNames(const StatePlan& sp) {
  std::vector<std::string> names;
  for (const auto& a : sp.actions) names.push_back(a.name);
  return names;
}

int FindAction(const StatePlan& sp, const std::string& name) {
  for (std::size_t i = 0; i < sp.actions.size(); ++i)
    if (sp.actions[i].name == name) return static_cast<int>(i);
  return -1;
}

// A location of automaton au, or -1 with an error at pointer.
int ReadLocation(const ObjectReader& r, const std::string& key, const Automaton& au,
                 Diagnostics& diags) {
  auto name = r.String(key, false);
  if (!name) return -1;
  int loc = au.LocationIndex(*name);
  if (loc < 0)
    diags.Error(r.Child(key), "unknown location '" + *name + "' of automaton '" + au.name + "'" +
                                  DidYouMean(*name, au.locations));
  return loc;
}

// Locations of au reachable from `start` over its transitions (guards ignored).
std::vector<bool> Reachable(const Automaton& au, int start) {
  std::vector<bool> seen(au.locations.size(), false);
  std::queue<int> todo;
  seen[start] = true;
  todo.push(start);
  while (!todo.empty()) {
    int l = todo.front();
    todo.pop();
    for (const auto& t : au.transitions)
      if (t.from == l && !seen[t.to]) {
        seen[t.to] = true;
        todo.push(t.to);
      }
  }
  return seen;
}

std::string Describe(const Automaton& au, const Transition& t) {
  std::string s = "'" + au.locations[t.from] + "' -> '" + au.locations[t.to] + "'";
  if (t.commanded && t.command > 0) s += " (" + au.commands[t.command - 1] + ")";
  return s;
}

// The transitions an action names: a command's, narrowed by from/to when given.
std::vector<int> Matching(const Automaton& au, int command, int from, int to) {
  std::vector<int> out;
  for (std::size_t k = 0; k < au.transitions.size(); ++k) {
    const Transition& t = au.transitions[k];
    if (command > 0 && !(t.commanded && t.command == command)) continue;
    if (from >= 0 && t.from != from) continue;
    if (to >= 0 && t.to != to) continue;
    out.push_back(static_cast<int>(k));
  }
  return out;
}

std::optional<ActionEvent> ReadAction(const std::string& name, const Json& entry, const Domain& d,
                                      const std::vector<int>& initial, Diagnostics& diags) {
  ObjectReader r(entry, "/constraints/actions/" + PointerToken(name), diags);
  if (!r.valid()) return std::nullopt;
  r.CheckKeys({"automaton", "command", "from", "to", "occurrence"});
  ActionEvent act;
  act.name = name;
  act.pointer = r.pointer();
  auto automaton = r.String("automaton", true);
  if (!automaton) return std::nullopt;
  act.automaton = d.AutomatonIndex(*automaton);
  if (act.automaton < 0) {
    std::vector<std::string> names;
    for (const auto& a : d.automata) names.push_back(a.name);
    diags.Error(r.Child("automaton"), "unknown automaton '" + *automaton + "' in domain '" +
                                          d.name + "'" + DidYouMean(*automaton, names));
    return std::nullopt;
  }
  const Automaton& au = d.automata[act.automaton];
  bool ok = true;
  int command = -1;
  if (auto c = r.String("command", false)) {
    act.command = *c;
    command = au.CommandCode(*c);
    if (command < 0) {
      diags.Error(r.Child("command"),
                  "unknown command '" + *c + "' of automaton '" + au.name + "'" +
                      (au.commands.empty() ? " (it takes no commands)" : DidYouMean(*c, au.commands)));
      ok = false;
    }
  } else if (r.Has("command")) {
    ok = false;
  }
  const bool has_from = r.Has("from"), has_to = r.Has("to");
  int from = has_from ? ReadLocation(r, "from", au, diags) : -1;
  int to = has_to ? ReadLocation(r, "to", au, diags) : -1;
  if (from >= 0) act.from = au.locations[from];
  if (to >= 0) act.to = au.locations[to];
  if ((has_from && from < 0) || (has_to && to < 0)) ok = false;
  if (!r.Has("command") && !(has_from && has_to)) {
    diags.Error(act.pointer, "an action names its \"command\", or \"from\" and \"to\" (both)");
    return std::nullopt;
  }
  if (r.Has("occurrence")) {
    auto o = r.String("occurrence", false);
    if (o && *o == "first") act.occurrence = Occurrence::kFirst;
    else if (o && *o == "last") act.occurrence = Occurrence::kLast;
    else if (o && *o == "every") act.occurrence = Occurrence::kEvery;
    else {
      if (o) diags.Error(r.Child("occurrence"), "unknown occurrence '" + *o + "' (expected first, last or every)");
      ok = false;
    }
  }
  if (!ok) return std::nullopt;
  act.transitions = Matching(au, command > 0 ? command : 0, from, to);
  if (act.transitions.empty()) {
    std::string what = command > 0 ? "command '" + act.command + "' causes no transition of '" + au.name + "'"
                                   : "'" + au.name + "' has no transition";
    if (from >= 0) what += " from '" + au.locations[from] + "'";
    if (to >= 0) what += " to '" + au.locations[to] + "'";
    std::string known;
    for (const auto& t : au.transitions)
      if (command <= 0 || (t.commanded && t.command == command))
        known += (known.empty() ? "" : ", ") + Describe(au, t);
    diags.Error(act.pointer, what + (known.empty() ? "" : "; it has " + known));
    return std::nullopt;
  }
  const int start = act.automaton < static_cast<int>(initial.size()) ? initial[act.automaton] : -1;
  if (start >= 0) {
    auto seen = Reachable(au, start);
    bool any = false;
    for (int k : act.transitions) any = any || seen[au.transitions[k].from];
    if (!any)
      diags.Warning(act.pointer, "no run can take this action: '" + au.name + "' never reaches '" +
                                     au.locations[au.transitions[act.transitions[0]].from] +
                                     "' from '" + au.locations[start] + "'");
  }
  return act;
}

// An action name in a list (sequence, forbidden, an order's end); -1 with an error.
int ActionAt(const Json& v, const StatePlan& sp, const std::string& pointer, Diagnostics& diags) {
  if (!v.is_string()) {
    diags.Error(pointer, std::string("expected an action name, got ") + JsonTypeName(v));
    return -1;
  }
  const std::string name = v.get<std::string>();
  int i = FindAction(sp, name);
  if (i >= 0 && sp.actions[i].automaton < 0) return -1;  // reported where it is defined
  if (i < 0)
    diags.Error(pointer, "unknown action '" + name + "'" +
                             (sp.actions.empty() ? " (constraints.actions names none)"
                                                 : DidYouMean(name, ActionNames(sp))));
  return i;
}

// An order's bounds: lower_bound defaults to 0, upper_bound to none (null or absent).
bool ReadOrderBounds(const ObjectReader& r, const Domain& d, Order& o, Diagnostics& diags) {
  bool ok = true;
  auto check = [&](const char* key, double v) { ok = CheckBound(r, key, v, d, diags) && ok; };
  if (r.Has("lower_bound")) {
    auto lo = r.NonNegative("lower_bound", false);
    if (!lo) return false;
    o.lower = *lo;
    check("lower_bound", o.lower);
  }
  if (const Json* hi = r.Get("upper_bound"); hi && !hi->is_null()) {
    auto v = r.NonNegative("upper_bound", false);
    if (!v) return false;
    o.upper = *v;
    check("upper_bound", *v);
  }
  if (ok && o.upper && o.lower > *o.upper) {
    diags.Error(r.Child("lower_bound"), "lower_bound " + Json(o.lower).dump() +
                                            " is greater than upper_bound " + Json(*o.upper).dump());
    ok = false;
  }
  return ok;
}

// One end of an order: "eventN" (an action) or "accepting_eventN_constraint".
bool ReadEnd(const ObjectReader& r, int n, const StatePlan& sp, const ConditionReader& read,
             OrderEnd& end, Diagnostics& diags) {
  const std::string ev = "event" + std::to_string(n);
  const std::string cond = "accepting_event" + std::to_string(n) + "_constraint";
  const bool has_ev = r.Has(ev), has_cond = r.Has(cond);
  if (has_ev == has_cond) {
    diags.Error(r.pointer(), "give either \"" + ev + "\" (an action) or \"" + cond +
                                 "\" (a condition), " + (has_ev ? "not both" : "one of them"));
    return false;
  }
  if (has_ev) {
    end.action = ActionAt(*r.Get(ev), sp, r.Child(ev), diags);
    return end.action >= 0;
  }
  auto c = read(r, cond);
  if (!c) return false;
  end.condition = std::move(*c);
  return true;
}

}  // namespace

bool CheckBound(const ObjectReader& reader, const std::string& key, double v, const Domain& d,
                Diagnostics& diags) {
  constexpr double kMaxBound = 1e7;
  if (v > kMaxBound) {
    diags.Error(reader.Child(key), "bound beyond 10,000,000 seconds");
    return false;
  }
  const double q = v / d.time_resolution;
  if (std::fabs(q - std::round(q)) > 1e-9 * std::max(1.0, q)) {
    diags.Error(reader.Child(key), "bound is not a multiple of the domain's time resolution (" +
                                       Json(d.time_resolution).dump() + " s)");
    return false;
  }
  return true;
}

bool IsOrderEntry(const Json& entry) {
  if (!entry.is_object()) return false;
  if (entry.contains("event1") || entry.contains("event2")) return true;
  auto it = entry.find("ordered");
  return it != entry.end() && it->is_boolean() && it->get<bool>();
}

void ReadActions(const Json& group, const Domain& d, const std::vector<int>& initial, StatePlan& sp,
                 Diagnostics& diags) {
  if (!group.is_object()) {
    diags.Error("/constraints/actions", std::string("expected an object, got ") + JsonTypeName(group));
    return;
  }
  for (const auto& [name, entry] : group.items()) {
    if (!IsIdentifier(name)) {
      diags.Error("/constraints/actions/" + PointerToken(name),
                  "'" + name + "' is not a valid name (letters, digits and '_')");
      continue;
    }
    // An action that does not load stays as a name only (automaton -1), so that the orders that
    // name it are not reported again; the state plan does not load anyway.
    auto a = ReadAction(name, entry, d, initial, diags);
    if (!a) {
      a.emplace();
      a->name = name;
    }
    sp.actions.push_back(std::move(*a));
  }
}

void ReadOrder(const std::string& name, const Json& entry, const Domain& d, StatePlan& sp,
               const ConditionReader& read_condition, Diagnostics& diags) {
  ObjectReader r(entry, "/constraints/temporal/" + PointerToken(name), diags);
  if (!r.valid()) return;
  r.CheckKeys({"accepting_event1_constraint", "accepting_event2_constraint", "event1", "event2",
               "ordered", "lower_bound", "upper_bound"});
  Order o;
  o.name = name;
  o.pointer = r.pointer();
  auto ordered = r.Has("ordered") ? r.Bool("ordered", false) : std::optional<bool>(false);
  bool ok = ordered.has_value();
  o.ordered = ordered.value_or(false);
  ok = ReadEnd(r, 1, sp, read_condition, o.first, diags) && ok;
  ok = ReadEnd(r, 2, sp, read_condition, o.second, diags) && ok;
  ok = ReadOrderBounds(r, d, o, diags) && ok;
  if (!ok) return;
  auto every = [&](const OrderEnd& e) {
    return e.action >= 0 && sp.actions[e.action].occurrence == Occurrence::kEvery;
  };
  if (every(o.first)) {
    diags.Error(r.Child("event1"), "an action with occurrence 'every' can only be the later end "
                                   "(event2) of an ordered constraint, or forbidden");
    return;
  }
  if (every(o.second) && !o.ordered) {
    diags.Error(r.Child("event2"), "an action with occurrence 'every' needs \"ordered\": true "
                                   "(each occurrence after event1)");
    return;
  }
  sp.orders.push_back(std::move(o));
}

void ReadSequence(const Json& list, StatePlan& sp, Diagnostics& diags) {
  if (!list.is_array() || list.size() < 2) {
    diags.Error("/constraints/sequence", "expected an array of at least two action names");
    return;
  }
  std::vector<int> ids;
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string p = "/constraints/sequence/" + std::to_string(k);
    int i = ActionAt(list[k], sp, p, diags);
    if (i >= 0 && sp.actions[i].occurrence == Occurrence::kEvery) {
      diags.Error(p, "an action with occurrence 'every' cannot be a step of a sequence");
      i = -1;
    }
    ids.push_back(i);
  }
  for (int i : ids)
    if (i < 0) return;
  for (std::size_t k = 1; k < ids.size(); ++k)
    for (std::size_t m = 0; m < k; ++m)
      if (ids[m] == ids[k]) {
        diags.Error("/constraints/sequence/" + std::to_string(k),
                    "action '" + sp.actions[ids[k]].name + "' is already step " + std::to_string(m) +
                        ": one event cannot come after itself");
        return;
      }
  sp.sequence = ids;
  for (std::size_t k = 1; k < ids.size(); ++k) {
    Order o;
    o.first.action = ids[k - 1];
    o.second.action = ids[k];
    o.strict = true;
    o.pointer = "/constraints/sequence/" + std::to_string(k);
    sp.orders.push_back(std::move(o));
  }
}

void ReadForbidden(const Json& list, StatePlan& sp, Diagnostics& diags) {
  if (!list.is_array()) {
    diags.Error("/constraints/forbidden", std::string("expected an array of action names, got ") +
                                              JsonTypeName(list));
    return;
  }
  for (std::size_t k = 0; k < list.size(); ++k) {
    int i = ActionAt(list[k], sp, "/constraints/forbidden/" + std::to_string(k), diags);
    if (i >= 0) sp.forbidden.push_back(i);
  }
}

bool ResolveActionEndpoint(const std::string& text, const StatePlan& sp, const std::string& pointer,
                           Endpoint& out, Diagnostics& diags) {
  if (int a = FindAction(sp, text); a >= 0) {
    if (sp.actions[a].automaton < 0) {
      out = {EndpointKind::kAction, -1, text};
      return true;
    }
    if (sp.actions[a].occurrence == Occurrence::kEvery) {
      diags.Error(pointer, "action '" + text + "' happens at every occurrence, not at one event");
      out = {EndpointKind::kAction, -1, text};
      return true;
    }
    out = {EndpointKind::kAction, a, text};
    return true;
  }
  auto dot = text.rfind('.');
  if (dot == std::string::npos) return false;
  const std::string owner = text.substr(0, dot), part = text.substr(dot + 1);
  if (part != "event1" && part != "event2") return false;
  for (std::size_t q = 0; q < sp.orders.size(); ++q) {
    const Order& o = sp.orders[q];
    if (o.name.empty() || o.name != owner) continue;
    const OrderEnd& end = part == "event1" ? o.first : o.second;
    if (end.action >= 0 && sp.actions[end.action].occurrence == Occurrence::kEvery) {
      diags.Error(pointer, "'" + text + "' is every occurrence of an action, not one event");
      out = {EndpointKind::kOrder2, -1, text};
      return true;
    }
    out = {part == "event1" ? EndpointKind::kOrder1 : EndpointKind::kOrder2, static_cast<int>(q), text};
    return true;
  }
  return false;
}

void ActionsToJson(const StatePlan& sp, const Domain& d, Json& constraints) {
  if (!sp.actions.empty()) {
    Json acts = Json::object();
    for (const auto& a : sp.actions) {
      const Automaton& au = d.automata[a.automaton];
      Json j = {{"automaton", au.name}};
      if (!a.command.empty()) j["command"] = a.command;
      if (!a.from.empty()) j["from"] = a.from;
      if (!a.to.empty()) j["to"] = a.to;
      if (a.occurrence != Occurrence::kFirst) j["occurrence"] = OccurrenceName(a.occurrence);
      acts[a.name] = j;
    }
    constraints["actions"] = acts;
  }
  for (const auto& o : sp.orders) {
    if (o.name.empty()) continue;
    Json j = Json::object();
    auto end = [&](const OrderEnd& e, int n) {
      if (e.action >= 0) j["event" + std::to_string(n)] = sp.actions[e.action].name;
      else j["accepting_event" + std::to_string(n) + "_constraint"] = e.condition.text;
    };
    end(o.first, 1);
    end(o.second, 2);
    if (o.ordered) j["ordered"] = true;
    j["lower_bound"] = o.lower;
    j["upper_bound"] = o.upper ? Json(*o.upper) : Json(nullptr);
    constraints["temporal"][o.name] = j;
  }
  auto names = [&](const std::vector<int>& ids) {
    Json list = Json::array();
    for (int i : ids) list.push_back(sp.actions[i].name);
    return list;
  };
  if (!sp.sequence.empty()) constraints["sequence"] = names(sp.sequence);
  if (!sp.forbidden.empty()) constraints["forbidden"] = names(sp.forbidden);
}

}  // namespace actions
}  // namespace ctb
