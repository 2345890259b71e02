// Grouping fluents into state variables: each action must leave one value of one object's
// variable for another (or switch one boolean atom); the predicates it moves between are merged.
#include "interchange/pddl/internal/state_vars.h"

#include <numeric>
#include <set>

namespace ctb::pddl {

namespace {

bool SameAtom(const Atom& a, const Atom& b) {
  return a.pred == b.pred && a.args == b.args && a.equality == b.equality;
}

// The object whose state a fluent atom describes: its first argument ("" for a 0-ary one).
std::string OwnerTerm(const Atom& a) { return a.args.empty() ? std::string() : a.args[0]; }

std::string AtomText(const Atom& a) { return "(" + GroundKey(a.pred, a.args) + ")"; }

std::string OwnerText(const std::string& term) {
  return term.empty() ? "the world (no argument)" : term;
}

class Analysis {
 public:
  Analysis(const DomainAst& d, std::vector<Issue>& issues, std::vector<Issue>& warnings)
      : d_(d), issues_(issues), warnings_(warnings) {
    parent_.resize(d.predicates.size());
    std::iota(parent_.begin(), parent_.end(), 0);
  }

  std::optional<StateVars> Run();

 private:
  void Fail(const Action& a, Pos p, std::string message) {
    issues_.push_back(Issue{d_.file, p.line, p.column, a.name, std::move(message)});
  }
  int PredIndex(const std::string& n) const {
    for (std::size_t i = 0; i < d_.predicates.size(); ++i)
      if (d_.predicates[i].name == n) return static_cast<int>(i);
    return -1;
  }
  int Find(int x) { return parent_[x] == x ? x : parent_[x] = Find(parent_[x]); }
  void Union(int a, int b) { parent_[Find(a)] = Find(b); }

  std::optional<ActionChange> Lifted(const Action& a, bool& ok);
  bool Requires(const Action& a, const Literal& l) const;
  void CheckEndConditions(const Action& a);

  const DomainAst& d_;
  std::vector<Issue>& issues_;
  std::vector<Issue>& warnings_;
  std::vector<int> parent_;
};

// True when the action requires `l` positively at start or over all.
bool Analysis::Requires(const Action& a, const Literal& l) const {
  for (const auto& c : a.conditions)
    if (c.when != When::kEnd && c.lit.positive && SameAtom(c.lit.atom, l.atom)) return true;
  return false;
}

void Analysis::CheckEndConditions(const Action& a) {
  for (const auto& c : a.conditions) {
    if (c.when != When::kEnd) continue;
    bool repeated = false;
    for (const auto& o : a.conditions)
      repeated = repeated || (o.when != When::kEnd && o.lit.positive == c.lit.positive &&
                              SameAtom(o.lit.atom, c.lit.atom));
    if (!repeated)
      Fail(a, c.lit.pos,
           "condition (at end " + c.lit.text +
               ") cannot be mapped: an action ends by an automatic transition, "
               "which cannot wait for it; write it (over all ...) if it must hold throughout");
  }
}

std::optional<ActionChange> Analysis::Lifted(const Action& a, bool& ok) {
  std::vector<const Literal*> dels, adds;
  for (const auto& e : a.effects) {
    auto& list = e.lit.positive ? adds : dels;
    bool dup = false;
    for (const Literal* l : list) dup = dup || SameAtom(l->atom, e.lit.atom);
    if (!dup) list.push_back(&e.lit);
  }
  if (dels.empty() && adds.empty()) {
    warnings_.push_back(Issue{d_.file, a.pos.line, a.pos.column, a.name,
                              "changes no fluent (no add or delete effect); left out"});
    return std::nullopt;
  }
  std::vector<const Literal*> all = dels;
  all.insert(all.end(), adds.begin(), adds.end());
  std::string owner = OwnerTerm(all[0]->atom);
  for (const Literal* l : all) {
    if (OwnerTerm(l->atom) == owner) continue;
    Fail(a, l->pos,
         "changes two state variables at once: " + AtomText(all[0]->atom) + " of " +
             OwnerText(owner) + " and " + AtomText(l->atom) + " of " +
             OwnerText(OwnerTerm(l->atom)) +
             "; an action may change one object's state (split it into actions)");
    ok = false;
    return std::nullopt;
  }
  if (dels.size() > 1 || adds.size() > 1) {
    std::string list;
    for (const Literal* l : all) list += (list.empty() ? "" : ", ") + l->text;
    Fail(a, a.pos,
         "changes two state variables of " + OwnerText(owner) + " at once (" + list +
             "); an action may leave one value for one other");
    ok = false;
    return std::nullopt;
  }
  ActionChange c;
  if (!dels.empty()) c.del = *dels[0];
  if (!adds.empty()) c.add = *adds[0];
  if (c.del && c.add) {
    if (!Requires(a, *c.del)) {
      Fail(a, c.del->pos,
           "deletes " + AtomText(c.del->atom) +
               " without requiring it (at start or over "
               "all): the value it leaves is unknown, so " +
               c.del->atom.pred + " is not one value per object");
      ok = false;
      return std::nullopt;
    }
    Union(PredIndex(c.del->atom.pred), PredIndex(c.add->atom.pred));
  }
  return c;
}

std::optional<StateVars> Analysis::Run() {
  StateVars sv;
  bool ok = true;
  for (const auto& a : d_.actions) {
    CheckEndConditions(a);
    sv.changes.push_back(Lifted(a, ok));
  }
  // Groups in predicate declaration order; only predicates that some action changes.
  std::set<int> fluent;
  for (const auto& c : sv.changes) {
    if (!c) continue;
    if (c->del) fluent.insert(PredIndex(c->del->atom.pred));
    if (c->add) fluent.insert(PredIndex(c->add->atom.pred));
  }
  std::map<int, int> group_of_root;
  for (int p : fluent) {
    auto [it, fresh] = group_of_root.emplace(Find(p), static_cast<int>(sv.groups.size()));
    if (fresh) sv.groups.push_back(Group{{}, false, d_.predicates[p].name});
    sv.groups[it->second].preds.push_back(d_.predicates[p].name);
    sv.group_of[d_.predicates[p].name] = it->second;
  }
  for (auto& c : sv.changes) {
    if (!c) continue;
    c->group = sv.group_of.at((c->del ? c->del : c->add)->atom.pred);
    if (!c->del || !c->add) sv.groups[c->group].boolean = true;
  }
  // A boolean group must be one predicate that actions only switch (or re-add what they took).
  for (std::size_t i = 0; i < sv.changes.size(); ++i) {
    const auto& c = sv.changes[i];
    if (!c || !sv.groups[c->group].boolean) continue;
    const Group& g = sv.groups[c->group];
    const Action& a = d_.actions[i];
    std::string values;
    for (const auto& p : g.preds) values += (values.empty() ? "" : ", ") + p;
    if (!c->del || !c->add) {
      if (g.preds.size() > 1) {
        const Literal& l = c->del ? *c->del : *c->add;
        Fail(a, l.pos,
             std::string(c->add ? "adds " : "deletes ") + AtomText(l.atom) + " without " +
                 (c->add ? "deleting" : "adding") + " another value of its state variable (" +
                 values + "): the values are then not mutually exclusive");
        ok = false;
      }
    } else if (g.preds.size() == 1 && !SameAtom(c->del->atom, c->add->atom)) {
      Fail(a, c->add->pos,
           "moves " + AtomText(c->del->atom) + " to " + AtomText(c->add->atom) +
               ", but another "
               "action adds or deletes " +
               c->add->atom.pred + " alone: its atoms are then not one value per object");
      ok = false;
    }
  }
  if (!ok) return std::nullopt;
  return sv;
}

}  // namespace

std::optional<StateVars> AnalyzeStateVars(const DomainAst& d, std::vector<Issue>& issues,
                                          std::vector<Issue>& warnings) {
  std::size_t before = issues.size();
  auto sv = Analysis(d, issues, warnings).Run();
  if (issues.size() > before) return std::nullopt;
  return sv;
}

}  // namespace ctb::pddl
