// Writing the ground model: one automaton per state variable, a command location chain per
// durative action, guards from the conditions, and guards that protect over-all conditions.
#include "interchange/pddl/internal/writer.h"

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
  int VarIndex(const VarKey& k) const {
    auto it = var_index_.find(k);
    return it == var_index_.end() ? -1 : it->second;
  }
  void Index();
  void NameAutomata();
  std::string ValueName(const VarKey& k, const std::string& value) const;
  void NameLocations();
  std::string Atom(int var, const std::string& value, bool equal, const std::string& index) const;
  std::string Guard(std::size_t action) const;
  void Protect();
  std::optional<double> Resolution();
  Json Duration(double v) const;
  Json Automata();
  std::optional<std::string> GoalText(const Goal& goal);

  const DomainAst& d_;
  const StateVars& sv_;
  const Grounded& g_;
  const ProblemAst* p_;
  const ImportOptions& o_;
  std::vector<Issue>& issues_;
  std::vector<std::string> automaton_;                        // per variable
  std::vector<std::map<std::string, std::string>> location_;  // per variable: value -> name
  std::vector<std::string> step_;                  // per ground action: timed location and command
  std::vector<int> var_of_;                        // per ground action
  std::vector<std::vector<std::string>> protect_;  // per ground action: extra guard atoms
  std::map<VarKey, int> var_index_;
  // Ground actions by (variable, value they leave) and (variable, value they enter).
  std::map<std::pair<int, std::string>, std::vector<std::size_t>> leaving_, entering_;
  double resolution_ = 1;
};

void Writer::Index() {
  for (std::size_t i = 0; i < g_.variables.size(); ++i)
    var_index_[g_.variables[i].key] = static_cast<int>(i);
  for (std::size_t a = 0; a < g_.actions.size(); ++a) {
    int v = VarIndex(g_.actions[a].var);
    leaving_[{v, g_.actions[a].from}].push_back(a);
    entering_[{v, g_.actions[a].to}].push_back(a);
  }
}

const std::vector<std::size_t>& Lookup(
    const std::map<std::pair<int, std::string>, std::vector<std::size_t>>& m, int v,
    const std::string& value) {
  static const std::vector<std::size_t> kNone;
  auto it = m.find({v, value});
  return it == m.end() ? kNone : it->second;
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
  const Group& grp = sv_.groups[k.group];
  if (grp.boolean)
    return value.rfind("not ", 0) == 0 ? Identifier("not_" + value.substr(4)) : Identifier(value);
  std::vector<std::string> parts = Split(value);  // pred, then the arguments after the owner
  if (grp.preds.size() == 1 && parts.size() == 2) return Identifier(parts[1]);
  return Identifier(Join(parts, "_"));
}

void Writer::NameLocations() {
  location_.resize(g_.variables.size());
  std::vector<NameSet> used(g_.variables.size());
  for (std::size_t i = 0; i < g_.variables.size(); ++i)
    for (const auto& v : g_.variables[i].values)
      location_[i][v] = used[i].Take(ValueName(g_.variables[i].key, v));
  std::vector<NameSet> commands(g_.variables.size());
  for (const auto& ga : g_.actions) {
    int v = VarIndex(ga.var);
    var_of_.push_back(v);
    std::string base =
        Identifier(d_.actions[ga.action].name + (ga.args.empty() ? "" : "_" + Join(ga.args, "_")));
    std::string n = base;
    for (int k = 2; used[v].Has(n) || commands[v].Has(n); ++k) n = base + "_" + std::to_string(k);
    if (d_.actions[ga.action].durative) used[v].Reserve(n);
    commands[v].Reserve(n);
    step_.push_back(n);
  }
}

std::string Writer::Atom(int var, const std::string& value, bool equal,
                         const std::string& index) const {
  return automaton_[var] + "l[" + index + "]" + (equal ? "==" : "!=") + location_[var].at(value);
}

// Over-all conditions hold throughout: while X runs (in its timed location), the variable it
// reads may not leave the value it needs (nor enter the value it forbids).
void Writer::Protect() {
  protect_.resize(g_.actions.size());
  for (std::size_t x = 0; x < g_.actions.size(); ++x) {
    const GroundAction& ga = g_.actions[x];
    if (!d_.actions[ga.action].durative) continue;
    std::string running = automaton_[var_of_[x]] + "l[i]!=" + step_[x];
    for (const auto& c : ga.conditions) {
      if (!c.over_all) continue;
      int v = VarIndex(c.var);
      for (std::size_t y : Lookup(c.positive ? leaving_ : entering_, v, c.value)) {
        const GroundAction& gy = g_.actions[y];
        // Needless when y needs X's variable at a value: X running is at none.
        bool blocked = false;
        for (const auto& yc : gy.conditions) blocked = blocked || (yc.positive && yc.var == ga.var);
        if (!blocked) protect_[y].push_back(running);
      }
    }
  }
}

std::string Writer::Guard(std::size_t a) const {
  const GroundAction& ga = g_.actions[a];
  std::vector<std::string> atoms{automaton_[var_of_[a]] + "u[i]==" + step_[a]};
  for (const auto& c : ga.conditions) {
    int v = VarIndex(c.var);
    atoms.push_back(Atom(v, c.value, c.positive, "i"));
    if (c.positive || !c.over_all) continue;
    // Not heading for the forbidden value either: no action on v that ends in it is running.
    for (std::size_t y : Lookup(entering_, v, c.value))
      if (d_.actions[g_.actions[y].action].durative)
        atoms.push_back(automaton_[v] + "l[i]!=" + step_[y]);
  }
  for (const auto& p : protect_[a]) atoms.push_back(p);
  return Join(atoms, " /\\ ");
}

// The coarsest time resolution (1, 0.1, ..., 0.000001 s) that every duration is a multiple of.
std::optional<double> Writer::Resolution() {
  for (int k = 0; k <= 6; ++k) {
    double scale = std::pow(10.0, k);
    bool all = true;
    for (const auto& ga : g_.actions) {
      for (double v : {ga.lo, ga.hi.value_or(0)}) {
        double q = v * scale;
        all = all && std::fabs(q - std::round(q)) < 1e-6;
      }
    }
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

Json Writer::Automata() {
  std::vector<Json> automata;
  for (std::size_t i = 0; i < g_.variables.size(); ++i) {
    Json locations = Json::array();
    for (const auto& v : g_.variables[i].values) locations.push_back(location_[i].at(v));
    automata.push_back({{"name", automaton_[i]},
                        {"locations", locations},
                        {"commands", Json::array()},
                        {"transitions", Json::array()}});
  }
  for (std::size_t a = 0; a < g_.actions.size(); ++a) {
    const GroundAction& ga = g_.actions[a];
    int v = var_of_[a];
    Json& au = automata[v];
    const std::string& from = location_[v].at(ga.from);
    const std::string& to = location_[v].at(ga.to);
    bool durative = d_.actions[ga.action].durative;
    if (!durative && from == to) continue;  // an instantaneous action that changes nothing
    au["commands"].push_back(step_[a]);
    if (!durative) {
      au["transitions"].push_back({{"from", from}, {"to", to}, {"guard", Guard(a)}, {"cost", 2}});
      continue;
    }
    au["locations"].push_back(step_[a]);
    au["transitions"].push_back({{"from", from}, {"to", step_[a]}, {"guard", Guard(a)}});
    Json t = {{"from", step_[a]},
              {"to", to},
              {"duration", {Duration(ga.lo), ga.hi ? Duration(*ga.hi) : Json()}}};
    if (!ga.hi || *ga.hi != ga.lo) t["controllable"] = true;
    au["transitions"].push_back(std::move(t));
  }
  for (auto& au : automata)
    if (au["commands"].empty()) au.erase("commands");
  return automata;
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
  if (v < 0 || !location_[v].count(loc->second)) return constant(false);  // never reached
  return Atom(v, loc->second, goal.lit.positive, "i+1");
}

std::optional<Written> Writer::Run() {
  if (g_.variables.empty()) {
    issues_.push_back(Issue{d_.file, 0, 0, "",
                            "nothing to import: no action applies to any "
                            "object and no state variable has a value"});
    return std::nullopt;
  }
  Index();
  NameAutomata();
  NameLocations();
  Protect();
  auto res = Resolution();
  if (!res) return std::nullopt;
  resolution_ = *res;
  Written w;
  std::string desc = "Imported from the PDDL domain '" + d_.name + "'";
  if (p_) desc += " with the objects of problem '" + p_->name + "'";
  w.domain = {{"name", o_.name.empty() ? Identifier(d_.name) : o_.name}, {"description", desc}};
  if (resolution_ != 1.0) w.domain["time_resolution"] = resolution_;
  w.domain["automata"] = Automata();
  if (!p_) return w;
  Json initial = Json::object();
  for (std::size_t i = 0; i < g_.variables.size(); ++i)
    initial[automaton_[i]] = location_[i].at(*g_.variables[i].initial);
  auto goal = GoalText(*p_->goal);
  if (!goal) return std::nullopt;
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
