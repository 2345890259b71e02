#include "translator/guards.h"

#include <cctype>
#include <regex>
#include <set>

#include "planner/expr/expr.h"
#include "planner/expr/expr_print.h"
#include "planner/expr/normalize.h"
#include "translator/text.h"

namespace ctb {

std::vector<std::string> StatedDurations(const std::string& command) {
  static const std::regex kDuration(
      R"((\d+(?:\.\d+)?)\s*(milliseconds?|ms|seconds?|secs?|s|minutes?|mins?|hours?|hrs?|h)\b)",
      std::regex::icase);
  std::vector<std::string> out;
  for (std::sregex_iterator it(command.begin(), command.end(), kDuration), end; it != end; ++it)
    out.push_back(it->str());
  return out;
}

std::vector<Diagnostic> DefaultedStateConstraints(const Json& plan) {
  std::vector<Diagnostic> out;
  if (!plan.is_object() || !plan.contains("constraints") || !plan["constraints"].is_object())
    return out;
  const Json& c = plan["constraints"];
  if (!c.contains("episodes") || !c["episodes"].is_object()) return out;
  for (auto it = c["episodes"].begin(); it != c["episodes"].end(); ++it) {
    if (!it.value().is_object() || it.value().contains("state_constraint")) continue;
    out.push_back({"/constraints/episodes/" + PointerToken(it.key()) + "/state_constraint",
                   std::nullopt,
                   "missing: it defaults to \"true\", so nothing has to hold during the episode; "
                   "give the state that must last (usually the accepting constraint's)"});
  }
  return out;
}

bool GoalHoldsAtStart(const StatePlan& sp, const Domain& d) {
  (void)d;
  if (!sp.episodes.empty() || !sp.temporals.empty() || !sp.orders.empty()) return false;
  if (sp.goal.raw_info.IsChange()) return false;  // a change cannot hold at e[0]
  return Evaluate(sp.goal.raw, [&](const Expr& atom) {
    switch (atom.var_kind) {
      case VarKind::kLocation:
        return sp.initial[atom.target];
      default:
        return 0;  // commands idle (no-op), accepting automata waiting
    }
  });
}

MeaningFindings CheckMeaning(const Json& plan, const StatePlan& sp, const Domain& d,
                             const std::string& command) {
  MeaningFindings f;
  for (auto& w : DefaultedStateConstraints(plan)) f.doubtful.push_back(std::move(w));
  auto durations = StatedDurations(command);
  // Orders (contract section 15) carry durations too ("at least 5 seconds later").
  if (!durations.empty() && sp.episodes.empty() && sp.temporals.empty() && sp.orders.empty()) {
    std::string list;
    for (std::size_t i = 0; i < durations.size() && i < 5; ++i)
      list += (i ? ", \"" : "\"") + Cut(durations[i], 40) + "\"";
    f.blocking.push_back(
        {"/constraints", std::nullopt,
         "the command states durations (" + list +
             ") but the state plan has no "
             "episode or temporal constraint: add the constraints the command states"});
  }
  if (GoalHoldsAtStart(sp, d))
    f.doubtful.push_back({"/end_state/goal_constraint", std::nullopt,
                          "the goal already holds in the initial state and nothing else is asked: "
                          "the plan would be empty (makespan 0); state what the command asks for"});
  return f;
}

namespace {

std::set<std::string> Names(const Json& plan, const char* group) {
  std::set<std::string> out;
  if (!plan.contains("constraints") || !plan["constraints"].is_object()) return out;
  const Json& c = plan["constraints"];
  if (!c.contains(group) || !c[group].is_object()) return out;
  for (auto it = c[group].begin(); it != c[group].end(); ++it) out.insert(it.key());
  return out;
}

// The goal's conjuncts as printed source; empty when there is no goal or it does not parse.
// `quantified` (when given) is set when the goal holds a quantifier: one every(...) may say what
// many conjuncts said, so counts do not compare.
std::vector<std::string> GoalConjuncts(const Json& plan, bool* quantified = nullptr) {
  std::vector<std::string> out;
  if (!plan.contains("end_state") || !plan["end_state"].is_object()) return out;
  const Json& e = plan["end_state"];
  if (!e.contains("goal_constraint") || !e["goal_constraint"].is_string()) return out;
  ExprError err;
  auto expr = Parse(e["goal_constraint"].get<std::string>(), err);
  if (!expr) return out;
  if (quantified && HasQuantifier(*expr)) *quantified = true;
  std::vector<const Expr*> parts;
  Flatten(*expr, Expr::Op::kAnd, parts);
  for (const Expr* p : parts)
    if (p->op != Expr::Op::kTrue) out.push_back(PrintSource(*p));
  return out;
}

}  // namespace

std::vector<Diagnostic> Dropped(const Json& before, const Json& after, bool goal_flagged) {
  std::vector<Diagnostic> out;
  if (!before.is_object() || !after.is_object()) return out;
  for (const char* group : {"episodes", "temporal", "event"}) {
    auto b = Names(before, group), a = Names(after, group);
    if (a.size() >= b.size()) continue;
    std::string missing;
    for (const auto& n : b)
      if (!a.count(n)) missing += (missing.empty() ? "'" : ", '") + Cut(n, 60) + "'";
    out.push_back({std::string("/constraints/") + group, std::nullopt,
                   "the repair dropped " + std::to_string(b.size() - a.size()) + " of the " +
                       std::to_string(b.size()) + " " + group +
                       " constraint(s) of the previous "
                       "answer (" +
                       missing + "); keep every constraint the command states"});
  }
  if (goal_flagged) return out;
  bool quantified = false;
  auto gb = GoalConjuncts(before, &quantified), ga = GoalConjuncts(after, &quantified);
  if (!quantified && !gb.empty() && ga.size() < gb.size()) {
    std::set<std::string> kept(ga.begin(), ga.end());
    std::string missing;
    for (const auto& g : gb)
      if (!kept.count(g)) missing += (missing.empty() ? "" : ", ") + Cut(g, 80);
    out.push_back({"/end_state/goal_constraint", std::nullopt,
                   "the repair dropped part of the goal of the previous answer (" + missing + ")"});
  }
  return out;
}

}  // namespace ctb
