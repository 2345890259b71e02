// Grouping fluents into state variables: an action that deletes one atom and adds another sharing
// arguments with it (at ?t ?from -> at ?t ?to; free ?r ?g -> carry ?r ?o ?g) pairs their
// predicates with the shared arguments as the owner; a group of paired predicates is kept as one
// multi-valued variable per owner when every action balances it, and split into booleans if not.
#include "interchange/pddl/internal/state_vars.h"

#include <numeric>
#include <set>

namespace ctb::pddl {

namespace {

bool SameAtom(const Atom& a, const Atom& b) {
  return a.pred == b.pred && a.args == b.args && a.equality == b.equality;
}

std::vector<std::string> OwnerTerms(const Atom& a, const std::vector<int>& pos) {
  std::vector<std::string> t;
  for (int i : pos) t.push_back(a.args[i]);
  return t;
}

class Analysis {
 public:
  Analysis(const DomainAst& d, const ProblemAst* p, std::vector<Issue>& issues)
      : d_(d), p_(p), issues_(issues) {
    parent_.resize(d.predicates.size());
    std::iota(parent_.begin(), parent_.end(), 0);
    owner_.resize(d.predicates.size());
    bad_.resize(d.predicates.size());
  }

  std::optional<StateVars> Run();

 private:
  int PredIndex(const std::string& n) const {
    for (std::size_t i = 0; i < d_.predicates.size(); ++i)
      if (d_.predicates[i].name == n) return static_cast<int>(i);
    return -1;
  }
  int Find(int x) const {
    while (parent_[x] != x) x = parent_[x];
    return x;
  }
  void SetOwner(int pred, const std::vector<int>& pos) {
    if (owner_[pred] && *owner_[pred] != pos) bad_[pred] = true;
    owner_[pred] = pos;
  }
  void Pair(const Action& a);
  bool Balanced(int root) const;
  bool BalancedIn(const Action& a, int root) const;
  bool InitOk(int root) const;

  const DomainAst& d_;
  const ProblemAst* p_;
  std::vector<Issue>& issues_;
  std::vector<int> parent_;
  std::vector<std::optional<std::vector<int>>> owner_;  // per predicate
  std::vector<bool> bad_;
  std::set<int> changed_;
};

// Pairs each deleted atom with the added atom sharing the most arguments with it (at least one,
// or both without arguments); the shared arguments, in the deleted atom's order, are the owner.
void Analysis::Pair(const Action& a) {
  std::vector<const TimedLiteral*> dels, adds;
  for (const auto& e : a.effects) {
    changed_.insert(PredIndex(e.lit.atom.pred));
    (e.lit.positive ? adds : dels).push_back(&e);
  }
  std::vector<bool> taken(adds.size());
  for (const TimedLiteral* del : dels) {
    const Atom& x = del->lit.atom;
    int best = -1, best_k = -1;
    std::vector<int> best_x, best_y;
    for (std::size_t k = 0; k < adds.size(); ++k) {
      const Atom& y = adds[k]->lit.atom;
      if (taken[k]) continue;
      std::vector<int> px, py;
      for (std::size_t i = 0; i < x.args.size(); ++i)
        for (std::size_t j = 0; j < y.args.size(); ++j)
          if (x.args[i] == y.args[j] && x.args[i][0] == '?') {
            px.push_back(static_cast<int>(i));
            py.push_back(static_cast<int>(j));
            break;
          }
      bool ok = !px.empty() || (x.args.empty() && y.args.empty());
      if (ok && static_cast<int>(px.size()) > best) {
        best = static_cast<int>(px.size());
        best_k = static_cast<int>(k);
        best_x = px;
        best_y = py;
      }
    }
    if (best_k < 0) continue;
    taken[best_k] = true;
    int px = PredIndex(x.pred), py = PredIndex(adds[best_k]->lit.atom.pred);
    SetOwner(px, best_x);
    SetOwner(py, best_y);
    parent_[Find(px)] = Find(py);
  }
}

// In every action, per owner, the group's atoms change as "delete the required one, add one":
// deleted at start and added at start or end, or both at end.
bool Analysis::BalancedIn(const Action& a, int root) const {
  std::map<std::vector<std::string>, std::pair<std::vector<const TimedLiteral*>,
                                               std::vector<const TimedLiteral*>>>
      per_owner;
  for (const auto& e : a.effects) {
    int p = PredIndex(e.lit.atom.pred);
    if (Find(p) != root) continue;
    auto& slot = per_owner[OwnerTerms(e.lit.atom, *owner_[p])];
    auto& list = e.lit.positive ? slot.second : slot.first;
    bool dup = false;
    for (const auto* l : list) dup = dup || (SameAtom(l->lit.atom, e.lit.atom) && l->when == e.when);
    if (!dup) list.push_back(&e);
  }
  for (const auto& [owner, dels_adds] : per_owner) {
    const auto& [dels, adds] = dels_adds;
    if (dels.size() != 1 || adds.size() != 1) return false;
    if (dels[0]->when == When::kEnd && adds[0]->when == When::kStart) return false;
    bool required = false;
    for (const auto& c : a.conditions)
      required = required || (c.lit.positive && SameAtom(c.lit.atom, dels[0]->lit.atom) &&
                              (c.when != When::kEnd || dels[0]->when == When::kEnd));
    if (!required) return false;
  }
  return true;
}

bool Analysis::Balanced(int root) const {
  std::size_t size = 0;
  bool first = true;
  for (std::size_t p = 0; p < d_.predicates.size(); ++p) {
    if (Find(static_cast<int>(p)) != root) continue;
    if (bad_[p] || !owner_[p] || !changed_.count(static_cast<int>(p))) return false;
    if (!first && owner_[p]->size() != size) return false;
    size = owner_[p]->size();
    first = false;
  }
  for (const auto& a : d_.actions)
    if (!BalancedIn(a, root)) return false;
  return InitOk(root);
}

// At most one initial value per owner.
bool Analysis::InitOk(int root) const {
  if (!p_) return true;
  std::set<std::vector<std::string>> seen;
  for (const Atom& a : p_->init) {
    int p = PredIndex(a.pred);
    if (p < 0 || Find(p) != root || !owner_[p]) continue;
    if (a.args.size() != d_.predicates[p].params.size()) continue;  // refused while grounding
    if (!seen.insert(OwnerTerms(a, *owner_[p])).second) return false;
  }
  return true;
}

std::optional<StateVars> Analysis::Run() {
  for (const auto& a : d_.actions) Pair(a);
  std::set<int> timed;
  if (p_) {
    for (const auto& t : p_->tils) {
      int p = PredIndex(t.lit.atom.pred);
      if (p < 0) continue;  // refused while grounding
      if (changed_.count(p)) {
        issues_.push_back(Issue{p_->file, t.lit.pos.line, t.lit.pos.column, "",
                                "timed initial literal " + t.lit.text + " changes '" +
                                    t.lit.atom.pred +
                                    "', which actions change too: cannot be mapped (only "
                                    "predicates that no action changes may have them)"});
        continue;
      }
      timed.insert(p);
    }
  }
  StateVars sv;
  std::map<int, int> group_of_root;
  std::map<int, bool> balanced;
  for (std::size_t i = 0; i < d_.predicates.size(); ++i) {
    int p = static_cast<int>(i);
    if (!changed_.count(p) && !timed.count(p)) continue;
    const std::string& name = d_.predicates[p].name;
    int root = Find(p);
    if (!balanced.count(root)) balanced[root] = !timed.count(p) && Balanced(root);
    if (balanced[root]) {
      auto [it, fresh] = group_of_root.emplace(root, static_cast<int>(sv.groups.size()));
      if (fresh) sv.groups.push_back(Group{{}, {}, false, false, name});
      sv.groups[it->second].preds.push_back(name);
      sv.groups[it->second].owner[name] = *owner_[p];
      sv.group_of[name] = it->second;
      continue;
    }
    Group g{{name}, {}, true, timed.count(p) > 0, name};
    std::vector<int> all(d_.predicates[p].params.size());
    std::iota(all.begin(), all.end(), 0);
    g.owner[name] = all;
    sv.group_of[name] = static_cast<int>(sv.groups.size());
    sv.groups.push_back(std::move(g));
  }
  return sv;
}

}  // namespace

std::optional<StateVars> AnalyzeStateVars(const DomainAst& d, const ProblemAst* p,
                                          std::vector<Issue>& issues, std::vector<Issue>&) {
  std::size_t before = issues.size();
  auto sv = Analysis(d, p, issues).Run();
  if (issues.size() > before) return std::nullopt;
  return sv;
}

}  // namespace ctb::pddl
