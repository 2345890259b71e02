// Grounding: objects and facts from the domain's constants and the problem, every binding of
// each action's parameters that its static conditions allow, then the state variables.
#include "interchange/pddl/internal/grounding.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace ctb::pddl {

std::string NotValue(const std::string& pred) { return "not " + pred; }

std::optional<std::pair<VarKey, std::string>> Grounded::Locate(const StateVars& sv,
                                                               const Atom& a) const {
  auto it = sv.group_of.find(a.pred);
  if (a.equality || it == sv.group_of.end()) return std::nullopt;
  if (sv.groups[it->second].boolean) return std::make_pair(VarKey{it->second, a.args}, a.pred);
  VarKey k{it->second, {}};
  if (!a.args.empty()) k.owner.push_back(a.args[0]);
  std::vector<std::string> rest(a.args.begin() + (a.args.empty() ? 0 : 1), a.args.end());
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
  void Bind(std::size_t index);
  void Complete(std::size_t index, const std::vector<std::string>& binding);
  std::optional<double> Eval(const NumExpr& e, const Action& a,
                             const std::function<std::string(const std::string&)>& term,
                             bool& failed);
  void Variables();
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
    if (!fresh) {
      if (it->second != o.types) Fail(file, o.pos, "", "object '" + o.name + "' declared twice");
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

// One complete binding: the change, the conditions on other variables, the duration.
void Grounder::Complete(std::size_t index, const std::vector<std::string>& binding) {
  const Action& a = d_.actions[index];
  const ActionChange& c = *sv_.changes[index];
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
  const Group& grp = sv_.groups[c.group];
  if (grp.boolean) {
    const Atom x = ground((c.del ? c.del : c.add)->atom);
    ga.var = g_.Locate(sv_, x)->first;
    ga.from = c.del ? x.pred : NotValue(x.pred);
    ga.to = c.add ? x.pred : NotValue(x.pred);
  } else {
    auto from = g_.Locate(sv_, ground(c.del->atom));
    auto to = g_.Locate(sv_, ground(c.add->atom));
    ga.var = from->first;
    ga.from = from->second;
    ga.to = to->second;
  }
  for (const auto& tc : a.conditions) {
    if (tc.when == When::kEnd) continue;  // repeats an earlier one (state_vars.cpp)
    Atom x = ground(tc.lit.atom);
    auto loc = g_.Locate(sv_, x);
    if (!loc) continue;          // static: checked while binding
    if (loc->first == ga.var) {  // the variable the action moves: read on its source value
      if ((loc->second == ga.from) != tc.lit.positive) return;
      continue;
    }
    ga.conditions.push_back(GroundLit{loc->first, loc->second, tc.lit.positive,
                                      tc.when == When::kOverAll, tc.lit.text});
  }
  if (a.durative) {
    bool failed = false;
    if (a.min_duration) {
      auto lo = Eval(*a.min_duration, a, term, failed);
      if (!lo) {
        if (!failed) ++undefined_durations_[index];
        return;
      }
      ga.lo = *lo;
    }
    if (a.max_duration) {
      auto hi = Eval(*a.max_duration, a, term, failed);
      if (!hi) {
        if (!failed) ++undefined_durations_[index];
        return;
      }
      ga.hi = *hi;
    }
    std::string where = "(" + GroundKey(a.name, binding) + ")";
    if (ga.lo < 0 || (ga.hi && *ga.hi < 0) || (ga.hi && *ga.hi < ga.lo) || ga.lo > kMaxDuration ||
        (ga.hi && *ga.hi > kMaxDuration) || !std::isfinite(ga.lo)) {
      Fail(d_.file, a.pos, a.name,
           "the duration of " + where + " is negative, empty, or beyond 10,000,000 seconds");
      too_many_ = true;  // stop: one such message is enough
      return;
    }
  }
  if (g_.actions.size() >= o_.max_ground_actions) {
    Fail(d_.file, a.pos, a.name,
         "more than " + std::to_string(o_.max_ground_actions) +
             " ground actions; the import stops here");
    too_many_ = true;
    return;
  }
  g_.actions.push_back(std::move(ga));
}

// Every binding of the action's parameters (by type) whose static and equality conditions hold,
// each checked as soon as its last parameter is bound.
void Grounder::Bind(std::size_t index) {
  const Action& a = d_.actions[index];
  std::size_t n = a.params.size();
  std::vector<std::vector<std::string>> candidates(n);
  for (std::size_t i = 0; i < n; ++i)
    for (const auto& o : g_.objects)
      if (IsA(o, a.params[i].types)) candidates[i].push_back(o);
  std::vector<std::vector<const Literal*>> checks(n + 1);
  for (const auto& tc : a.conditions) {
    const Atom& x = tc.lit.atom;
    if (!x.equality && sv_.IsFluent(x.pred)) continue;
    if (!x.equality && !p_) {
      Fail(d_.file, tc.lit.pos, a.name,
           "condition " + tc.lit.text +
               " reads the static "
               "predicate '" +
               x.pred +
               "', whose facts come from a "
               "problem's :init: give the problem file");
      return;
    }
    std::size_t last = 0;
    for (const auto& t : x.args)
      for (std::size_t i = 0; i < n; ++i)
        if (a.params[i].name == t) last = std::max(last, i + 1);
    checks[last].push_back(&tc.lit);
  }
  std::vector<std::string> binding(n);
  auto holds = [&](const Literal* l, std::size_t bound) {
    std::vector<std::string> args;
    for (const auto& t : l->atom.args) {
      std::string v = t;
      for (std::size_t i = 0; i < bound; ++i)
        if (a.params[i].name == t) v = binding[i];
      args.push_back(v);
    }
    bool truth =
        l->atom.equality ? args[0] == args[1] : g_.facts.count(GroundKey(l->atom.pred, args)) > 0;
    return truth == l->positive;
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
      if (!holds(l, k)) return;
    if (k == n) return Complete(index, binding);
    for (const auto& o : candidates[k]) {
      binding[k] = o;
      walk(k + 1);
      if (too_many_) return;
    }
  };
  walk(0);
}

void Grounder::Variables() {
  std::map<VarKey, Variable> vars;
  auto value = [&](const VarKey& k, const std::string& v) {
    auto& var = vars[k];
    var.key = k;
    if (std::find(var.values.begin(), var.values.end(), v) == var.values.end())
      var.values.push_back(v);
  };
  if (p_) {
    for (const Atom& a : p_->init) {
      if (!g_.facts.count(GroundKey(a.pred, a.args))) continue;  // refused above
      auto loc = g_.Locate(sv_, a);
      if (!loc) continue;
      auto& var = vars[loc->first];
      if (var.initial && *var.initial != loc->second) {
        Fail(p_->file, a.pos, "",
             "two initial values of one state variable: (" + GroundKey(a.pred, a.args) +
                 ") and the value '" + *var.initial + "' before it; the predicates " +
                 sv_.groups[loc->first.group].name + " form one variable per object");
        continue;
      }
      var.initial = loc->second;
      value(loc->first, loc->second);
    }
  }
  for (const auto& ga : g_.actions) {
    if (p_ && sv_.groups[ga.var.group].boolean && !vars.count(ga.var))
      vars[ga.var].initial = NotValue(sv_.groups[ga.var.group].preds[0]);
    if (vars.count(ga.var) && vars[ga.var].initial) value(ga.var, *vars[ga.var].initial);
    value(ga.var, ga.from);
    value(ga.var, ga.to);
  }
  // With a problem, a move variable nobody gave a value has none: its actions never apply.
  std::map<VarKey, int> dropped;
  if (p_) {
    for (auto it = vars.begin(); it != vars.end();) {
      if (it->second.initial) {
        ++it;
        continue;
      }
      dropped[it->first] = 0;
      it = vars.erase(it);
    }
    std::erase_if(g_.actions, [&](const GroundAction& ga) {
      auto it = dropped.find(ga.var);
      if (it == dropped.end()) return false;
      ++it->second;
      return true;
    });
    for (const auto& [k, n] : dropped) {
      std::string owner;
      for (const auto& o : k.owner) owner += (owner.empty() ? "" : " ") + o;
      warnings_.push_back(Issue{p_->file, 0, 0, "",
                                "'" + owner + "' has no initial value of " +
                                    sv_.groups[k.group].name +
                                    " in :init: its state variable and " + std::to_string(n) +
                                    " ground actions are left out"});
    }
  }
  for (auto& [k, v] : vars) g_.variables.push_back(std::move(v));
  auto order = [&](const Variable& v) {
    std::vector<int> o{v.key.group};
    for (const auto& x : v.key.owner) o.push_back(object_order_.count(x) ? object_order_[x] : -1);
    return o;
  };
  std::stable_sort(g_.variables.begin(), g_.variables.end(),
                   [&](const Variable& a, const Variable& b) { return order(a) < order(b); });
}

// A condition on a variable or value that does not exist can never hold (positive: the action
// is left out) or always holds (negative: the literal is dropped).
void Grounder::FilterConditions() {
  std::map<VarKey, const Variable*> index;
  for (const auto& v : g_.variables) index[v.key] = &v;
  std::erase_if(g_.actions, [&](GroundAction& ga) {
    bool never = false;
    std::erase_if(ga.conditions, [&](const GroundLit& l) {
      auto it = index.find(l.var);
      const Variable* v = it == index.end() ? nullptr : it->second;
      bool exists = v && std::find(v->values.begin(), v->values.end(), l.value) != v->values.end();
      if (!exists && l.positive) never = true;
      return !exists;
    });
    return never;
  });
}

std::optional<Grounded> Grounder::Run() {
  std::size_t before = issues_.size();
  g_.has_problem = p_ != nullptr;
  Objects();
  Facts();
  if (issues_.size() > before) return std::nullopt;
  for (std::size_t i = 0; i < d_.actions.size() && !too_many_; ++i) {
    if (!sv_.changes[i]) continue;
    const Action& a = d_.actions[i];
    bool uses_functions = false;
    std::function<void(const NumExpr&)> scan = [&](const NumExpr& e) {
      uses_functions = uses_functions || e.kind == NumExpr::Kind::kFunction;
      for (const auto& k : e.kids) scan(k);
    };
    if (a.min_duration) scan(*a.min_duration);
    if (a.max_duration) scan(*a.max_duration);
    if (uses_functions && !p_) {
      Fail(d_.file, a.pos, a.name,
           "the duration reads a function, whose values come from a "
           "problem's :init: give the problem file");
      continue;
    }
    std::size_t n = g_.actions.size();
    Bind(i);
    if (undefined_durations_[i])
      warnings_.push_back(Issue{d_.file, a.pos.line, a.pos.column, a.name,
                                std::to_string(undefined_durations_[i]) +
                                    " bindings left out: their duration reads a function value "
                                    "that :init does not give"});
    if (g_.actions.size() == n && issues_.size() == before)
      warnings_.push_back(
          Issue{d_.file, a.pos.line, a.pos.column, a.name,
                "has no binding of its parameters that its static conditions allow"});
  }
  if (issues_.size() > before) return std::nullopt;
  Variables();
  FilterConditions();
  if (issues_.size() > before) return std::nullopt;
  return std::move(g_);
}

}  // namespace

std::optional<Grounded> Ground(const DomainAst& d, const StateVars& sv, const ProblemAst* p,
                               const ImportOptions& options, std::vector<Issue>& issues,
                               std::vector<Issue>& warnings) {
  return Grounder(d, sv, p, options, issues, warnings).Run();
}

}  // namespace ctb::pddl
