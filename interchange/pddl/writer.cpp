// Writing the ground model: one automaton per state variable; per ground action a command that
// every variable it reads or changes takes at its start (and at its end), commanded transitions
// of every variable it changes at that event, step locations for the variables it changes at
// its end (left by commanded transitions its duration later), and guards that protect over-all
// conditions. Timed initial literals are automatic transitions of their atoms' automata.
#include "interchange/pddl/internal/writer.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "planner/model/domain.h"

namespace ctb::pddl {

std::string Identifier(const std::string& name) {
  std::string s;
  for (char c : name) {
    unsigned char u = static_cast<unsigned char>(c);
    s += std::isalnum(u) || c == '_' ? static_cast<char>(std::tolower(u)) : '_';
  }
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) s = "_" + s;
  if (s.size() > 120) s = s.substr(0, 120);
  if (!IsIdentifier(s)) s += "_";
  return s;
}

namespace {

std::string Join(const std::vector<std::string>& parts, const std::string& sep) {
  std::string s;
  for (const auto& p : parts) s += (s.empty() ? "" : sep) + p;
  return s;
}

std::vector<std::string> Split(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= s.size()) {
    auto end = s.find(' ', start);
    if (end == std::string::npos) end = s.size();
    out.push_back(s.substr(start, end - start));
    start = end + 1;
  }
  return out;
}

// Makes names unique within one namespace: "x", then "x_2", "x_3", ...
class NameSet {
 public:
  std::string Take(const std::string& base) {
    std::string n = base;
    for (int k = 2; taken_.count(n); ++k) n = base + "_" + std::to_string(k);
    taken_.insert(n);
    return n;
  }
  void Reserve(const std::string& n) { taken_.insert(n); }
  bool Has(const std::string& n) const { return taken_.count(n) > 0; }

 private:
  std::set<std::string> taken_;
};

class Writer {
 public:
  Writer(const DomainAst& d, const StateVars& sv, const Grounded& g, const ProblemAst* p,
         const ImportOptions& o, std::vector<Issue>& issues)
      : d_(d), sv_(sv), g_(g), p_(p), o_(o), issues_(issues) {}

  std::optional<Written> Run();

 private:
  struct Loc {
    std::string name;
    std::string value;  // the value the variable has while here
    bool step = false;
  };
  struct Trans {
    int var = -1, from = -1, to = -1;
    std::vector<std::string> guard;
    std::optional<std::pair<double, std::optional<double>>> duration;
    int cost = 0;
    int action = -1;  // -1: a timed initial literal
  };
  // A ground action's plan: per changed variable its source values and their step locations.
  struct Plan {
    std::vector<const VarUse*> changed, at_end, read_start, read_end;
    std::map<const VarUse*, std::vector<std::string>> sources;
  };

  int VarIndex(const VarKey& k) const {
    auto it = var_index_.find(k);
    return it == var_index_.end() ? -1 : it->second;
  }
  void NameAutomata();
  std::string ValueName(const VarKey& k, const std::string& value) const;
  void BaseLocations();
  int LocOf(int var, const std::string& value, const std::string& step_name);
  std::string Accept(int var, const std::string& value, const std::string& index) const;
  std::string Refuse(int var, const std::string& value, const std::string& index) const;
  std::string InLocs(int var, const std::vector<int>& locs, const std::string& index) const;
  void Command(int var, std::size_t action);
  std::optional<Plan> MakePlan(std::size_t x);
  std::vector<std::string> Reads(const VarUse& u, int first, int last, std::size_t x);
  void WriteAction(std::size_t x);
  void Timelines();
  void Protect();
  std::optional<double> Resolution();
  Json Duration(double v) const;
  Json Automata() const;
  std::string Unfinished() const;
  std::optional<std::string> GoalText(const Goal& goal);

  const DomainAst& d_;
  const StateVars& sv_;
  const Grounded& g_;
  const ProblemAst* p_;
  const ImportOptions& o_;
  std::vector<Issue>& issues_;
  std::map<VarKey, int> var_index_;
  std::vector<std::string> automaton_;                      // per variable
  std::vector<std::vector<Loc>> locs_;                      // per variable
  std::vector<NameSet> loc_names_;                          // per variable
  std::vector<std::vector<std::string>> commands_;          // per variable
  std::vector<std::string> cmd_;                            // per ground action
  std::vector<int> timing_;                                 // per ground action: var or -1
  std::vector<std::vector<int>> timing_steps_;              // per ground action
  std::vector<std::vector<std::pair<int, const VarUse*>>> over_all_;  // per action: protected
  std::vector<std::set<int>> touches_;                      // per action: variables changed
  std::vector<Trans> trans_;
  double resolution_ = 1;
};

void Writer::BaseLocations() {
  locs_.resize(g_.variables.size());
  loc_names_.resize(g_.variables.size());
  commands_.resize(g_.variables.size());
  for (std::size_t i = 0; i < g_.variables.size(); ++i) {
    const Variable& v = g_.variables[i];
    if (!v.timeline.empty()) continue;  // Timelines()
    for (const auto& value : v.values)
      locs_[i].push_back(Loc{loc_names_[i].Take(ValueName(v.key, value)), value});
  }
}

// The base location of a value, or with a step name, the step location holding that value.
int Writer::LocOf(int var, const std::string& value, const std::string& step_name) {
  auto& locs = locs_[var];
  for (std::size_t k = 0; k < locs.size(); ++k)
    if (locs[k].value == value && (step_name.empty() ? !locs[k].step
                                                     : locs[k].name.rfind(step_name, 0) == 0 &&
                                                           locs[k].step))
      return static_cast<int>(k);
  if (step_name.empty()) return -1;
  locs.push_back(Loc{loc_names_[var].Take(step_name), value, true});
  return static_cast<int>(locs.size()) - 1;
}

std::string Writer::Accept(int var, const std::string& value, const std::string& index) const {
  std::vector<std::string> atoms;
  for (const auto& l : locs_[var])
    if (l.value == value) atoms.push_back(automaton_[var] + "l[" + index + "]==" + l.name);
  if (atoms.empty()) return "false";
  return atoms.size() == 1 ? atoms[0] : "(" + Join(atoms, " \\/ ") + ")";
}

std::string Writer::Refuse(int var, const std::string& value, const std::string& index) const {
  std::vector<std::string> atoms;
  for (const auto& l : locs_[var])
    if (l.value == value) atoms.push_back(automaton_[var] + "l[" + index + "]!=" + l.name);
  return atoms.empty() ? "true" : Join(atoms, " /\\ ");
}

std::string Writer::InLocs(int var, const std::vector<int>& locs, const std::string& index) const {
  std::vector<std::string> atoms;
  for (int k : locs) atoms.push_back(automaton_[var] + "l[" + index + "]==" + locs_[var][k].name);
  if (atoms.empty()) return "false";
  return atoms.size() == 1 ? atoms[0] : "(" + Join(atoms, " \\/ ") + ")";
}

void Writer::Command(int var, std::size_t action) {
  auto& c = commands_[var];
  if (std::find(c.begin(), c.end(), cmd_[action]) == c.end()) c.push_back(cmd_[action]);
}

// Which variables the action changes (at start, at end), reads, and from which values each
// changed variable can start; nullopt when some changed variable has none (never applicable).
std::optional<Writer::Plan> Writer::MakePlan(std::size_t x) {
  const GroundAction& ga = g_.actions[x];
  bool durative = d_.actions[ga.action].durative;
  Plan plan;
  for (const auto& u : ga.uses) {
    if (u.Changes()) plan.changed.push_back(&u);
    if (durative && u.eff_end) plan.at_end.push_back(&u);
  }
  if (plan.changed.empty()) return std::nullopt;
  if (durative && plan.at_end.empty()) plan.at_end.push_back(plan.changed[0]);
  for (const auto& u : ga.uses) {
    bool changed = u.Changes(), ends = std::count(plan.at_end.begin(), plan.at_end.end(), &u);
    if (!changed && (u.need[0] || u.need[1] || !u.forbid[0].empty() || !u.forbid[1].empty()))
      plan.read_start.push_back(&u);
    if (!ends && (u.need[2] || !u.forbid[2].empty())) plan.read_end.push_back(&u);
  }
  auto allowed = [](const VarUse& u, int w, const std::string& v) {
    return (!u.need[w] || *u.need[w] == v) &&
           std::find(u.forbid[w].begin(), u.forbid[w].end(), v) == u.forbid[w].end();
  };
  for (const VarUse* u : plan.changed) {
    bool ends = std::count(plan.at_end.begin(), plan.at_end.end(), u);
    for (const auto& s : g_.variables[VarIndex(u->var)].values) {
      std::string post = u->eff_start.value_or(s);
      if (!allowed(*u, 0, s) || (durative && !allowed(*u, 1, post))) continue;
      if (ends && !allowed(*u, 2, post)) continue;
      if (!ends && post == kNoValue) continue;
      plan.sources[u].push_back(s);
    }
    if (plan.sources[u].empty()) return std::nullopt;
  }
  return plan;
}

// Guard atoms for what the action reads of a variable it does not change, at start (first 0,
// last 1) or at its end (2, 2).
std::vector<std::string> Writer::Reads(const VarUse& u, int first, int last, std::size_t x) {
  int v = VarIndex(u.var);
  std::vector<std::string> atoms;
  std::set<std::string> done;
  for (int w = first; w <= last; ++w) {
    if (u.need[w] && done.insert("+" + *u.need[w]).second) atoms.push_back(Accept(v, *u.need[w], "i"));
    for (const auto& f : u.forbid[w])
      if (done.insert("-" + f).second) atoms.push_back(Refuse(v, f, "i"));
  }
  if (first == 0 && (u.need[1] || !u.forbid[1].empty())) over_all_[x].emplace_back(v, &u);
  return atoms;
}

void Writer::WriteAction(std::size_t x) {
  auto plan = MakePlan(x);
  if (!plan) return;
  const GroundAction& ga = g_.actions[x];
  bool durative = d_.actions[ga.action].durative;
  auto ends = [&](const VarUse* u) {
    return std::count(plan->at_end.begin(), plan->at_end.end(), u) > 0;
  };
  timing_[x] = durative ? VarIndex(plan->at_end[0]->var) : VarIndex(plan->changed[0]->var);
  // Start: every changed variable's command and source, every read variable's command and value.
  std::vector<std::string> start;
  std::map<const VarUse*, std::string> source_atom;
  for (const VarUse* u : plan->changed) {
    int v = VarIndex(u->var);
    Command(v, x);
    touches_[x].insert(v);
    std::vector<int> locs;
    for (const auto& s : plan->sources[u]) locs.push_back(LocOf(v, s, ""));
    source_atom[u] = InLocs(v, locs, "i");
  }
  for (const VarUse* u : plan->read_start) {
    int v = VarIndex(u->var);
    Command(v, x);
    start.push_back(automaton_[v] + "u[i]==" + cmd_[x]);
    for (auto& a : Reads(*u, 0, 1, x)) start.push_back(a);
  }
  for (const VarUse* u : plan->changed)
    if (durative && !ends(u) && (u->need[1] || !u->forbid[1].empty()))
      over_all_[x].emplace_back(VarIndex(u->var), u);
  std::map<const VarUse*, std::vector<int>> steps;
  for (const VarUse* u : plan->changed) {
    int v = VarIndex(u->var);
    std::vector<std::string> guard{automaton_[v] + "u[i]==" + cmd_[x]};
    for (const VarUse* o : plan->changed)
      if (o != u) {
        guard.push_back(automaton_[VarIndex(o->var)] + "u[i]==" + cmd_[x]);
        guard.push_back(source_atom[o]);
      }
    guard.insert(guard.end(), start.begin(), start.end());
    std::set<std::string> posts;
    for (const auto& s : plan->sources[u]) posts.insert(u->eff_start.value_or(s));
    for (const auto& s : plan->sources[u]) {
      std::string post = u->eff_start.value_or(s);
      std::string step = posts.size() == 1 ? cmd_[x] : cmd_[x] + "_" + ValueName(u->var, post);
      int to = ends(u) ? LocOf(v, post, step) : LocOf(v, post, "");
      if (ends(u) && std::find(steps[u].begin(), steps[u].end(), to) == steps[u].end())
        steps[u].push_back(to);
      int from = LocOf(v, s, "");
      if (from == to) continue;
      int cost = v == timing_[x] ? (durative ? 1 : 2) : 0;
      trans_.push_back(Trans{v, from, to, guard, std::nullopt, cost, static_cast<int>(x)});
    }
  }
  if (!durative) return;
  timing_steps_[x] = steps[plan->at_end[0]];
  // End: every variable with a step leaves it together, the duration after the start.
  std::vector<std::string> end;
  for (const VarUse* u : plan->read_end) {
    int v = VarIndex(u->var);
    Command(v, x);
    end.push_back(automaton_[v] + "u[i]==" + cmd_[x]);
    for (auto& a : Reads(*u, 2, 2, x)) end.push_back(a);
  }
  for (const VarUse* u : plan->at_end) {
    int v = VarIndex(u->var);
    std::vector<std::string> guard{automaton_[v] + "u[i]==" + cmd_[x]};
    for (const VarUse* o : plan->at_end)
      if (o != u) {
        int ov = VarIndex(o->var);
        guard.push_back(automaton_[ov] + "u[i]==" + cmd_[x]);
        guard.push_back(InLocs(ov, steps[o], "i"));
      }
    guard.insert(guard.end(), end.begin(), end.end());
    for (int from : steps[u]) {
      const std::string& post = locs_[v][from].value;
      int to = LocOf(v, u->eff_end.value_or(post), "");
      int cost = v == timing_[x] ? 1 : 0;
      trans_.push_back(Trans{v, from, to, guard, std::make_pair(ga.lo, ga.hi), cost,
                             static_cast<int>(x)});
    }
  }
}

// A timed initial literal's atom: one location per stretch of time with one value, left
// automatically at the next literal's time.
void Writer::Timelines() {
  for (std::size_t i = 0; i < g_.variables.size(); ++i) {
    const Variable& var = g_.variables[i];
    if (var.timeline.empty()) continue;
    std::string value = *var.initial;
    double since = 0;
    locs_[i].push_back(Loc{loc_names_[i].Take(ValueName(var.key, value)), value});
    for (const auto& [t, v] : var.timeline) {
      if (v == value) continue;
      std::string when = Duration(t).dump();
      std::replace(when.begin(), when.end(), '.', '_');
      locs_[i].push_back(Loc{loc_names_[i].Take(ValueName(var.key, v) + "_at_" + when), v});
      int to = static_cast<int>(locs_[i].size()) - 1;
      trans_.push_back(Trans{static_cast<int>(i), to - 1, to, {},
                             std::make_pair(t - since, std::optional<double>(t - since)), 0, -1});
      value = v;
      since = t;
    }
  }
}

// Over-all conditions hold throughout: while X runs (its timing variable in one of its steps),
// no other action's transition takes the variable X reads out of the value X needs (or into the
// value it forbids). Left out where that action changes X's timing variable itself.
void Writer::Protect() {
  for (std::size_t x = 0; x < g_.actions.size(); ++x) {
    if (timing_steps_[x].empty()) continue;
    int m = timing_[x];
    std::vector<std::string> idle;
    for (int k : timing_steps_[x]) idle.push_back(automaton_[m] + "l[i]!=" + locs_[m][k].name);
    for (const auto& [v, u] : over_all_[x]) {
      for (auto& t : trans_) {
        if (t.var != v || t.action < 0 || t.action == static_cast<int>(x)) continue;
        if (touches_[t.action].count(m)) continue;
        const std::string& from = locs_[v][t.from].value;
        const std::string& to = locs_[v][t.to].value;
        bool breaks = u->need[1] && from == *u->need[1] && to != *u->need[1];
        for (const auto& f : u->forbid[1]) breaks = breaks || (to == f && from != f);
        if (breaks) t.guard.insert(t.guard.end(), idle.begin(), idle.end());
      }
    }
  }
}

Json Writer::Automata() const {
  std::vector<Json> automata;
  for (std::size_t i = 0; i < g_.variables.size(); ++i) {
    Json locations = Json::array();
    for (const auto& l : locs_[i]) locations.push_back(l.name);
    automata.push_back({{"name", automaton_[i]},
                        {"locations", locations},
                        {"transitions", Json::array()}});
    if (!commands_[i].empty()) automata.back()["commands"] = commands_[i];
  }
  for (const auto& t : trans_) {
    Json j = {{"from", locs_[t.var][t.from].name}, {"to", locs_[t.var][t.to].name}};
    if (!t.guard.empty()) j["guard"] = Join(t.guard, " /\\ ");
    if (t.duration)
      j["duration"] = {Duration(t.duration->first),
                       t.duration->second ? Duration(*t.duration->second) : Json()};
    j["cost"] = t.cost;
    automata[t.var]["transitions"].push_back(std::move(j));
  }
  return automata;
}

// Every action has ended: no variable in a step location (shorter of the two ways to say it).
std::string Writer::Unfinished() const {
  std::vector<std::string> parts;
  for (std::size_t v = 0; v < locs_.size(); ++v) {
    std::vector<std::string> in, out;
    for (const auto& l : locs_[v]) {
      (l.step ? out : in).push_back(automaton_[v] + "l[i+1]" + (l.step ? "!=" : "==") + l.name);
    }
    if (out.empty()) continue;
    if (out.size() <= in.size() || in.size() <= 1)
      parts.push_back(in.size() == 1 && out.size() > 1 ? in[0] : Join(out, " /\\ "));
    else
      parts.push_back("(" + Join(in, " \\/ ") + ")");
  }
  return Join(parts, " /\\ ");
}

// An automaton is named from its object when the object has no other state variable, and so are
// the other automata of its group (robot1, robot2); else object_group (arm1_busy, arm2_busy);
// a 0-ary group by its name, a boolean atom of several objects as pred_a_b.
void Writer::NameAutomata() {
  std::map<std::vector<std::string>, int> per_owner;
  for (const auto& v : g_.variables) ++per_owner[v.key.owner];
  std::set<int> shared;  // groups with an owner that has several variables
  for (const auto& v : g_.variables)
    if (v.key.owner.size() != 1 || per_owner[v.key.owner] > 1) shared.insert(v.key.group);
  NameSet vars;
  for (const auto& v : g_.variables) {
    const Group& grp = sv_.groups[v.key.group];
    std::string base;
    if (v.key.owner.size() == 1)
      base = shared.count(v.key.group) ? v.key.owner[0] + "_" + grp.name : v.key.owner[0];
    else if (v.key.owner.empty())
      base = grp.name;
    else  // a boolean atom of several objects: connected_a_b
      base = grp.name + "_" + Join(v.key.owner, "_");
    base = Identifier(base);
    // The automaton's variables X, Xl and Xu must not meet another's.
    std::string n = base;
    for (int k = 2; vars.Has(n) || vars.Has(n + "l") || vars.Has(n + "u"); ++k)
      n = base + "_" + std::to_string(k);
    for (const std::string& x : {n, n + "l", n + "u"}) vars.Reserve(x);
    automaton_.push_back(n);
  }
}

std::string Writer::ValueName(const VarKey& k, const std::string& value) const {
  if (value == kNoValue) return "none";
  const Group& grp = sv_.groups[k.group];
  if (grp.boolean)
    return value.rfind("not ", 0) == 0 ? Identifier("not_" + value.substr(4)) : Identifier(value);
  std::vector<std::string> parts = Split(value);  // pred, then the arguments after the owner
  if (grp.preds.size() == 1 && parts.size() == 2) return Identifier(parts[1]);
  return Identifier(Join(parts, "_"));
}

// The coarsest time resolution (1, 0.1, ..., 0.000001 s) that every duration is a multiple of.
std::optional<double> Writer::Resolution() {
  for (int k = 0; k <= 6; ++k) {
    double scale = std::pow(10.0, k);
    bool all = true;
    auto fits = [&](double v) { return std::fabs(v * scale - std::round(v * scale)) < 1e-6; };
    for (const auto& ga : g_.actions) all = all && fits(ga.lo) && fits(ga.hi.value_or(0));
    for (const auto& var : g_.variables)
      for (const auto& [t, value] : var.timeline) all = all && fits(t);
    if (all) return 1.0 / scale;
  }
  for (const auto& ga : g_.actions) {
    issues_.push_back(Issue{d_.file, d_.actions[ga.action].pos.line,
                            d_.actions[ga.action].pos.column, d_.actions[ga.action].name,
                            "durations finer than a microsecond cannot be mapped"});
    break;
  }
  return std::nullopt;
}

Json Writer::Duration(double v) const {
  double ticks = std::round(v / resolution_);
  if (resolution_ == 1.0) return static_cast<long long>(ticks);
  return ticks * resolution_;
}

std::optional<std::string> Writer::GoalText(const Goal& goal) {
  auto join = [&](const char* op, const char* empty) -> std::optional<std::string> {
    if (goal.kids.empty()) return std::string(empty);
    std::vector<std::string> parts;
    for (const auto& k : goal.kids) {
      auto t = GoalText(k);
      if (!t) return std::nullopt;
      parts.push_back(*t);
    }
    return parts.size() == 1 ? parts[0] : "(" + Join(parts, op) + ")";
  };
  switch (goal.kind) {
    case Goal::Kind::kAnd:
      return join(" /\\ ", "true");
    case Goal::Kind::kOr:
      return join(" \\/ ", "false");
    case Goal::Kind::kImply:
      return join(" -> ", "true");
    case Goal::Kind::kNot: {
      auto t = GoalText(goal.kids[0]);
      if (!t) return std::nullopt;
      return "(not " + *t + ")";
    }
    case Goal::Kind::kLiteral:
      break;
  }
  const ::ctb::pddl::Atom& a = goal.lit.atom;
  for (const auto& x : a.args) {
    if (std::find(g_.objects.begin(), g_.objects.end(), x) == g_.objects.end()) {
      issues_.push_back(Issue{p_->file, a.pos.line, a.pos.column, "",
                              "goal " + goal.lit.text + ": unknown object '" + x + "'"});
      return std::nullopt;
    }
  }
  const Signature* s = a.equality ? nullptr : d_.Predicate(a.pred);
  if (!a.equality && (!s || s->params.size() != a.args.size())) {
    issues_.push_back(Issue{p_->file, a.pos.line, a.pos.column, "",
                            "goal " + goal.lit.text + ": unknown predicate or wrong arity"});
    return std::nullopt;
  }
  auto constant = [&](bool truth) {
    return std::string(truth == goal.lit.positive ? "true" : "false");
  };
  if (a.equality) return constant(a.args[0] == a.args[1]);
  auto loc = g_.Locate(sv_, a);
  if (!loc) return constant(g_.facts.count(GroundKey(a.pred, a.args)) > 0);
  int v = VarIndex(loc->first);
  if (v < 0) return constant(false);  // never reached
  return goal.lit.positive ? Accept(v, loc->second, "i+1") : Refuse(v, loc->second, "i+1");
}

std::optional<Written> Writer::Run() {
  if (g_.variables.empty()) {
    issues_.push_back(Issue{d_.file, 0, 0, "",
                            "nothing to import: no action applies to any "
                            "object and no state variable has a value"});
    return std::nullopt;
  }
  for (std::size_t i = 0; i < g_.variables.size(); ++i)
    var_index_[g_.variables[i].key] = static_cast<int>(i);
  NameAutomata();
  auto res = Resolution();
  if (!res) return std::nullopt;
  resolution_ = *res;
  BaseLocations();
  NameSet commands;
  for (const auto& ga : g_.actions)
    cmd_.push_back(commands.Take(Identifier(d_.actions[ga.action].name +
                                            (ga.args.empty() ? "" : "_" + Join(ga.args, "_")))));
  std::size_t n = g_.actions.size();
  timing_.assign(n, -1);
  timing_steps_.resize(n);
  over_all_.resize(n);
  touches_.resize(n);
  for (std::size_t x = 0; x < n; ++x) WriteAction(x);
  Timelines();
  Protect();
  Written w;
  std::string desc = "Imported from the PDDL domain '" + d_.name + "'";
  if (p_) desc += " with the objects of problem '" + p_->name + "'";
  w.domain = {{"name", o_.name.empty() ? Identifier(d_.name) : o_.name}, {"description", desc}};
  if (resolution_ != 1.0) w.domain["time_resolution"] = resolution_;
  w.domain["automata"] = Automata();
  if (!p_) return w;
  Json initial = Json::object();
  for (std::size_t i = 0; i < g_.variables.size(); ++i)
    initial[automaton_[i]] = locs_[i][g_.variables[i].timeline.empty()
                                          ? LocOf(static_cast<int>(i), *g_.variables[i].initial, "")
                                          : 0]
                                 .name;
  auto goal = GoalText(*p_->goal);
  if (!goal) return std::nullopt;
  std::string ended = Unfinished();
  if (!ended.empty()) *goal = *goal == "true" ? ended : "(" + *goal + ") /\\ " + ended;
  w.state_plan = {{"initial_state", initial},
                  {"end_state", {{"maintenance_constraint", "true"}, {"goal_constraint", *goal}}}};
  if (p_->minimize_total_time) w.state_plan["objective"] = "makespan";
  return w;
}

}  // namespace

std::optional<Written> WriteModel(const DomainAst& d, const StateVars& sv, const Grounded& g,
                                  const ProblemAst* p, const ImportOptions& options,
                                  std::vector<Issue>& issues) {
  return Writer(d, sv, g, p, options, issues).Run();
}

}  // namespace ctb::pddl
