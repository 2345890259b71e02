// Grounding: objects and facts from the domain's constants and the problem, the bindings of each
// action's parameters that its conditions allow once the reachable atoms are known, then the
// state variables.
#include "interchange/pddl/internal/grounding.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>

namespace ctb::pddl {

std::string NotValue(const std::string& pred) { return "not " + pred; }

std::optional<std::pair<VarKey, std::string>> Grounded::Locate(const StateVars& sv,
                                                               const Atom& a) const {
  auto it = sv.group_of.find(a.pred);
  if (a.equality || it == sv.group_of.end()) return std::nullopt;
  const Group& g = sv.groups[it->second];
  if (g.timed && !timed.count(GroundKey(a.pred, a.args))) return std::nullopt;
  if (g.boolean) return std::make_pair(VarKey{it->second, a.args}, a.pred);
  const std::vector<int>& pos = g.owner.at(a.pred);
  VarKey k{it->second, {}};
  std::vector<std::string> rest;
  for (std::size_t i = 0; i < a.args.size(); ++i) {
    bool owner = std::find(pos.begin(), pos.end(), static_cast<int>(i)) != pos.end();
    (owner ? k.owner : rest).push_back(a.args[i]);
  }
  // The owner in the order of the owner positions.
  k.owner.clear();
  for (int i : pos) k.owner.push_back(a.args[i]);
  return std::make_pair(k, GroundKey(a.pred, rest));
}

namespace {

constexpr long kMaxBindingSteps = 5'000'000;
constexpr double kMaxDuration = 1e7;

class Grounder {
 public:
  Grounder(const DomainAst& d, const StateVars& sv, const ProblemAst* p, const ImportOptions& o,
           std::vector<Issue>& issues, std::vector<Issue>& warnings)
      : d_(d), sv_(sv), p_(p), o_(o), issues_(issues), warnings_(warnings) {}

  std::optional<Grounded> Run();

 private:
  void Fail(const std::string& file, Pos p, std::string action, std::string message) {
    issues_.push_back(Issue{file, p.line, p.column, std::move(action), std::move(message)});
  }
  bool IsA(const std::string& object, const std::vector<std::string>& types) const;
  void Objects();
  void Facts();
  void Complete(std::size_t index, const std::vector<std::string>& binding);
  bool Duration(const Action& a, const std::function<std::string(const std::string&)>& term,
                GroundAction& ga);
  void Bind(std::size_t index, std::vector<std::vector<std::string>>& found);
  std::optional<double> Eval(const NumExpr& e, const Action& a,
                             const std::function<std::string(const std::string&)>& term,
                             bool& failed);
  void Tils();
  void Reach();
  bool NeedsProblem(const Action& a);
  void Variables();
  void DropUnset(std::map<VarKey, Variable>& vars);
  void FilterConditions();

  const DomainAst& d_;
  const StateVars& sv_;
  const ProblemAst* p_;
  const ImportOptions& o_;
  std::vector<Issue>& issues_;
  std::vector<Issue>& warnings_;
  Grounded g_;
  std::map<std::string, std::vector<std::string>> object_types_;
  std::map<std::string, int> object_order_;
  bool too_many_ = false;
  std::map<std::size_t, int> undefined_durations_;
  long steps_ = 0;
  std::set<std::string> reachable_;
  std::vector<std::vector<std::vector<std::string>>> bindings_;  // per action
  std::vector<Til> tils_;
};

bool Grounder::IsA(const std::string& object, const std::vector<std::string>& types) const {
  for (std::string t : object_types_.at(object)) {
    for (int hops = 0; hops < 64; ++hops) {  // a cycle in :types ends here
      for (const auto& want : types)
        if (want == t || want == "object") return true;
      auto it = d_.type_parents.find(t);
      if (it == d_.type_parents.end() || it->second.empty()) break;
      t = it->second[0];
    }
  }
  return false;
}

void Grounder::Objects() {
  auto add = [&](const TypedName& o, const std::string& file) {
    for (const auto& t : o.types)
      if (t != "object" && !d_.type_parents.count(t))
        Fail(file, o.pos, "", "object '" + o.name + "' has the undeclared type '" + t + "'");
    auto [it, fresh] = object_types_.emplace(o.name, o.types);
    if (!fresh) {  // declared again (IPC 2014 TMS: kiln0 - kiln8, kiln0 - kiln20): all its types
      for (const auto& t : o.types)
        if (std::find(it->second.begin(), it->second.end(), t) == it->second.end()) {
          it->second.push_back(t);
          warnings_.push_back(Issue{
              file, o.pos.line, o.pos.column, "",
              "object '" + o.name + "' declared again with type '" + t + "': it has both types"});
        }
      return;
    }
    object_order_[o.name] = static_cast<int>(g_.objects.size());
    g_.objects.push_back(o.name);
  };
  for (const auto& c : d_.constants) add(c, d_.file);
  if (p_)
    for (const auto& o : p_->objects) add(o, p_->file);
}

void Grounder::Facts() {
  if (!p_) return;
  for (const Atom& a : p_->init) {
    const Signature* s = d_.Predicate(a.pred);
    if (!s) {
      Fail(p_->file, a.pos, "", "unknown predicate '" + a.pred + "' in :init");
      continue;
    }
    bool ok = s->params.size() == a.args.size();
    if (!ok)
      Fail(p_->file, a.pos, "",
           "predicate '" + a.pred + "' takes " + std::to_string(s->params.size()) + " arguments");
    for (const auto& x : a.args)
      if (!object_types_.count(x)) {
        Fail(p_->file, a.pos, "", "unknown object '" + x + "' in :init");
        ok = false;
      }
    if (ok) g_.facts.insert(GroundKey(a.pred, a.args));
  }
}

std::optional<double> Grounder::Eval(const NumExpr& e, const Action& a,
                                     const std::function<std::string(const std::string&)>& term,
                                     bool& failed) {
  switch (e.kind) {
    case NumExpr::Kind::kNumber:
      return e.value;
    case NumExpr::Kind::kFunction: {
      std::vector<std::string> args;
      for (const auto& t : e.args) args.push_back(term(t));
      auto it = p_->init_values.find(GroundKey(e.name, args));
      if (it == p_->init_values.end()) return std::nullopt;
      return it->second;
    }
    case NumExpr::Kind::kOp: {
      std::vector<double> v;
      for (const auto& k : e.kids) {
        auto x = Eval(k, a, term, failed);
        if (!x) return std::nullopt;
        v.push_back(*x);
      }
      if (v.size() == 1) return -v[0];
      if (e.name == "+") return v[0] + v[1];
      if (e.name == "-") return v[0] - v[1];
      if (e.name == "*") return v[0] * v[1];
      if (v[1] == 0) {
        Fail(d_.file, e.pos, a.name, "duration divides by zero");
        failed = true;
        return std::nullopt;
      }
      return v[0] / v[1];
    }
  }
  return std::nullopt;
}

// Records what the binding requires of (need/forbid) or does to a variable; false when two
// conditions on one variable contradict each other.
bool Require(VarUse& u, When w, const std::string& value, bool positive, bool boolean) {
  if (!positive && boolean)
    return Require(u, w, value.rfind("not ", 0) == 0 ? value.substr(4) : NotValue(value), true,
                   boolean);
  auto& need = u.need[static_cast<int>(w)];
  if (!positive) {
    if (need == value) return false;
    u.forbid[static_cast<int>(w)].push_back(value);
    return true;
  }
  if (need && *need != value) return false;
  need = value;
  return true;
}

VarUse& UseOf(GroundAction& ga, const VarKey& k) {
  for (auto& u : ga.uses)
    if (u.var == k) return u;
  ga.uses.push_back(VarUse{k});
  return ga.uses.back();
}

// One complete binding: what it requires of and does to each variable, and its duration.
void Grounder::Complete(std::size_t index, const std::vector<std::string>& binding) {
  const Action& a = d_.actions[index];
  auto term = [&](const std::string& t) {
    if (t[0] != '?') return t;
    for (std::size_t i = 0; i < a.params.size(); ++i)
      if (a.params[i].name == t) return binding[i];
    return t;
  };
  auto ground = [&](const Atom& x) {
    Atom y = x;
    for (auto& t : y.args) t = term(t);
    return y;
  };
  GroundAction ga;
  ga.action = static_cast<int>(index);
  ga.args = binding;
  for (const auto& tc : a.conditions) {
    Atom x = ground(tc.lit.atom);
    auto loc = g_.Locate(sv_, x);
    if (!loc) {
      if (x.equality || !sv_.IsFluent(x.pred)) continue;  // checked while binding
      if (g_.facts.count(GroundKey(x.pred, x.args)) != tc.lit.positive) return;  // timed, static
      continue;
    }
    bool boolean = sv_.groups[loc->first.group].boolean;
    if (!Require(UseOf(ga, loc->first), tc.when, loc->second, tc.lit.positive, boolean)) return;
  }
  // Per variable and time: an add gives its value; a delete alone leaves none (false).
  for (When w : {When::kStart, When::kEnd}) {
    std::map<VarKey, std::string> value;
    for (const auto& e : a.effects) {
      if (e.when != w) continue;
      auto loc = g_.Locate(sv_, ground(e.lit.atom));
      bool boolean = sv_.groups[loc->first.group].boolean;
      std::string v = e.lit.positive ? loc->second : boolean ? NotValue(loc->second) : kNoValue;
      auto [it, fresh] = value.emplace(loc->first, v);
      if (!fresh && e.lit.positive) it->second = v;  // an add wins over a delete
    }
    for (const auto& [k, v] : value)
      (w == When::kStart ? UseOf(ga, k).eff_start : UseOf(ga, k).eff_end) = v;
  }
  if (!Duration(a, term, ga)) return;
  if (g_.actions.size() >= o_.max_ground_actions) {
    Fail(d_.file, a.pos, a.name,
         "more than " + std::to_string(o_.max_ground_actions) +
             " ground actions; the import stops here");
    too_many_ = true;
    return;
  }
  g_.actions.push_back(std::move(ga));
}

bool Grounder::Duration(const Action& a, const std::function<std::string(const std::string&)>& term,
                        GroundAction& ga) {
  if (!a.durative) return true;
  bool failed = false;
  for (int bound = 0; bound < 2; ++bound) {
    const auto& expr = bound == 0 ? a.min_duration : a.max_duration;
    if (!expr) continue;
    auto v = Eval(*expr, a, term, failed);
    if (!v) {
      if (!failed) ++undefined_durations_[ga.action];
      return false;
    }
    if (bound == 0)
      ga.lo = *v;
    else
      ga.hi = *v;
  }
  std::string where = "(" + GroundKey(a.name, ga.args) + ")";
  if (ga.lo < 0 || (ga.hi && *ga.hi < 0) || (ga.hi && *ga.hi < ga.lo) || ga.lo > kMaxDuration ||
      (ga.hi && *ga.hi > kMaxDuration) || !std::isfinite(ga.lo)) {
    Fail(d_.file, a.pos, a.name,
         "the duration of " + where + " is negative, empty, or beyond 10,000,000 seconds");
    too_many_ = true;  // stop: one such message is enough
    return false;
  }
  return true;
}

// The order in which to bind an action's parameters: each time the one that completes the most
// conditions (fewest candidates on a tie), so that static relations prune early (sokoban's
// push-to-goal binds the direction, then positions adjacent in it, not every triple of places).
std::vector<std::size_t> BindingOrder(const std::vector<std::set<std::size_t>>& conds,
                                      const std::vector<std::vector<std::string>>& candidates) {
  std::size_t n = candidates.size();
  std::vector<std::size_t> order;
  std::vector<bool> placed(n, false);
  for (std::size_t step = 0; step < n; ++step) {
    std::size_t best = n;
    std::pair<int, std::size_t> best_score{-1, 0};
    for (std::size_t p = 0; p < n; ++p) {
      if (placed[p]) continue;
      int completes = 0;
      for (const auto& c : conds) {
        bool all = c.count(p) > 0;
        for (std::size_t q : c) all = all && (q == p || placed[q]);
        completes += all;
      }
      std::pair<int, std::size_t> score{completes, ~candidates[p].size()};
      if (best == n || score > best_score) best = p, best_score = score;
    }
    placed[best] = true;
    order.push_back(best);
  }
  return order;
}

// Every binding of the action's parameters (by type) whose static, equality and (relaxed: the
// reachable atoms) positive fluent conditions hold, each checked as soon as its last parameter
// is bound (in BindingOrder); `found` gets each.
void Grounder::Bind(std::size_t index, std::vector<std::vector<std::string>>& found) {
  const Action& a = d_.actions[index];
  std::size_t n = a.params.size();
  steps_ = 0;  // the limit is per action and pass
  std::vector<std::vector<std::string>> candidates(n);
  for (std::size_t i = 0; i < n; ++i)
    for (const auto& o : g_.objects)
      if (IsA(o, a.params[i].types)) candidates[i].push_back(o);
  std::vector<const Literal*> lits;
  std::vector<std::set<std::size_t>> params_of;
  for (const auto& tc : a.conditions) {
    const Atom& x = tc.lit.atom;
    bool fluent = !x.equality && sv_.IsFluent(x.pred);
    if (fluent && !tc.lit.positive) continue;  // relaxed: negative fluent conditions ignored
    std::set<std::size_t> ps;
    for (const auto& t : x.args)
      for (std::size_t i = 0; i < n; ++i)
        if (a.params[i].name == t) ps.insert(i);
    lits.push_back(&tc.lit);
    params_of.push_back(ps);
  }
  std::vector<std::size_t> order = BindingOrder(params_of, candidates), position(n);
  for (std::size_t k = 0; k < n; ++k) position[order[k]] = k;
  std::vector<std::vector<const Literal*>> checks(n + 1);
  for (std::size_t c = 0; c < lits.size(); ++c) {
    std::size_t last = 0;
    for (std::size_t i : params_of[c]) last = std::max(last, position[i] + 1);
    checks[last].push_back(lits[c]);
  }
  std::vector<std::string> binding(n);
  auto holds = [&](const Literal* l) {
    std::vector<std::string> args;
    for (const auto& t : l->atom.args) {
      std::string v = t;
      for (std::size_t i = 0; i < n; ++i)
        if (a.params[i].name == t) v = binding[i];
      args.push_back(v);
    }
    if (l->atom.equality) return (args[0] == args[1]) == l->positive;
    std::string key = GroundKey(l->atom.pred, args);
    if (sv_.IsFluent(l->atom.pred)) return !p_ || reachable_.count(key) > 0;
    return (g_.facts.count(key) > 0) == l->positive;
  };
  std::function<void(std::size_t)> walk = [&](std::size_t k) {
    if (too_many_) return;
    if (++steps_ > kMaxBindingSteps) {
      Fail(d_.file, a.pos, a.name,
           "too many parameter bindings to try (more than " + std::to_string(kMaxBindingSteps) +
               "); the import stops here");
      too_many_ = true;
      return;
    }
    for (const Literal* l : checks[k])
      if (!holds(l)) return;
    if (k == n) return found.push_back(binding);
    for (const auto& o : candidates[order[k]]) {
      binding[order[k]] = o;
      walk(k + 1);
      if (too_many_) return;
    }
  };
  walk(0);
  // In the order of the parameters and the objects (as if bound left to right).
  auto rank = [&](const std::vector<std::string>& b) {
    std::vector<int> r;
    for (const auto& o : b) r.push_back(object_order_.at(o));
    return r;
  };
  std::sort(found.begin(), found.end(),
            [&](const auto& x, const auto& y) { return rank(x) < rank(y); });
}

void Grounder::Variables() {
  std::map<VarKey, Variable> vars;
  auto value = [&](const VarKey& k, const std::string& v) {
    auto& var = vars[k];
    var.key = k;
    if (v != kNoValue && std::find(var.values.begin(), var.values.end(), v) == var.values.end())
      var.values.push_back(v);
  };
  if (p_) {
    for (const Atom& a : p_->init) {
      if (!g_.facts.count(GroundKey(a.pred, a.args))) continue;  // refused above
      auto loc = g_.Locate(sv_, a);
      if (!loc) continue;
      auto& var = vars[loc->first];
      var.key = loc->first;
      if (var.initial && *var.initial != loc->second) continue;  // ruled out by the analysis
      var.initial = loc->second;
      value(loc->first, loc->second);
    }
  }
  auto boolean_initial = [&](const VarKey& k) {
    const Group& grp = sv_.groups[k.group];
    if (p_ && grp.boolean && !(vars.count(k) && vars[k].initial)) {
      vars[k].key = k;
      vars[k].initial = NotValue(grp.preds[0]);
      value(k, *vars[k].initial);
    }
  };
  for (const auto& t : tils_) {
    auto loc = g_.Locate(sv_, t.lit.atom);
    boolean_initial(loc->first);
    std::string v = t.lit.positive ? loc->second : NotValue(loc->second);
    vars[loc->first].timeline.emplace_back(t.time, v);
    value(loc->first, v);
  }
  for (const auto& ga : g_.actions) {
    for (const auto& u : ga.uses) {
      boolean_initial(u.var);
      if (sv_.groups[u.var.group].boolean) {  // both values, whatever the action reads
        value(u.var, sv_.groups[u.var.group].preds[0]);
        value(u.var, NotValue(sv_.groups[u.var.group].preds[0]));
      }
      for (const auto* v : {&u.need[0], &u.need[1], &u.need[2], &u.eff_start, &u.eff_end})
        if (*v) value(u.var, **v);
    }
  }
  DropUnset(vars);
  for (auto& [k, v] : vars) {
    std::stable_sort(v.timeline.begin(), v.timeline.end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
    g_.variables.push_back(std::move(v));
  }
  auto order = [&](const Variable& v) {
    std::vector<int> o{v.key.group};
    for (const auto& x : v.key.owner) o.push_back(object_order_.count(x) ? object_order_[x] : -1);
    return o;
  };
  std::stable_sort(g_.variables.begin(), g_.variables.end(),
                   [&](const Variable& a, const Variable& b) { return order(a) < order(b); });
}

// With a problem, a multi-valued variable nobody gave a value has none: its actions never apply.
void Grounder::DropUnset(std::map<VarKey, Variable>& vars) {
  if (!p_) return;
  std::map<VarKey, int> dropped;
  for (auto it = vars.begin(); it != vars.end();) {
    if (it->second.initial) {
      ++it;
      continue;
    }
    dropped[it->first] = 0;
    it = vars.erase(it);
  }
  std::erase_if(g_.actions, [&](const GroundAction& ga) {
    for (const auto& u : ga.uses) {
      auto it = dropped.find(u.var);
      if (it == dropped.end()) continue;
      ++it->second;
      return true;
    }
    return false;
  });
  for (const auto& [k, n] : dropped) {
    std::string owner;
    for (const auto& o : k.owner) owner += (owner.empty() ? "" : " ") + o;
    warnings_.push_back(Issue{p_->file, 0, 0, "",
                              "'" + owner + "' has no initial value of " +
                                  sv_.groups[k.group].name + " in :init: its state variable and " +
                                  std::to_string(n) + " ground actions are left out"});
  }
}

// Timed initial literals: their atoms become variables (the analysis made their predicates
// timed); each must name a known predicate and objects.
void Grounder::Tils() {
  if (!p_) return;
  for (const auto& t : p_->tils) {
    const Atom& a = t.lit.atom;
    const Signature* s = d_.Predicate(a.pred);
    bool ok = s && s->params.size() == a.args.size();
    for (const auto& x : a.args) ok = ok && object_types_.count(x);
    if (!ok) {
      Fail(p_->file, t.lit.pos, "",
           "timed initial literal " + t.lit.text + ": unknown predicate, object or arity");
      continue;
    }
    g_.timed.insert(GroundKey(a.pred, a.args));
    if (t.lit.positive) reachable_.insert(GroundKey(a.pred, a.args));
    tils_.push_back(t);
  }
}

// The relaxed reachability fixpoint: the atoms that :init, timed initial literals and the adds
// of applicable bindings make true, until nothing new; then the bindings applicable at the end.
void Grounder::Reach() {
  reachable_.insert(g_.facts.begin(), g_.facts.end());
  for (int pass = 0; !too_many_; ++pass) {
    std::size_t before = reachable_.size();
    bindings_.assign(d_.actions.size(), {});
    for (std::size_t i = 0; i < d_.actions.size() && !too_many_; ++i) {
      Bind(i, bindings_[i]);
      const Action& a = d_.actions[i];
      for (const auto& b : bindings_[i])
        for (const auto& e : a.effects) {
          if (!e.lit.positive) continue;
          std::vector<std::string> args;
          for (const auto& t : e.lit.atom.args) {
            std::string v = t;
            for (std::size_t k = 0; k < a.params.size(); ++k)
              if (a.params[k].name == t) v = b[k];
            args.push_back(v);
          }
          reachable_.insert(GroundKey(e.lit.atom.pred, args));
        }
    }
    if (reachable_.size() == before || !p_) break;
  }
}

// A condition on a value that does not exist can never hold (positive: the action is left out)
// or always holds (negative: the literal is dropped).
void Grounder::FilterConditions() {
  std::map<VarKey, const Variable*> index;
  for (const auto& v : g_.variables) index[v.key] = &v;
  std::erase_if(g_.actions, [&](GroundAction& ga) {
    for (auto& u : ga.uses) {
      auto it = index.find(u.var);
      if (it == index.end()) return true;
      const auto& values = it->second->values;
      auto exists = [&](const std::string& v) {
        return std::find(values.begin(), values.end(), v) != values.end();
      };
      for (int w = 0; w < 3; ++w) {
        if (u.need[w] && !exists(*u.need[w])) return true;
        std::erase_if(u.forbid[w], [&](const std::string& v) { return !exists(v); });
      }
    }
    return false;
  });
}

std::optional<Grounded> Grounder::Run() {
  std::size_t before = issues_.size();
  g_.has_problem = p_ != nullptr;
  Objects();
  Facts();
  Tils();
  if (issues_.size() > before) return std::nullopt;
  for (std::size_t i = 0; i < d_.actions.size(); ++i)
    if (!NeedsProblem(d_.actions[i])) return std::nullopt;
  Reach();
  for (std::size_t i = 0; i < d_.actions.size() && !too_many_; ++i) {
    const Action& a = d_.actions[i];
    std::size_t n = g_.actions.size();
    if (a.effects.empty()) {
      warnings_.push_back(Issue{d_.file, a.pos.line, a.pos.column, a.name,
                                "changes no fluent (no add or delete effect); left out"});
      continue;
    }
    for (const auto& b : bindings_[i]) {
      Complete(i, b);
      if (too_many_) break;
    }
    if (undefined_durations_[i])
      warnings_.push_back(Issue{d_.file, a.pos.line, a.pos.column, a.name,
                                std::to_string(undefined_durations_[i]) +
                                    " bindings left out: their duration reads a function value "
                                    "that :init does not give"});
    if (g_.actions.size() == n && issues_.size() == before)
      warnings_.push_back(Issue{d_.file, a.pos.line, a.pos.column, a.name,
                                "has no binding of its parameters whose conditions can hold"});
  }
  if (issues_.size() > before) return std::nullopt;
  Variables();
  FilterConditions();
  if (issues_.size() > before) return std::nullopt;
  return std::move(g_);
}

// Static predicates and duration functions take their values from a problem.
bool Grounder::NeedsProblem(const Action& a) {
  if (p_) return true;
  bool uses_functions = false;
  std::function<void(const NumExpr&)> scan = [&](const NumExpr& e) {
    uses_functions = uses_functions || e.kind == NumExpr::Kind::kFunction;
    for (const auto& k : e.kids) scan(k);
  };
  if (a.min_duration) scan(*a.min_duration);
  if (a.max_duration) scan(*a.max_duration);
  if (uses_functions) {
    Fail(d_.file, a.pos, a.name,
         "the duration reads a function, whose values come from a problem's :init: give the "
         "problem file");
    return false;
  }
  for (const auto& tc : a.conditions) {
    const Atom& x = tc.lit.atom;
    if (x.equality || sv_.IsFluent(x.pred)) continue;
    Fail(d_.file, tc.lit.pos, a.name,
         "condition " + tc.lit.text + " reads the static predicate '" + x.pred +
             "', whose facts come from a problem's :init: give the problem file");
    return false;
  }
  return true;
}

}  // namespace

std::optional<Grounded> Ground(const DomainAst& d, const StateVars& sv, const ProblemAst* p,
                               const ImportOptions& options, std::vector<Issue>& issues,
                               std::vector<Issue>& warnings) {
  return Grounder(d, sv, p, options, issues, warnings).Run();
}

}  // namespace ctb::pddl
