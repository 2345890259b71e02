#include "translator/schema.h"

#include <set>

namespace ctb {

namespace {

const char* kIdentifier = "^[A-Za-z_][A-Za-z0-9_]*$";

Json Condition(const char* what) {
  return {{"type", "string"}, {"minLength", 1}, {"description", what}};
}

Json Bound() { return {{"type", "number"}, {"minimum", 0}, {"maximum", 10000000}}; }

Json Named(Json item) {
  return {{"type", "object"},
          {"propertyNames", {{"pattern", kIdentifier}}},
          {"additionalProperties", std::move(item)}};
}

}  // namespace

Json StatePlanSchema(const Domain& d) {
  Json initial_props = Json::object();
  Json automata = Json::array();
  for (const auto& a : d.automata) {
    initial_props[a.name] = {{"type", "string"}, {"enum", a.locations}};
    automata.push_back(a.name);
  }
  Json initial = {{"type", "object"},
                  {"description", "the location of every automaton at the start"},
                  {"properties", initial_props},
                  {"required", automata},
                  {"additionalProperties", false}};
  Json end = {
      {"type", "object"},
      {"properties",
       {{"maintenance_constraint", Condition("holds on every stage until the goal is reached")},
        {"goal_constraint", Condition("the goal")}}},
      {"required", {"goal_constraint"}},
      {"additionalProperties", false}};
  Json episode = {
      {"type", "object"},
      {"properties",
       {{"accepting_constraint", Condition("the episode starts when this first holds")},
        {"state_constraint", Condition("holds during the whole episode")},
        {"lower_bound", Bound()},
        {"upper_bound", Bound()}}},
      {"required", {"accepting_constraint", "state_constraint", "lower_bound", "upper_bound"}},
      {"additionalProperties", false}};
  // A temporal constraint: two conditions in either order (the thesis'), or an order (contract
  // section 15) naming actions as its events and/or "ordered": true.
  Json action_name = {{"type", "string"}, {"pattern", kIdentifier}, {"description", "an action of constraints.actions"}};
  Json temporal = {
      {"type", "object"},
      {"properties",
       {{"accepting_event1_constraint", Condition("the first event")},
        {"accepting_event2_constraint", Condition("the second event")},
        {"event1", action_name},
        {"event2", action_name},
        {"ordered", {{"type", "boolean"}, {"description", "event1 no later than event2"}}},
        {"lower_bound", Bound()},
        {"upper_bound", {{"anyOf", {Bound(), {{"type", "null"}}}}}}}},
      {"anyOf",
       {{{"required", {"accepting_event1_constraint", "accepting_event2_constraint", "lower_bound",
                       "upper_bound"}}},
        {{"required", {"event1"}}},
        {{"required", {"event2"}}},
        {{"required", {"ordered"}}, {"properties", {{"ordered", {{"const", true}}}}}}}},
      {"additionalProperties", false}};
  Json endpoint = {{"type", "string"},
                   {"pattern", "^[A-Za-z_][A-Za-z0-9_]*(\\.(start|end|event1|event2))?$"}};
  std::set<std::string> commands, locations;
  for (const auto& a : d.automata) {
    commands.insert(a.commands.begin(), a.commands.end());
    locations.insert(a.locations.begin(), a.locations.end());
  }
  Json action = {
      {"type", "object"},
      {"description", "the event at which a transition of one automaton fires"},
      {"properties",
       {{"automaton", {{"type", "string"}, {"enum", automata}}},
        {"command", {{"type", "string"}, {"enum", commands}}},
        {"from", {{"type", "string"}, {"enum", locations}}},
        {"to", {{"type", "string"}, {"enum", locations}}},
        {"occurrence", {{"type", "string"}, {"enum", {"first", "last", "every"}}}}}},
      {"required", {"automaton"}},
      {"anyOf", {{{"required", {"command"}}}, {{"required", {"from", "to"}}}}},
      {"additionalProperties", false}};
  Json names = {{"type", "array"}, {"items", action_name}};
  Json sequence = names;
  sequence["minItems"] = 2;
  Json constraints = {
      {"type", "object"},
      {"properties",
       {{"episodes", Named(episode)},
        {"temporal", Named(temporal)},
        {"event", Named({{"type", "array"}, {"minItems", 2}, {"items", endpoint}})},
        {"actions", Named(action)},
        {"sequence", sequence},
        {"forbidden", names}}},
      {"additionalProperties", false}};
  return {
      {"$schema", "https://json-schema.org/draft/2020-12/schema"},
      {"title", "state plan for domain " + d.name},
      {"type", "object"},
      {"properties",
       {{"initial_state", initial},
        {"end_state", end},
        {"constraints", constraints},
        {"objective", {{"type", "string"}, {"enum", {"cost", "makespan", "cost_then_makespan"}}}}}},
      {"required", {"initial_state", "end_state"}},
      {"additionalProperties", false}};
}

Json ResponseFormatMember(ResponseFormat f, const Domain& d) {
  switch (f) {
    case ResponseFormat::kNone:
      return nullptr;
    case ResponseFormat::kJsonObject:
      return {{"type", "json_object"}};
    case ResponseFormat::kJsonSchema:
      return {{"type", "json_schema"},
              {"json_schema",
               {{"name", "state_plan"}, {"strict", false}, {"schema", StatePlanSchema(d)}}}};
  }
  return nullptr;
}

}  // namespace ctb
