#include "planner/explain/summary.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "planner/expr/expr_print.h"
#include "planner/model/expr_check.h"

namespace ctb {

namespace {

constexpr double kNoUpper = 1e7;  // the largest bound a state plan may give

std::string JoinAnd(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (k > 0) s += k + 1 == v.size() ? " and " : ", ";
    s += v[k];
  }
  return s;
}

class Words {
 public:
  Words(const Domain& d, const StatePlan& sp, bool change, int self_temporal = -1)
      : d_(d), sp_(sp), change_(change), self_(self_temporal) {}

  std::string Of(const Expr& e) const {
    switch (e.op) {
      case Expr::Op::kTrue: return "anything holds";
      case Expr::Op::kFalse: return "never (false)";
      case Expr::Op::kAtom: return Atom(e);
      case Expr::Op::kAnd: return Conjunction(e);
      case Expr::Op::kOr: {
        std::vector<const Expr*> parts;
        Flatten(e, Expr::Op::kOr, parts);
        std::vector<std::string> w;
        for (const Expr* p : parts) w.push_back(Group(*p));
        std::string s = "either " + w[0];
        for (std::size_t k = 1; k < w.size(); ++k) s += " or " + w[k];
        return s;
      }
      case Expr::Op::kNot: return "it is not the case that " + Group(e.kids[0]);
      case Expr::Op::kImplies: return "if " + Group(e.kids[0]) + ", then " + Group(e.kids[1]);
      case Expr::Op::kIff: return Group(e.kids[0]) + " exactly when " + Group(e.kids[1]);
      case Expr::Op::kEvery:
      case Expr::Op::kAny: return Quantified(e);
    }
    return "";
  }

 private:
  // A sub-phrase: parenthesised when it is itself a connective other than a conjunction.
  std::string Group(const Expr& e) const {
    if (e.op == Expr::Op::kOr || e.op == Expr::Op::kImplies || e.op == Expr::Op::kIff ||
        e.op == Expr::Op::kEvery || e.op == Expr::Op::kAny)
      return "(" + Of(e) + ")";
    return Of(e);
  }

  // every(k in robot: B) as written: "for every k in robot (the 3 instances robot1 to robot3),
  // B" with B's names as written (robot{k}).
  std::string Quantified(const Expr& e) const {
    std::string range;
    std::string first;
    if (!e.range.empty()) {
      const TemplateRange* t = d_.Template(e.range);
      const std::size_t n = t ? t->values.size() : 0;
      range = e.var + " in " + e.range;
      if (n == 1) range += " (its one instance " + e.range + t->values[0] + ")";
      else if (n > 1)
        range += " (the " + std::to_string(n) + " instances " + e.range + t->values.front() +
                 " to " + e.range + t->values.back() + ")";
      else range += " (no instance)";
      if (n > 0) first = t->values.front();
    } else {
      range = e.var + " from " + std::to_string(e.range_lo) + " to " + std::to_string(e.range_hi);
      if (e.range_lo <= e.range_hi) first = std::to_string(e.range_lo);
    }
    env_.emplace_back(e.var, first);
    std::string body = Group(e.kids[0]);
    env_.pop_back();
    return std::string(e.op == Expr::Op::kEvery ? "for every " : "for some ") + range + ", " +
           body;
  }

  // An atom of a quantifier's body, its names as written: the variable's kind is read from the
  // name with the range's first values in the placeholders.
  std::string WrittenAtom(const Expr& e) const {
    std::string v = e.var;
    for (const auto& [name, value] : env_) {
      const std::string ph = "{" + name + "}";
      for (std::size_t at = v.find(ph); at != std::string::npos; at = v.find(ph, at + value.size()))
        v.replace(at, ph.size(), value);
    }
    const std::string neg = e.not_equal ? " not " : " ";
    const bool before = change_ && e.index.kind == IndexKind::kI;
    const std::string after = before ? " just before" : "";
    if (d_.AutomatonIndex(v) >= 0)
      return e.var + (before ? " was" : " is") + neg + e.value + after;
    if (v.size() > 1 && d_.AutomatonIndex(v.substr(0, v.size() - 1)) >= 0) {
      const std::string who = e.var.substr(0, e.var.size() - 1);
      if (v.back() == 'l') return who + (before ? " was" : " is") + neg + e.value + after;
      if (v.back() == 'u')
        return who + (e.not_equal ? " is not given " : " is given ") + "the command " + e.value;
    }
    return PrintSource(e);
  }

  // "temporalAcceptConstraint_Traj_<self>[i]==tempActive": the idiom that orders the two events
  // of a temporal constraint; "after" already says it.
  bool IsSelfActive(const Expr& e) const {
    return e.op == Expr::Op::kAtom && e.var_kind == VarKind::kTemporalState && e.target == self_ &&
           !e.not_equal && e.value_code == 1;
  }

  std::string Conjunction(const Expr& e) const {
    std::vector<const Expr*> parts;
    Flatten(e, Expr::Op::kAnd, parts);
    std::vector<std::string> w;
    std::vector<bool> used(parts.size(), false);
    for (std::size_t k = 0; k < parts.size(); ++k) {
      if (used[k]) continue;
      const Expr& x = *parts[k];
      if (IsSelfActive(x) && parts.size() > 1) continue;
      // "X goes from A to B": X[i]==A with X[i+1]==B in one conjunction.
      if (change_ && x.op == Expr::Op::kAtom && x.var_kind == VarKind::kLocation && !x.not_equal &&
          x.index.kind == IndexKind::kI) {
        bool paired = false;
        for (std::size_t m = 0; m < parts.size() && !paired; ++m) {
          const Expr& y = *parts[m];
          if (m == k || used[m] || y.op != Expr::Op::kAtom || y.var_kind != VarKind::kLocation ||
              y.not_equal || y.index.kind != IndexKind::kIPlus1 || y.target != x.target)
            continue;
          const Automaton& au = d_.automata[x.target];
          w.push_back(au.name + " goes from " + au.locations[x.value_code] + " to " +
                      au.locations[y.value_code]);
          used[m] = paired = true;
        }
        if (paired) continue;
      }
      w.push_back(Group(x));
    }
    if (w.empty()) return "anything holds";
    return JoinAnd(w);
  }

  std::string Atom(const Expr& e) const {
    std::string when;
    if (e.index.kind == IndexKind::kFixed)
      when = e.index.fixed == 0 ? " at the start" : " on stage " + std::to_string(e.index.fixed);
    switch (e.var_kind) {
      case VarKind::kLocation: {
        const Automaton& au = d_.automata[e.target];
        const bool before = change_ && e.index.kind == IndexKind::kI;
        std::string verb = e.index.kind == IndexKind::kFixed ? "is" : before ? "was" : "is";
        return au.name + " " + verb + (e.not_equal ? " not " : " ") + au.locations[e.value_code] +
               (before ? " just before" : "") + when;
      }
      case VarKind::kCommand: {
        const Automaton& au = d_.automata[e.target];
        std::string cmd = e.value_code == 0 ? "no command" : "the command " + au.commands[e.value_code - 1];
        return au.name + (e.not_equal ? " is not given " : " is given ") + cmd + when;
      }
      case VarKind::kEpisodeState: {
        static const char* kWords[] = {"has not started", "is under way", "is over",
                                       "has failed"};
        return "episode " + sp_.episodes[e.target].name + (e.not_equal ? " is not in state " : " ") +
               (e.not_equal ? EpisodeStateNames()[e.value_code] : kWords[e.value_code]);
      }
      case VarKind::kTemporalState: {
        static const char* kWords[] = {"has not started", "has started (one event has happened)",
                                       "is met", "has failed"};
        return "temporal constraint " + sp_.temporals[e.target].name +
               (e.not_equal ? " is not in state " : " ") +
               (e.not_equal ? TemporalStateNames()[e.value_code] : kWords[e.value_code]);
      }
      case VarKind::kUnresolved: return WrittenAtom(e);
    }
    return PrintSource(e);
  }

  const Domain& d_;
  const StatePlan& sp_;
  bool change_;
  int self_;
  mutable std::vector<std::pair<std::string, std::string>> env_;  // quantifier -> first value
};

// The tree to put in words: as written when it has quantifiers, else the checked one.
const Expr& Said(const Condition& c) { return c.written ? *c.written : c.raw; }

std::string Capitalize(std::string s) {
  if (!s.empty() && s[0] >= 'a' && s[0] <= 'z') s[0] = static_cast<char>(s[0] - 'a' + 'A');
  return s;
}

std::string EventWords(const Domain& d, const StatePlan& sp, const Condition& c, int self) {
  return Words(d, sp, c.raw_info.IsChange(), self).Of(Said(c));
}

// "robot1 takes openDoor1 (from hall to door1)", with the occurrence.
std::string ActionWords(const Domain& d, const StatePlan& sp, int j, bool with_occurrence = true) {
  const ActionEvent& a = sp.actions[j];
  const Automaton& au = d.automata[a.automaton];
  std::string s = au.name;
  if (!a.command.empty()) s += " takes command " + a.command;
  else s += " goes from " + a.from + " to " + a.to;
  if (!a.command.empty() && !a.from.empty()) s += " from " + a.from;
  if (!a.command.empty() && !a.to.empty()) s += " to " + a.to;
  if (with_occurrence) {
    if (a.occurrence == Occurrence::kFirst) s += " (the first time)";
    if (a.occurrence == Occurrence::kLast) s += " (the last time)";
  }
  return s + " [action " + a.name + "]";
}

std::string EndWords(const Domain& d, const StatePlan& sp, const OrderEnd& e) {
  if (e.action < 0)
    return "the moment " + Words(d, sp, e.condition.raw_info.IsChange()).Of(Said(e.condition));
  if (sp.actions[e.action].occurrence == Occurrence::kEvery)
    return "every time " + ActionWords(d, sp, e.action, false);
  return ActionWords(d, sp, e.action);
}

std::string OrderWords(const Domain& d, const StatePlan& sp, const Order& o) {
  const double upper = o.upper.value_or(kNoUpper);
  const std::string gap = o.lower == 0 && !o.upper ? "" : ", " + BoundWords(o.lower, upper) + " later";
  if (o.ordered)
    return "First " + EndWords(d, sp, o.first) + "; then, at that moment or later, " +
           EndWords(d, sp, o.second) + gap + " (temporal constraint " + o.name + ").";
  return Capitalize(BoundWords(o.lower, upper)) + " between " + EndWords(d, sp, o.first) + " and " +
         EndWords(d, sp, o.second) + ", in either order (temporal constraint " + o.name + ").";
}

// The action parts of a state plan in words (contract section 15).
void SummarizeActions(const Domain& d, const StatePlan& sp,
                      const std::function<void(const std::string&, const std::string&)>& add) {
  for (const auto& o : sp.orders)
    if (!o.name.empty()) add("/constraints/temporal/" + PointerToken(o.name), OrderWords(d, sp, o));
  if (!sp.sequence.empty()) {
    std::vector<std::string> steps;
    for (int j : sp.sequence) steps.push_back(ActionWords(d, sp, j));
    std::string text = "One after the other (each after the one before, possibly at the same time): ";
    for (std::size_t k = 0; k < steps.size(); ++k) text += (k ? ", then " : "") + steps[k];
    add("/constraints/sequence", text + ".");
  }
  if (!sp.forbidden.empty()) {
    std::vector<std::string> never;
    for (int j : sp.forbidden) never.push_back(ActionWords(d, sp, j, false));
    add("/constraints/forbidden", "Never: " + JoinAnd(never) + ".");
  }
}

}  // namespace

std::string SecondsText(double v) {
  if (std::fabs(v - std::round(v)) < 1e-9) return std::to_string(std::llround(v));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string BoundWords(double lower, double upper) {
  const std::string lo = SecondsText(lower), hi = SecondsText(upper);
  if (lower == upper) return "exactly " + lo + " s";
  if (upper >= kNoUpper) return "at least " + lo + " s (at most " + hi + " s, the largest bound)";
  if (lower == 0) return "within 0 to " + hi + " s";
  return "between " + lo + " and " + hi + " s";
}

std::string ConditionWords(const Domain& d, const StatePlan& sp, const Condition& c) {
  return Words(d, sp, c.raw_info.IsChange()).Of(Said(c));
}

Json SummarizeStatePlan(const Domain& d, const StatePlan& sp) {
  Json out = Json::array();
  auto add = [&](const std::string& pointer, const std::string& text) {
    out.push_back({{"pointer", pointer}, {"text", text}});
  };

  // The instances of a template that all start in one location are said once ("every robot
  // (robot1 to robot256) is outside"), at the place of the first of them.
  std::vector<std::string> group(d.automata.size());
  std::vector<bool> grouped(d.automata.size(), false);
  for (const auto& t : d.templates) {
    if (t.values.size() < 2) continue;
    std::vector<int> members;
    for (const auto& v : t.values) {
      const int a = d.AutomatonIndex(t.name + v);
      if (a < 0 || grouped[a] || sp.initial[a] < 0 ||
          (!members.empty() && d.automata[a].locations[sp.initial[a]] !=
                                   d.automata[members[0]].locations[sp.initial[members[0]]])) {
        members.clear();
        break;
      }
      members.push_back(a);
    }
    if (members.empty()) continue;
    for (int a : members) grouped[a] = true;
    group[members[0]] = "every " + t.name + " (" + d.automata[members.front()].name + " to " +
                        d.automata[members.back()].name + ") is " +
                        d.automata[members[0]].locations[sp.initial[members[0]]];
  }
  std::vector<std::string> init;
  for (std::size_t a = 0; a < d.automata.size(); ++a) {
    if (!group[a].empty()) init.push_back(group[a]);
    else if (!grouped[a]) init.push_back(d.automata[a].name + " is " + d.automata[a].locations[sp.initial[a]]);
  }
  std::string where = "In the " + d.name + " domain" +
                      (d.description.empty() ? "" : " (" + d.description + ")") + ", initially ";
  add("/initial_state", where + JoinAnd(init) + ".");

  if (sp.goal.raw.op == Expr::Op::kTrue) {
    add(sp.goal.pointer, "There is no goal state: the plan ends once every constraint is met.");
  } else if (sp.goal.raw_info.IsChange()) {
    add(sp.goal.pointer, "The plan ends at the moment " + ConditionWords(d, sp, sp.goal) + ".");
  } else {
    add(sp.goal.pointer, "At the end, " + ConditionWords(d, sp, sp.goal) + ".");
  }

  if (sp.maintenance.expr.op != Expr::Op::kTrue)
    add(sp.maintenance.pointer,
        "Until the end, at every moment: " + Words(d, sp, false).Of(Said(sp.maintenance)) + ".");

  for (const auto& ep : sp.episodes) {
    std::string text = "Episode " + ep.name + " starts the first time " +
                       ConditionWords(d, sp, ep.accepting);
    if (ep.state.expr.op != Expr::Op::kTrue)
      text += "; while it lasts, " + Words(d, sp, false).Of(Said(ep.state));
    text += "; it lasts " + BoundWords(ep.lower, ep.upper) + ".";
    add("/constraints/episodes/" + PointerToken(ep.name), text);
  }

  for (std::size_t q = 0; q < sp.temporals.size(); ++q) {
    const Temporal& tc = sp.temporals[q];
    const int self = static_cast<int>(q);
    const std::string e1 = EventWords(d, sp, tc.event1, self);
    const std::string e2 = EventWords(d, sp, tc.event2, self);
    add("/constraints/temporal/" + PointerToken(tc.name),
        Capitalize(BoundWords(tc.lower, tc.upper)) + " after " + e1 + ", " + e2 +
            " (temporal constraint " + tc.name + ").");
  }

  SummarizeActions(d, sp, add);

  for (const SharedEvent* evp : sp.AllSharedEvents()) {
    const SharedEvent& ev = *evp;
    std::vector<std::string> ends;
    for (const auto& p : ev.endpoints) {
      switch (p.kind) {
        case EndpointKind::kEpisodeStart:
          ends.push_back("the start of episode " + sp.episodes[p.index].name);
          break;
        case EndpointKind::kEpisodeEnd:
          ends.push_back("the end of episode " + sp.episodes[p.index].name);
          break;
        case EndpointKind::kEvent1:
          ends.push_back("the moment " +
                         EventWords(d, sp, sp.temporals[p.index].event1, p.index) +
                         " (first event of " + sp.temporals[p.index].name + ")");
          break;
        case EndpointKind::kEvent2:
          ends.push_back("the moment " +
                         EventWords(d, sp, sp.temporals[p.index].event2, p.index) +
                         " (second event of " + sp.temporals[p.index].name + ")");
          break;
        case EndpointKind::kAction:
          ends.push_back("the moment " + ActionWords(d, sp, p.index));
          break;
        case EndpointKind::kOrder1:
          ends.push_back(EndWords(d, sp, sp.orders[p.index].first) + " (first event of " +
                         sp.orders[p.index].name + ")");
          break;
        case EndpointKind::kOrder2:
          ends.push_back(EndWords(d, sp, sp.orders[p.index].second) + " (second event of " +
                         sp.orders[p.index].name + ")");
          break;
      }
    }
    add("/constraints/event/" + PointerToken(ev.name),
        "These happen at one and the same moment: " + JoinAnd(ends) + ".");
  }
  return out;
}

}  // namespace ctb
