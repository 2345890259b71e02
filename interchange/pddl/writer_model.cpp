// The model around the compiled actions: timed initial literals, protections of over-all
// conditions, "run" automata (an action's timing automaton busy or idle, where listing its step
// locations would be too long), the goal with "no action still runs", names and the JSON.
#include <algorithm>
#include <cmath>

#include "interchange/pddl/internal/writer_impl.h"
#include "planner/model/domain.h"

namespace ctb::pddl {
namespace writer_impl {

// A timed initial literal's atom: its locations (BaseLocations) are stretches of time, each left
// automatically at the next literal's time.
void Writer::Timelines() {
  for (std::size_t i = 0; i < g_.variables.size(); ++i) {
    const Variable& var = g_.variables[i];
    std::string value = var.initial.value_or("");
    double since = 0;
    int at = 0;
    for (const auto& [t, v] : var.timeline) {
      if (v == value) continue;
      trans_.push_back(Trans{static_cast<int>(i),
                             at,
                             at + 1,
                             {},
                             std::make_pair(t - since, std::optional<double>(t - since)),
                             0,
                             -1});
      ++at;
      value = v;
      since = t;
    }
  }
}

// Over-all conditions hold throughout: while X runs (its timing automaton in one of its steps), no
// other action's transition takes the variable X reads out of the value X needs (or into the value
// it forbids). Left out where that action changes X's timing automaton itself. Collected per
// transition as timing automaton -> X's steps; written by ProtectText.
void Writer::Protect() {
  protect_.assign(trans_.size(), {});
  std::map<int, std::vector<std::size_t>> by_var;
  for (std::size_t k = 0; k < trans_.size(); ++k)
    if (trans_[k].action >= 0) by_var[trans_[k].var].push_back(k);
  for (std::size_t x = 0; x < g_.actions.size(); ++x) {
    if (timing_steps_[x].empty()) continue;
    int m = timing_[x];
    for (const auto& [v, u] : over_all_[x]) {
      for (std::size_t k : by_var[v]) {
        const Trans& t = trans_[k];
        if (t.action == static_cast<int>(x) || touches_[t.action].count(m)) continue;
        const std::string& from = locs_[v][t.from].value;
        const std::string& to = locs_[v][t.to].value;
        bool breaks = u->need[1] && from == *u->need[1] && to != *u->need[1];
        for (const auto& f : u->forbid[1]) breaks = breaks || (to == f && from != f);
        if (breaks) protect_[k][m].insert(timing_steps_[x].begin(), timing_steps_[x].end());
      }
    }
  }
}

// The protection of one transition: per timing automaton, "not in any of these steps", or with
// `coarse` (where that list is too long) "its run automaton is idle" for those that have one.
std::string Writer::ProtectText(const std::map<int, std::set<int>>& running, bool coarse) const {
  std::vector<std::string> atoms;
  for (const auto& [m, steps] : running) {
    if (coarse && run_[m] >= 0) {
      atoms.push_back(automaton_[run_[m]] + "l[i]==idle");
      continue;
    }
    for (int k : steps) atoms.push_back(automaton_[m] + "l[i]!=" + locs_[m][k].name);
  }
  return Join(atoms, " /\\ ");
}

// The protections written into the guards: exact where short enough, else coarse (a run automaton
// per timing automaton named, created first); a run automaton's copy of a transition gets the same
// protection.
void Writer::WriteProtections() {
  std::vector<bool> coarse(protect_.size(), false);
  for (std::size_t k = 0; k < protect_.size(); ++k) {
    if (protect_[k].empty() || ProtectText(protect_[k], false).size() <= kExactProtection) continue;
    coarse[k] = true;
    ++coarse_;
    for (const auto& [m, steps] : protect_[k]) AddRun(m);
  }
  std::vector<std::vector<std::size_t>> copies(protect_.size());
  for (std::size_t k = protect_.size(); k < trans_.size(); ++k)
    if (trans_[k].copy_of >= 0) copies[trans_[k].copy_of].push_back(k);
  std::vector<std::string> text(protect_.size());
  for (std::size_t k = 0; k < protect_.size(); ++k) {
    if (protect_[k].empty()) continue;
    text[k] = ProtectText(protect_[k], coarse[k]);
    trans_[k].guard.push_back(text[k]);
    for (std::size_t c : copies[k]) trans_[c].guard.push_back(text[k]);
  }
  ProtectPartners(text);
}

// A protected transition holds back the whole event of its action, not only its own automaton:
// every other transition of that event (its partners, and their run automata's copies) gets "the
// protected automaton is not where its transition would break the condition, or the protection
// holds". Without it the partners moved on the command while the protected automaton stayed (an
// action half applied, which PDDL 2.1 does not allow: a plan that was not one).
void Writer::ProtectPartners(const std::vector<std::string>& text) {
  std::map<std::pair<int, bool>, std::vector<std::size_t>> events;  // (action, start)
  std::vector<std::vector<std::size_t>> copies(trans_.size());
  for (std::size_t k = 0; k < trans_.size(); ++k) {
    const Trans& t = trans_[k];
    if (t.copy_of >= 0) copies[t.copy_of].push_back(k);
    else if (t.action >= 0) events[{t.action, t.start}].push_back(k);
  }
  for (const auto& [event, members] : events) {
    // Per protected variable and protection: the locations it breaks the condition from.
    std::map<std::pair<int, std::string>, std::set<int>> held;
    for (std::size_t k : members)
      if (k < text.size() && !text[k].empty()) held[{trans_[k].var, text[k]}].insert(trans_[k].from);
    for (const auto& [key, froms] : held) {
      const auto& [v, protection] = key;
      auto src = event_sources_.find({event.first, v, event.second});
      bool all = src != event_sources_.end() &&
                 std::all_of(src->second.begin(), src->second.end(),
                             [&](int l) { return froms.count(l) > 0; });
      std::string atom = "(" + protection + ")";
      if (!all) {
        std::vector<std::string> away;
        for (int l : froms) away.push_back(automaton_[v] + "l[i]!=" + locs_[v][l].name);
        atom = "((" + Join(away, " /\\ ") + ") \\/ (" + protection + "))";
      }
      for (std::size_t p : members) {
        if (trans_[p].var == v) continue;
        trans_[p].guard.push_back(atom);
        for (std::size_t c : copies[p]) trans_[c].guard.push_back(atom);
      }
    }
  }
}

// A run automaton of m (idle, busy): busy from the start to the end of every action that m times,
// on the same commands and under the same guards as m's own transitions.
void Writer::AddRun(int m) {
  if (run_[m] >= 0) return;
  int r = static_cast<int>(automaton_.size());
  run_[m] = r;
  run_.push_back(-1);
  // Short names (run_1, run_2, ...): the goal names every one of them.
  std::string base = "run_" + std::to_string(r - static_cast<int>(g_.variables.size()) + 1);
  std::string n = base;
  for (int k = 2;
       automaton_names_.Has(n) || automaton_names_.Has(n + "l") || automaton_names_.Has(n + "u");
       ++k)
    n = base + "_" + std::to_string(k);
  for (const std::string& x : {n, n + "l", n + "u"}) automaton_names_.Reserve(x);
  automaton_.push_back(n);
  locs_.push_back({Loc{"idle", "", false}, Loc{"busy", "", false}});
  loc_names_.emplace_back();
  commands_.emplace_back();
  std::size_t count = trans_.size();
  for (std::size_t k = 0; k < count; ++k) {
    Trans t = trans_[k];
    if (t.var != m || t.action < 0 || timing_[t.action] != m || timing_steps_[t.action].empty())
      continue;
    const std::string& cmd = cmd_[t.action];
    trans_[k].guard.push_back(n + "u[i]==" + cmd);
    Command(r, t.action);
    t.guard.push_back(automaton_[m] + "l[i]==" + locs_[m][t.from].name);
    t.guard.push_back(n + "u[i]==" + cmd);
    t.var = r;
    t.from = t.start ? 0 : 1;
    t.to = t.start ? 1 : 0;
    t.cost = 0;
    t.copy_of = static_cast<int>(k);
    trans_.push_back(std::move(t));
  }
}

Json Writer::Automata() {
  std::vector<Json> automata;
  for (std::size_t i = 0; i < automaton_.size(); ++i) {
    Json locations = Json::array();
    for (const auto& l : locs_[i]) locations.push_back(l.name);
    automata.push_back(
        {{"name", automaton_[i]}, {"locations", locations}, {"transitions", Json::array()}});
    if (!commands_[i].empty()) automata.back()["commands"] = commands_[i];
  }
  for (const auto& t : trans_) {
    Json j = {{"from", locs_[t.var][t.from].name}, {"to", locs_[t.var][t.to].name}};
    std::vector<std::string> guard;
    for (const auto& a : t.guard) guard.push_back(Expand(a));
    if (!guard.empty()) j["guard"] = Join(guard, " /\\ ");
    if (t.duration)
      j["duration"] = {Duration(t.duration->first),
                       t.duration->second ? Duration(*t.duration->second) : Json()};
    j["cost"] = t.cost;
    automata[t.var]["transitions"].push_back(std::move(j));
  }
  return automata;
}

// Every action has ended: no timing automaton in a step location (a durative action's other
// automata leave their steps with it). Per automaton the shorter list (its steps excluded, or its
// other locations included); while the whole is longer than `budget`, the longest lists become "its
// run automaton is idle".
std::string Writer::Unfinished(std::size_t budget) {
  std::set<int> timing;
  for (std::size_t x = 0; x < g_.actions.size(); ++x)
    if (!timing_steps_[x].empty()) timing.insert(timing_[x]);
  std::map<int, std::string> parts;
  std::size_t total = 0;
  for (int m : timing) {
    std::vector<std::string> in, out;
    for (const auto& l : locs_[m])
      (l.step ? out : in).push_back(automaton_[m] + "l[i+1]" + (l.step ? "!=" : "==") + l.name);
    if (out.size() <= in.size() || in.size() <= 1)
      parts[m] = in.size() == 1 && out.size() > 1 ? in[0] : Join(out, " /\\ ");
    else
      parts[m] = "(" + Join(in, " \\/ ") + ")";
    total += parts[m].size() + 4;
  }
  std::vector<std::pair<std::size_t, int>> longest;
  for (const auto& [m, text] : parts) longest.emplace_back(text.size(), m);
  std::sort(longest.rbegin(), longest.rend());
  for (const auto& [size, m] : longest) {
    if (total <= budget) break;
    AddRun(m);
    parts[m] = automaton_[run_[m]] + "l[i+1]==idle";
    total = total - size + parts[m].size();
  }
  std::vector<std::string> all;
  for (const auto& [m, text] : parts) all.push_back(text);
  return Join(all, " /\\ ");
}

// An automaton is named from its object when the object has no other state variable, and so are the
// other automata of its group (robot1, robot2); else object_group (arm1_busy, arm2_busy); a 0-ary
// group by its name, a boolean atom of several objects as pred_a_b.
void Writer::NameAutomata() {
  std::map<std::vector<std::string>, int> per_owner;
  for (const auto& v : g_.variables) ++per_owner[v.key.owner];
  std::set<int> shared;  // groups with an owner that has several variables
  for (const auto& v : g_.variables)
    if (v.key.owner.size() != 1 || per_owner[v.key.owner] > 1) shared.insert(v.key.group);
  NameSet& vars = automaton_names_;
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

// The coarsest time resolution (1, 0.1, 0.01 or 0.001 s) that every duration and timed literal is a
// multiple of; finer ones (IPC durations computed by '/') are rounded to 0.001 s, with a warning
// naming the first action (or literal) rounded.
double Writer::Resolution() {
  auto fits = [](double v, double scale) {
    return std::fabs(v * scale - std::round(v * scale)) < 1e-6;
  };
  for (int k = 0; k <= 3; ++k) {
    double scale = std::pow(10.0, k);
    bool all = true;
    for (const auto& ga : g_.actions)
      all = all && fits(ga.lo, scale) && fits(ga.hi.value_or(0), scale);
    for (const auto& var : g_.variables)
      for (const auto& [t, value] : var.timeline) all = all && fits(t, scale);
    if (all) return 1.0 / scale;
  }
  std::size_t rounded = 0;
  const GroundAction* first = nullptr;
  for (const auto& ga : g_.actions)
    if (!fits(ga.lo, 1000) || !fits(ga.hi.value_or(0), 1000)) {
      ++rounded;
      if (!first) first = &ga;
    }
  std::string what = std::to_string(rounded) + " ground action(s)";
  Issue w{d_.file, 0, 0, "", ""};
  if (first) {
    const Action& a = d_.actions[first->action];
    w = Issue{d_.file, a.pos.line, a.pos.column, a.name, ""};
  }
  w.message = "durations finer than 0.001 s (" + what + ", or timed literals) are rounded to " +
              "the time resolution 0.001 s";
  warnings_.push_back(w);
  return 0.001;
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
  // The goal also requires that no action runs, so no automaton is in a step location.
  return Expand(goal.lit.positive ? Accept(v, loc->second, "i+1", true)
                                  : Refuse(v, loc->second, "i+1", true));
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
  run_.assign(g_.variables.size(), -1);
  resolution_ = Resolution();
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
  std::optional<std::string> goal = p_ ? GoalText(*p_->goal) : std::optional<std::string>("");
  if (!goal) return std::nullopt;
  std::size_t limit = kMaxExpressionChars - std::min(kMaxExpressionChars, goal->size() + 64);
  std::string ended = p_ ? Unfinished(limit) : "";
  WriteProtections();
  Written w;
  if (coarse_ > 0)
    warnings_.push_back(Issue{d_.file, 0, 0, "",
                              std::to_string(coarse_) +
                                  " transition(s) protect over-all conditions coarsely (waiting "
                                  "while the reading action's timing automaton runs any action): "
                                  "the exact list would be too long"});
  std::string desc = "Imported from the PDDL domain '" + d_.name + "'";
  if (p_) desc += " with the objects of problem '" + p_->name + "'";
  w.domain = {{"name", o_.name.empty() ? Identifier(d_.name) : o_.name}, {"description", desc}};
  if (resolution_ != 1.0) w.domain["time_resolution"] = resolution_;
  w.domain["automata"] = Automata();
  if (coarse_reads_ > 0)
    warnings_.push_back(Issue{d_.file, 0, 0, "",
                              std::to_string(coarse_reads_) +
                                  " guard read(s) of a value held in too many locations to list "
                                  "ask for the automaton at rest (no action of its own running)"});
  w.warnings = warnings_;
  for (std::size_t x = 0; x < g_.actions.size(); ++x) {
    if (timing_[x] < 0) continue;  // never applicable: not in the model
    const GroundAction& ga = g_.actions[x];
    std::string pddl = "(" + d_.actions[ga.action].name;
    for (const auto& a : ga.args) pddl += " " + a;
    w.actions.push_back(
        PlanAction{cmd_[x], automaton_[timing_[x]], pddl + ")", !timing_steps_[x].empty()});
  }
  if (!p_) return w;
  Json initial = Json::object();
  for (std::size_t i = 0; i < g_.variables.size(); ++i)
    initial[automaton_[i]] = locs_[i][g_.variables[i].timeline.empty()
                                          ? LocOf(static_cast<int>(i), *g_.variables[i].initial, "")
                                          : 0]
                                 .name;
  for (std::size_t i = g_.variables.size(); i < automaton_.size(); ++i)
    initial[automaton_[i]] = "idle";
  if (!ended.empty()) *goal = *goal == "true" ? ended : "(" + *goal + ") /\\ " + ended;
  w.state_plan = {{"initial_state", initial},
                  {"end_state", {{"maintenance_constraint", "true"}, {"goal_constraint", *goal}}}};
  if (p_->minimize_total_time) w.state_plan["objective"] = "makespan";
  return w;
}

}  // namespace writer_impl

std::optional<Written> WriteModel(const DomainAst& d, const StateVars& sv, const Grounded& g,
                                  const ProblemAst* p, const ImportOptions& options,
                                  std::vector<Issue>& issues) {
  return writer_impl::Writer(d, sv, g, p, options, issues).Run();
}

}  // namespace ctb::pddl