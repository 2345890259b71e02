#include "planner/model/state_plan.h"

#include <cmath>
#include <set>

#include "planner/model/state_plan_actions.h"

namespace ctb {

const char* ObjectiveName(Objective o) {
  switch (o) {
    case Objective::kCost: return "cost";
    case Objective::kMakespan: return "makespan";
    case Objective::kCostThenMakespan: return "cost_then_makespan";
  }
  return "cost";
}

std::optional<Objective> ParseObjective(const std::string& s) {
  if (s == "cost") return Objective::kCost;
  if (s == "makespan") return Objective::kMakespan;
  if (s == "cost_then_makespan") return Objective::kCostThenMakespan;
  return std::nullopt;
}

namespace {

std::optional<Condition> ReadCondition(const ObjectReader& r, const std::string& key,
                                       bool required, const char* default_text,
                                       const Scope& scope, Diagnostics& diags,
                                       const ValueNames& names) {
  auto text = r.String(key, required && !default_text);
  if (!text) {
    if (r.Has(key) || !default_text) return std::nullopt;
    text = default_text;
  }
  Condition c;
  c.text = *text;
  c.pointer = r.Child(key);
  ExprError err;
  auto e = Parse(c.text, err, scope.max_length);
  if (!e) {
    diags.Error(c.pointer, err.message, err.offset);
    return std::nullopt;
  }
  if (HasQuantifier(*e)) c.written = *e;
  if (!CheckExpr(*e, scope, ExprContext::kCondition, c.pointer, diags, &c.raw_info))
    return std::nullopt;
  c.raw = std::move(*e);
  c.expr = Normalize(c.raw, names);
  c.info = InfoOf(c.expr);
  c.info.domain_uses_i = c.raw_info.domain_uses_i;
  c.info.domain_uses_i1 = c.raw_info.domain_uses_i1;
  return c;
}

bool ReadBounds(const ObjectReader& r, const Domain& d, double& lower, double& upper,
                Diagnostics& diags) {
  auto lo = r.NonNegative("lower_bound", true);
  auto hi = r.NonNegative("upper_bound", true);
  if (!lo || !hi) return false;
  bool ok = true;
  for (auto [key, v] : {std::pair{"lower_bound", *lo}, std::pair{"upper_bound", *hi}})
    ok = actions::CheckBound(r, key, v, d, diags) && ok;
  if (ok && *lo > *hi) {
    diags.Error(r.Child("lower_bound"), "lower_bound " + Json(*lo).dump() +
                                            " is greater than upper_bound " + Json(*hi).dump());
    ok = false;
  }
  lower = *lo;
  upper = *hi;
  return ok;
}

// Collects the names of a constraints group first, so that every condition can refer to every
// accepting automaton whatever the order.
std::vector<std::string> GroupNames(const Json* group, const std::string& pointer,
                                    Diagnostics& diags) {
  std::vector<std::string> names;
  if (!group) return names;
  if (!group->is_object()) {
    diags.Error(pointer, std::string("expected an object, got ") + JsonTypeName(*group));
    return names;
  }
  for (const auto& [name, v] : group->items()) {
    if (!IsIdentifier(name)) {
      diags.Error(pointer + "/" + PointerToken(name),
                  "'" + name + "' is not a valid name (letters, digits and '_')");
      continue;
    }
    names.push_back(name);
  }
  return names;
}

}  // namespace

std::optional<StatePlan> LoadStatePlan(const Json& j, const Domain& d, Diagnostics& diags) {
  std::size_t errors_before = diags.errors().size();
  ObjectReader r(j, "", diags);
  if (!r.valid()) return std::nullopt;
  r.CheckKeys({"initial_state", "end_state", "constraints", "objective"});
  StatePlan sp;
  const DomainValueNames value_names(d);
  const ValueNames names = value_names.Function();

  // initial_state
  sp.initial.assign(d.automata.size(), -1);
  if (const Json* init = r.Get("initial_state")) {
    ObjectReader ir(*init, "/initial_state", diags);
    if (ir.valid()) {
      std::vector<std::string> automaton_names;
      for (const auto& a : d.automata) automaton_names.push_back(a.name);
      for (const auto& [name, v] : init->items()) {
        std::string p = ir.Child(name);
        int a = d.AutomatonIndex(name);
        if (a < 0) {
          std::string best = NearestName(name, automaton_names);
          diags.Error(p, "unknown automaton '" + name + "' in domain '" + d.name + "'" +
                             (best.empty() ? "" : " (did you mean '" + best + "'?)"));
          continue;
        }
        if (!v.is_string()) {
          diags.Error(p, std::string("expected a location name, got ") + JsonTypeName(v));
          continue;
        }
        int loc = d.automata[a].LocationIndex(v.get<std::string>());
        if (loc < 0) {
          std::string best = NearestName(v.get<std::string>(), d.automata[a].locations);
          diags.Error(p, "unknown location '" + v.get<std::string>() + "' of automaton '" + name +
                             "'" + (best.empty() ? "" : " (did you mean '" + best + "'?)"));
          continue;
        }
        sp.initial[a] = loc;
      }
      for (std::size_t a = 0; a < d.automata.size(); ++a)
        if (sp.initial[a] < 0 && !init->contains(d.automata[a].name))
          diags.Error("/initial_state", "missing initial location of automaton '" +
                                            d.automata[a].name + "'");
    }
  } else {
    diags.Error("/initial_state", "missing required field \"initial_state\"");
  }

  // Names of the accepting automata, for the scope of every condition.
  // Every condition's quantifiers share one node budget (quantify.h).
  QuantifierBudget budget;
  const auto automaton_index = AutomatonIndexOf(d);
  Scope scope{&d, {}, {}, kMaxExprLength, &budget, &automaton_index};
  std::vector<std::string> order_names;
  const Json* constraints = r.Get("constraints");
  std::optional<ObjectReader> cr;
  if (constraints) {
    cr.emplace(*constraints, "/constraints", diags);
    cr->CheckKeys({"episodes", "temporal", "event", "actions", "sequence", "forbidden"});
    scope.episodes = GroupNames(cr->Get("episodes"), "/constraints/episodes", diags);
    // Orders (contract section 15) are not accepting automata a condition can read.
    for (auto& name : GroupNames(cr->Get("temporal"), "/constraints/temporal", diags))
      (actions::IsOrderEntry((*cr->Get("temporal"))[name]) ? order_names : scope.temporals)
          .push_back(name);
    if (const Json* acts = cr->Get("actions")) actions::ReadActions(*acts, d, sp.initial, sp, diags);
  }

  // end_state
  if (const Json* end = r.Get("end_state")) {
    ObjectReader er(*end, "/end_state", diags);
    if (er.valid()) {
      er.CheckKeys({"maintenance_constraint", "goal_constraint"});
      if (auto c = ReadCondition(er, "maintenance_constraint", false, "true", scope, diags, names))
        sp.maintenance = std::move(*c);
      if (auto c = ReadCondition(er, "goal_constraint", true, nullptr, scope, diags, names))
        sp.goal = std::move(*c);
    }
  } else {
    diags.Error("/end_state", "missing required field \"end_state\"");
  }

  if (cr && cr->valid()) {
    if (const Json* eps = cr->Get("episodes"); eps && eps->is_object()) {
      for (const auto& name : scope.episodes) {
        ObjectReader er((*eps)[name], "/constraints/episodes/" + PointerToken(name), diags);
        if (!er.valid()) continue;
        er.CheckKeys({"accepting_constraint", "state_constraint", "lower_bound", "upper_bound"});
        Episode ep;
        ep.name = name;
        auto acc = ReadCondition(er, "accepting_constraint", true, nullptr, scope, diags, names);
        auto st = ReadCondition(er, "state_constraint", false, "true", scope, diags, names);
        bool bounds = ReadBounds(er, d, ep.lower, ep.upper, diags);
        if (!acc || !st || !bounds) continue;
        ep.accepting = std::move(*acc);
        ep.state = std::move(*st);
        sp.episodes.push_back(std::move(ep));
      }
    }
    if (const Json* tcs = cr->Get("temporal"); tcs && tcs->is_object()) {
      for (const auto& name : scope.temporals) {
        ObjectReader tr((*tcs)[name], "/constraints/temporal/" + PointerToken(name), diags);
        if (!tr.valid()) continue;
        tr.CheckKeys({"accepting_event1_constraint", "accepting_event2_constraint", "lower_bound",
                      "upper_bound", "ordered"});
        if (tr.Has("ordered")) tr.Bool("ordered", false);  // false here (true makes an order)
        Temporal tc;
        tc.name = name;
        auto e1 = ReadCondition(tr, "accepting_event1_constraint", true, nullptr, scope, diags, names);
        auto e2 = ReadCondition(tr, "accepting_event2_constraint", true, nullptr, scope, diags, names);
        bool bounds = ReadBounds(tr, d, tc.lower, tc.upper, diags);
        if (!e1 || !e2 || !bounds) continue;
        tc.event1 = std::move(*e1);
        tc.event2 = std::move(*e2);
        sp.temporals.push_back(std::move(tc));
      }
      for (const auto& name : order_names) {
        auto read = [&](const ObjectReader& rr, const std::string& key) {
          return ReadCondition(rr, key, true, nullptr, scope, diags, names);
        };
        actions::ReadOrder(name, (*tcs)[name], d, sp, read, diags);
      }
    }
    if (const Json* seq = cr->Get("sequence")) actions::ReadSequence(*seq, sp, diags);
    if (const Json* fb = cr->Get("forbidden")) actions::ReadForbidden(*fb, sp, diags);
    if (const Json* evs = cr->Get("event")) {
      if (!evs->is_object()) {
        diags.Error("/constraints/event", std::string("expected an object, got ") + JsonTypeName(*evs));
      } else {
        for (const auto& [name, list] : evs->items()) {
          std::string p = "/constraints/event/" + PointerToken(name);
          if (!list.is_array() || list.size() < 2) {
            diags.Error(p, "expected an array of at least two endpoints such as "
                           "\"ProjectorOn.end\"");
            continue;
          }
          SharedEvent ev;
          ev.name = name;
          bool ok = true;
          for (std::size_t k = 0; k < list.size(); ++k) {
            std::string ep = p + "/" + std::to_string(k);
            if (!list[k].is_string()) {
              diags.Error(ep, std::string("expected a string, got ") + JsonTypeName(list[k]));
              ok = false;
              continue;
            }
            std::string text = list[k].get<std::string>();
            auto dot = text.rfind('.');
            std::string owner = dot == std::string::npos ? text : text.substr(0, dot);
            std::string part = dot == std::string::npos ? "" : text.substr(dot + 1);
            auto find = [&](const std::vector<std::string>& v) {
              for (std::size_t x = 0; x < v.size(); ++x)
                if (v[x] == owner) return static_cast<int>(x);
              return -1;
            };
            int e = find(scope.episodes), t = find(scope.temporals);
            Endpoint endpoint{EndpointKind::kEpisodeStart, -1, text};
            if (actions::ResolveActionEndpoint(text, sp, ep, endpoint, diags)) {
              ok = ok && endpoint.index >= 0;
            } else if (e >= 0 && (part == "start" || part == "end")) {
              endpoint = {part == "start" ? EndpointKind::kEpisodeStart : EndpointKind::kEpisodeEnd,
                          e, text};
            } else if (t >= 0 && (part == "event1" || part == "event2")) {
              endpoint = {part == "event1" ? EndpointKind::kEvent1 : EndpointKind::kEvent2, t, text};
            } else {
              diags.Error(ep, "unknown endpoint '" + text + "': expected <episode>.start, "
                              "<episode>.end, <temporal>.event1, <temporal>.event2 or <action>");
              ok = false;
              continue;
            }
            ev.endpoints.push_back(endpoint);
          }
          bool actions = false;
          for (const auto& x : ev.endpoints)
            actions = actions || x.kind == EndpointKind::kAction || x.kind == EndpointKind::kOrder1 ||
                      x.kind == EndpointKind::kOrder2;
          if (ok) (actions ? sp.action_events : sp.events).push_back(std::move(ev));
        }
      }
    }
  }

  if (r.Has("objective")) {
    auto o = r.String("objective", false);
    if (o) {
      if (auto obj = ParseObjective(*o)) sp.objective = *obj;
      else diags.Error("/objective", "unknown objective '" + *o +
                                         "' (expected cost, makespan or cost_then_makespan)");
    }
  }
  if (diags.errors().size() > errors_before) return std::nullopt;
  return sp;
}

Json StatePlanToJson(const StatePlan& sp, const Domain& d) {
  Json init = Json::object();
  for (std::size_t a = 0; a < d.automata.size(); ++a)
    init[d.automata[a].name] = d.automata[a].locations[sp.initial[a]];
  Json eps = Json::object(), tcs = Json::object(), evs = Json::object();
  for (const auto& e : sp.episodes)
    eps[e.name] = {{"accepting_constraint", e.accepting.text}, {"state_constraint", e.state.text},
                   {"lower_bound", e.lower}, {"upper_bound", e.upper}};
  for (const auto& t : sp.temporals)
    tcs[t.name] = {{"accepting_event1_constraint", t.event1.text},
                   {"accepting_event2_constraint", t.event2.text},
                   {"lower_bound", t.lower}, {"upper_bound", t.upper}};
  for (const SharedEvent* ev : sp.AllSharedEvents()) {
    Json list = Json::array();
    for (const auto& p : ev->endpoints) list.push_back(p.text);
    evs[ev->name] = list;
  }
  Json constraints = {{"episodes", eps}, {"temporal", tcs}, {"event", evs}};
  actions::ActionsToJson(sp, d, constraints);
  return {{"initial_state", init},
          {"end_state", {{"maintenance_constraint", sp.maintenance.text},
                         {"goal_constraint", sp.goal.text}}},
          {"constraints", constraints},
          {"objective", ObjectiveName(sp.objective)}};
}

}  // namespace ctb
