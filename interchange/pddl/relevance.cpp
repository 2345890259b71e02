// Relevance (internal to ctb_pddl): the ground actions that can help reach a problem's goal,
// backwards from it. Thread-safe: calls share nothing.
#include <algorithm>
#include <map>
#include <set>

#include "interchange/pddl/internal/grounding.h"

namespace ctb::pddl {

namespace {

// What the goal and the relevant actions need of the variables: values, and variables any of
// whose values may matter (a value refused, a goal under a disjunction or a negation).
class Needs {
 public:
  bool Value(const VarKey& v, const std::string& value) {
    if (whole_.count(v)) return false;
    return values_[v].insert(value).second;
  }
  bool Whole(const VarKey& v) { return whole_.insert(v).second; }
  bool Matters(const VarKey& v, const std::string& value) const {
    if (whole_.count(v)) return true;
    auto it = values_.find(v);
    return it != values_.end() && it->second.count(value) > 0;
  }

 private:
  std::map<VarKey, std::set<std::string>> values_;
  std::set<VarKey> whole_;
};

// The goal's literals: a positive literal of a conjunction needs its value; anything else makes
// its variable matter as a whole (a refused value needs some other one; under a disjunction or a
// negation either value may be the one wanted).
void GoalNeeds(const Goal& goal, bool plain, const StateVars& sv, const Grounded& g, Needs& needs) {
  if (goal.kind == Goal::Kind::kLiteral) {
    auto loc = g.Locate(sv, goal.lit.atom);
    if (!loc) return;
    if (plain && goal.lit.positive) needs.Value(loc->first, loc->second);
    else needs.Whole(loc->first);
    return;
  }
  for (const auto& k : goal.kids) GoalNeeds(k, plain && goal.kind == Goal::Kind::kAnd, sv, g, needs);
}

// The action's conditions as needs; true when something new was needed.
bool ConditionNeeds(const GroundAction& ga, Needs& needs) {
  bool grew = false;
  for (const auto& u : ga.uses)
    for (int w = 0; w < 3; ++w) {
      if (u.need[w]) grew = needs.Value(u.var, *u.need[w]) || grew;
      if (!u.forbid[w].empty()) grew = needs.Whole(u.var) || grew;
    }
  return grew;
}

bool Helps(const GroundAction& ga, const Needs& needs) {
  for (const auto& u : ga.uses)
    for (const auto* e : {&u.eff_start, &u.eff_end})
      if (*e && needs.Matters(u.var, **e)) return true;
  return false;
}

}  // namespace

std::size_t DropIrrelevant(const StateVars& sv, const Goal& goal, Grounded& g) {
  Needs needs;
  GoalNeeds(goal, true, sv, g, needs);
  std::vector<char> relevant(g.actions.size(), 0);
  for (bool grew = true; grew;) {
    grew = false;
    for (std::size_t x = 0; x < g.actions.size(); ++x) {
      if (relevant[x] || !Helps(g.actions[x], needs)) continue;
      relevant[x] = 1;
      ConditionNeeds(g.actions[x], needs);
      grew = true;
    }
  }
  std::vector<GroundAction> kept;
  for (std::size_t x = 0; x < g.actions.size(); ++x)
    if (relevant[x]) kept.push_back(std::move(g.actions[x]));
  const std::size_t dropped = g.actions.size() - kept.size();
  g.actions = std::move(kept);
  return dropped;
}

}  // namespace ctb::pddl
