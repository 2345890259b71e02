// Compiling the ground actions: one automaton per state variable; per ground action a command
// that every variable it reads or changes takes at its start (and at its end), commanded
// transitions of every variable it changes at that event, and step locations for the variables it
// changes at its end (left by commanded transitions its duration later). The rest of the model
// (timed initial literals, over-all protections, the goal) is writer_model.cpp's.
#include "interchange/pddl/internal/writer.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "interchange/pddl/internal/writer_impl.h"
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

namespace writer_impl {

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

void Writer::BaseLocations() {
  locs_.resize(g_.variables.size());
  loc_names_.resize(g_.variables.size());
  commands_.resize(g_.variables.size());
  for (std::size_t i = 0; i < g_.variables.size(); ++i) {
    const Variable& v = g_.variables[i];
    if (!v.timeline.empty()) {  // a location per stretch of time with one value
      std::string value = *v.initial;
      locs_[i].push_back(Loc{loc_names_[i].Take(ValueName(v.key, value)), value});
      for (const auto& [t, next] : v.timeline) {
        if (next == value) continue;
        std::string when = Duration(t).dump();
        std::replace(when.begin(), when.end(), '.', '_');
        locs_[i].push_back(Loc{loc_names_[i].Take(ValueName(v.key, next) + "_at_" + when), next});
        value = next;
      }
      continue;
    }
    for (const auto& value : v.values)
      locs_[i].push_back(Loc{loc_names_[i].Take(ValueName(v.key, value)), value});
  }
}

// The base location of a value, or with a step name, the step location holding that value.
int Writer::LocOf(int var, const std::string& value, const std::string& step_name) {
  auto& locs = locs_[var];
  for (std::size_t k = 0; k < locs.size(); ++k)
    if (locs[k].value == value &&
        (step_name.empty() ? !locs[k].step : locs[k].name.rfind(step_name, 0) == 0 && locs[k].step))
      return static_cast<int>(k);
  if (step_name.empty()) return -1;
  locs.push_back(Loc{loc_names_[var].Take(step_name), value, true});
  return static_cast<int>(locs.size()) - 1;
}

// Accept and Refuse return a placeholder that Expand writes out once every location exists (an
// action written later may add step locations that hold the value).
std::string Writer::Accept(int var, const std::string& value, const std::string& index,
                           bool base_only) const {
  return std::string("\x01") + "+" + (base_only ? "b" : "a") + std::to_string(var) + " " + index +
         " " + value;
}

std::string Writer::Refuse(int var, const std::string& value, const std::string& index,
                           bool base_only) const {
  return std::string("\x01") + "-" + (base_only ? "b" : "a") + std::to_string(var) + " " + index +
         " " + value;
}

// A placeholder as atoms: the locations with the value, or where that is longer, not the others.
// Where both lists are longer than kListedReads, a guard's read asks for the automaton at rest
// (in a base location) with the value, or with another value for a refusal: stricter than PDDL
// (counted in coarse_reads_).
std::string Writer::Expand(const std::string& atom) {
  if (atom.empty() || atom[0] != '\x01') return atom;
  bool accept = atom[1] == '+', base_only = atom[2] == 'b';
  std::size_t sp1 = atom.find(' '), sp2 = atom.find(' ', sp1 + 1);
  int var = std::stoi(atom.substr(3, sp1 - 3));
  std::string index = atom.substr(sp1 + 1, sp2 - sp1 - 1), value = atom.substr(sp2 + 1);
  std::vector<std::string> in, out;
  for (const auto& l : locs_[var])
    (l.value == value && !(base_only && l.step) ? in : out).push_back(l.name);
  if (in.empty() || out.empty()) return (in.empty() != accept) ? "true" : "false";
  if (std::min(in.size(), out.size()) > kListedReads) {
    ++coarse_reads_;
    std::vector<std::string> at_rest;
    for (const auto& l : locs_[var])
      if (!l.step && (l.value == value) == accept) at_rest.push_back(l.name);
    in = at_rest;
    out.clear();
    accept = true;
    if (in.empty()) return "false";
  }
  bool listed = out.empty() || in.size() <= out.size();  // name the locations with the value
  const auto& names = listed ? in : out;
  bool equal = listed == accept;
  std::vector<std::string> atoms;
  for (const auto& n : names)
    atoms.push_back(automaton_[var] + "l[" + index + "]" + (equal ? "==" : "!=") + n);
  if (!equal) return Join(atoms, " /\\ ");
  return atoms.size() == 1 ? atoms[0] : "(" + Join(atoms, " \\/ ") + ")";
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

// Which variables the action changes (at start, at end), reads, and from which values each changed
// variable can start; nullopt when some changed variable has none (never applicable).
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
  // Starting from an idle source (the variable keeps its value throughout: no effect on it, or
  // effects that give it the value it has) changes nothing there. An action idle on every
  // variable it changes changes no state at all (its steps hold the values they came from): it is
  // never needed, and offering it lets a search pass time with it. The one-variable case drops the
  // idle sources; with several, Idle() guards them (WriteAction).
  for (const VarUse* u : plan.changed)
    for (const auto& s : plan.sources[u])
      if (IdleSource(*u, s)) plan.idle[u].insert(s);
  if (plan.changed.size() == 1) {
    const VarUse* u = plan.changed[0];
    std::erase_if(plan.sources[u], [&](const std::string& s) { return plan.idle[u].count(s) > 0; });
    plan.idle.clear();
    if (plan.sources[u].empty()) return std::nullopt;
  }
  return plan;
}

bool Writer::IdleSource(const VarUse& u, const std::string& s) {
  return (!u.eff_start || *u.eff_start == s) && (!u.eff_end || *u.eff_end == s);
}

// The guard of a start from an idle source of u: another changed variable starts from a source
// that is not idle ("true" when u's source is not idle; "false" when no other variable can).
std::string Writer::NotAllIdle(const Plan& plan, const VarUse* u, const std::string& source) {
  auto idle = plan.idle.find(u);
  if (idle == plan.idle.end() || !idle->second.count(source)) return "true";
  std::vector<std::string> some;
  for (const VarUse* w : plan.changed) {
    if (w == u) continue;
    auto wi = plan.idle.find(w);
    std::vector<int> busy;
    for (const auto& s : plan.sources.at(w))
      if (wi == plan.idle.end() || !wi->second.count(s)) busy.push_back(LocOf(VarIndex(w->var), s, ""));
    if (!busy.empty()) some.push_back(InLocs(VarIndex(w->var), busy, "i"));
  }
  if (some.empty()) return "false";
  return some.size() == 1 ? some[0] : "(" + Join(some, " \\/ ") + ")";
}

// Guard atoms for what the action reads of a variable it does not change, at start (first 0, last
// 1) or at its end (2, 2).
std::vector<std::string> Writer::Reads(const VarUse& u, int first, int last, std::size_t x) {
  int v = VarIndex(u.var);
  std::vector<std::string> atoms;
  std::set<std::string> done;
  for (int w = first; w <= last; ++w) {
    if (u.need[w] && done.insert("+" + *u.need[w]).second)
      atoms.push_back(Accept(v, *u.need[w], "i"));
    for (const auto& f : u.forbid[w])
      if (done.insert("-" + f).second) atoms.push_back(Refuse(v, f, "i"));
  }
  if (first == 0 && (u.need[1] || !u.forbid[1].empty())) over_all_[x].emplace_back(v, &u);
  return atoms;
}

// The end's check of a timed literal's atom cannot tell two stretches with the value apart: an
// action running across a change and back is accepted. Said once per atom where that can happen.
void Writer::WarnRepeatedStretch(const VarUse& u, std::size_t x) {
  int v = VarIndex(u.var);
  if (!u.need[1] || !warned_stretch_.insert(v).second) return;
  int stretches = 0;
  for (const auto& l : locs_[v]) stretches += l.value == *u.need[1];
  if (stretches < 2) {
    warned_stretch_.erase(v);
    return;
  }
  const Action& a = d_.actions[g_.actions[x].action];
  warnings_.push_back(Issue{d_.file, a.pos.line, a.pos.column, a.name,
                            "over all on '" + automaton_[v] + "', which timed initial literals " +
                                "give the value " + std::to_string(stretches) +
                                " times: checked at the start and the end only"});
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
    event_sources_[{static_cast<int>(x), v, true}] = locs;
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
      const std::string idle = NotAllIdle(*plan, u, s);
      if (idle == "false") continue;
      std::string post = u->eff_start.value_or(s);
      std::string step = posts.size() == 1 ? cmd_[x] : cmd_[x] + "_" + ValueName(u->var, post);
      int to = ends(u) ? LocOf(v, post, step) : LocOf(v, post, "");
      if (ends(u) && std::find(steps[u].begin(), steps[u].end(), to) == steps[u].end())
        steps[u].push_back(to);
      int from = LocOf(v, s, "");
      if (from == to) continue;
      int cost = v == timing_[x] ? (durative ? 1 : 2) : 0;
      std::vector<std::string> g = guard;
      if (idle != "true") g.push_back(idle);
      trans_.push_back(Trans{v, from, to, g, std::nullopt, cost, static_cast<int>(x), true});
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
  // A timed initial literal's atom read over all: still the value at the end (its transitions are
  // automatic at fixed times and cannot wait for the action).
  for (const VarUse* u : plan->read_start)
    if (!g_.variables[VarIndex(u->var)].timeline.empty()) {
      for (auto& a : Reads(*u, 1, 1, x)) end.push_back(a);
      WarnRepeatedStretch(*u, x);
    }
  for (const VarUse* u : plan->at_end) {
    int v = VarIndex(u->var);
    event_sources_[{static_cast<int>(x), v, false}] = steps[u];
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
      trans_.push_back(
          Trans{v, from, to, guard, std::make_pair(ga.lo, ga.hi), cost, static_cast<int>(x)});
    }
  }
}

}  // namespace writer_impl
}  // namespace ctb::pddl
