#include "planner/model/domain.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "planner/expr/expr_print.h"
#include "planner/model/expr_check.h"
#include "planner/model/templates.h"

namespace ctb {

// The command code a commanded guard requires: a positive atom "<own>u[i]==c" in the guard's
// top-level conjunction. 0 when the guard reads the command some other way.
int RequiredCommand(const Expr& e, int self) {
  if (e.op == Expr::Op::kAtom)
    return (e.var_kind == VarKind::kCommand && e.target == self && !e.not_equal) ? e.value_code : 0;
  if (e.op == Expr::Op::kAnd) {
    int l = RequiredCommand(e.kids[0], self), r = RequiredCommand(e.kids[1], self);
    if (l && r) return l == r ? l : -1;  // two different commands: never enabled
    return l ? l : r;
  }
  return 0;
}

bool IsIdentifier(const std::string& s) {
  if (s.empty() || s.size() > 128) return false;
  if (!(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return s != "not" && s != "true" && s != "false" && s != "i";
}

int Automaton::LocationIndex(const std::string& n) const {
  auto it = std::find(locations.begin(), locations.end(), n);
  return it == locations.end() ? -1 : static_cast<int>(it - locations.begin());
}

int Automaton::CommandCode(const std::string& n) const {
  auto it = std::find(commands.begin(), commands.end(), n);
  return it == commands.end() ? -1 : static_cast<int>(it - commands.begin()) + 1;
}

int Domain::AutomatonIndex(const std::string& n) const {
  for (std::size_t i = 0; i < automata.size(); ++i)
    if (automata[i].name == n) return static_cast<int>(i);
  return -1;
}

const TemplateRange* Domain::Template(const std::string& n) const {
  for (const auto& t : templates)
    if (t.name == n) return &t;
  return nullptr;
}

namespace {

// Reads an array of unique identifiers.
std::vector<std::string> ReadNames(const Json* j, const std::string& pointer, const char* what,
                                   bool non_empty, Diagnostics& diags) {
  std::vector<std::string> out;
  if (!j) return out;
  if (!j->is_array()) {
    diags.Error(pointer, std::string("expected an array of ") + what + " names, got " +
                             JsonTypeName(*j));
    return out;
  }
  if (non_empty && j->empty()) diags.Error(pointer, std::string("needs at least one ") + what);
  std::set<std::string> seen;
  for (std::size_t i = 0; i < j->size(); ++i) {
    const Json& v = (*j)[i];
    std::string p = pointer + "/" + std::to_string(i);
    if (!v.is_string()) {
      diags.Error(p, std::string("expected a string, got ") + JsonTypeName(v));
      continue;
    }
    std::string name = v.get<std::string>();
    if (!IsIdentifier(name)) {
      diags.Error(p, std::string("'") + name + "' is not a valid " + what +
                         " name (letters, digits and '_', not starting with a digit)");
      continue;
    }
    if (!seen.insert(name).second) {
      diags.Error(p, std::string("duplicate ") + what + " '" + name + "'");
      continue;
    }
    out.push_back(name);
  }
  return out;
}

bool IsMultiple(double v, double res) {
  double q = v / res;
  return std::fabs(q - std::round(q)) < 1e-9 * std::max(1.0, std::fabs(q));
}

// "distribution": {"kind": "uniform"} or {"kind": "normal", "mean": m, "sd": s}.
std::optional<Distribution> ReadDistribution(const ObjectReader& parent, const Transition& t,
                                             Diagnostics& diags) {
  const Json* j = parent.Get("distribution");
  ObjectReader r(*j, parent.Child("distribution"), diags);
  if (!r.valid()) return std::nullopt;
  r.CheckKeys({"kind", "mean", "sd"});
  auto kind = r.String("kind", true);
  if (!kind) return std::nullopt;
  Distribution dist;
  if (*kind == "uniform") {
    if (!r.Has("mean") && !r.Has("sd")) return dist;
    diags.Error(r.Child(r.Has("mean") ? "mean" : "sd"), "a uniform distribution has no mean or sd");
    return std::nullopt;
  }
  if (*kind != "normal") {
    diags.Error(r.Child("kind"), "unknown distribution '" + *kind + "' (uniform or normal)");
    return std::nullopt;
  }
  dist.kind = Distribution::Kind::kNormal;
  auto mean = r.NonNegative("mean", true);
  auto sd = r.NonNegative("sd", true);
  if (!mean || !sd) return std::nullopt;
  if (*sd <= 0) {
    diags.Error(r.Child("sd"), "sd must be positive");
    return std::nullopt;
  }
  if (*mean < t.duration.lo || *mean > *t.duration.hi)
    diags.Warning(r.Child("mean"), "the mean lies outside the duration's bounds");
  dist.mean = *mean;
  dist.sd = *sd;
  return dist;
}

// "contingent": nature picks the firing time in [lo, hi]: not commanded, not controllable, hi
// finite, guard true (contract section 13). Returns false after recording the errors.
bool ReadContingent(const ObjectReader& r, Transition& t, Diagnostics& diags) {
  if (auto c = r.Bool("contingent", false)) t.contingent = *c;
  if (!t.contingent) {
    if (r.Has("distribution"))
      diags.Error(r.Child("distribution"), "only a contingent transition has a distribution");
    return !r.Has("distribution");
  }
  const std::size_t before = diags.errors().size();
  const std::string at = r.Child("contingent");
  if (t.commanded)
    diags.Error(at, "a commanded transition cannot be contingent: its command sets when it fires");
  else if (t.controllable)
    diags.Error(at, "a transition is controllable (the planner picks) or contingent (nature "
                    "picks), not both");
  else if (t.guard.op != Expr::Op::kTrue)
    diags.Error(r.Child("guard"), "a contingent transition's guard must be true: nature picks "
                                  "when it fires, whatever the other automata do");
  if (!t.duration.hi)
    diags.Error(r.Child("duration"), "a contingent transition needs a finite upper bound [lo, hi]");
  if (diags.errors().size() > before) return false;
  if (r.Has("distribution")) {
    t.distribution = ReadDistribution(r, t, diags);
    if (!t.distribution) return false;
  }
  return true;
}

// How guards are read: the longest text (a template's expansion may write longer guards than a
// user may) and the quantifier budget of the whole domain.
struct GuardLimits {
  std::size_t max_length = kMaxExprLength;
  QuantifierBudget budget;
  std::unordered_map<std::string, int> automaton_index;  // the domain's automata by name
};

void ReadTransition(const Json& j, const std::string& p, const Domain& d, int self,
                    Automaton& a, GuardLimits& limits, Diagnostics& diags) {
  ObjectReader r(j, p, diags);
  if (!r.valid()) return;
  r.CheckKeys({"from", "to", "guard", "duration", "cost", "controllable", "contingent",
               "distribution"});
  Transition t;
  t.pointer = p;
  bool ok = true;
  for (const char* end : {"from", "to"}) {
    auto name = r.String(end, true);
    if (!name) {
      ok = false;
      continue;
    }
    int loc = a.LocationIndex(*name);
    if (loc < 0) {
      std::string best = NearestName(*name, a.locations);
      diags.Error(r.Child(end), "unknown location '" + *name + "' of automaton '" + a.name + "'" +
                                    (best.empty() ? "" : " (did you mean '" + best + "'?)"));
      ok = false;
      continue;
    }
    (std::string(end) == "from" ? t.from : t.to) = loc;
  }
  if (ok && t.from == t.to) {
    diags.Error(r.Child("to"), "a transition must change location ('" + a.locations[t.from] +
                                   "' to itself); staying is implicit");
    ok = false;
  }
  if (auto g = r.String("guard", false)) t.guard_text = *g;
  Scope scope{&d, {}, {}, limits.max_length, &limits.budget, &limits.automaton_index};
  ExprInfo info;
  auto guard = ParseChecked(t.guard_text, scope, ExprContext::kGuard, r.Child("guard"), diags,
                            &info);
  if (guard) {
    t.guard = std::move(*guard);
    t.guard_info = info;
    t.commanded = info.commands_read.count(self) > 0;
    t.command = t.commanded ? std::max(0, RequiredCommand(t.guard, self)) : 0;
  } else {
    ok = false;
  }
  if (const Json* dur = r.Get("duration")) {
    std::string dp = r.Child("duration");
    if (!dur->is_array() || dur->size() != 2) {
      diags.Error(dp, "expected [lo, hi] with hi a number or null");
      ok = false;
    } else {
      auto lo = AsNonNegative((*dur)[0], dp + "/0", diags);
      std::optional<double> hi;
      bool hi_ok = true;
      if (!(*dur)[1].is_null()) {
        hi = AsNonNegative((*dur)[1], dp + "/1", diags);
        hi_ok = hi.has_value();
      }
      if (!lo || !hi_ok) {
        ok = false;
      } else if (hi && *lo > *hi) {
        diags.Error(dp, "duration lower bound " + (*dur)[0].dump() + " is greater than upper bound " +
                            (*dur)[1].dump());
        ok = false;
      } else {
        for (int k = 0; k < 2; ++k) {
          if ((*dur)[k].is_null()) continue;
          double v = (*dur)[k].get<double>();
          if (v > 1e7) {
            diags.Error(dp + "/" + std::to_string(k), "duration beyond 10,000,000 seconds");
            ok = false;
          } else if (!IsMultiple(v, d.time_resolution)) {
            diags.Error(dp + "/" + std::to_string(k),
                        "duration is not a multiple of the domain's time_resolution");
            ok = false;
          }
        }
        t.duration = {*lo, hi};
      }
    }
  }
  if (const Json* c = r.Get("cost")) {
    if (!c->is_number_integer() && !c->is_number_unsigned()) {
      diags.Error(r.Child("cost"), std::string("expected a non-negative integer, got ") +
                                       (c->is_number() ? c->dump() : JsonTypeName(*c)));
      ok = false;
    } else if (c->get<long long>() < 0 || c->get<long long>() > 1000000) {
      diags.Error(r.Child("cost"), "cost must be between 0 and 1,000,000");
      ok = false;
    } else {
      t.cost = static_cast<long>(c->get<long long>());
    }
  }
  if (auto c = r.Bool("controllable", false)) t.controllable = *c;
  if (t.controllable && t.commanded) {
    diags.Error(r.Child("controllable"),
                "a commanded transition cannot also be controllable: its command already sets "
                "when it fires");
    ok = false;
  }
  if (ok) ok = ReadContingent(r, t, diags);
  if (ok) a.transitions.push_back(std::move(t));
}

// A contingent transition is the only way out of its location: another exit would race with
// nature's choice (contract section 13).
void CheckContingentExits(const Automaton& a, Diagnostics& diags) {
  for (const Transition& c : a.transitions) {
    if (!c.contingent) continue;
    for (const Transition& t : a.transitions)
      if (&t != &c && t.from == c.from)
        diags.Error(t.pointer, "'" + a.locations[c.from] + "' is left by the contingent transition " +
                                   c.pointer + ": it can have no other transition out");
  }
}

// A transition listed twice (same from, to and guard, as an LLM draft or a pasted edit easily
// gives) is an error at the second listing: the encoding assumes one transition per choice, and
// merging would have to guess which duration and cost were meant (issue 30).
void CheckDuplicateTransitions(const Automaton& a, Diagnostics& diags) {
  std::map<std::tuple<int, int, std::string>, const Transition*> seen;
  for (const Transition& t : a.transitions) {
    auto [it, inserted] = seen.emplace(std::make_tuple(t.from, t.to, PrintSource(t.guard)), &t);
    if (inserted) continue;
    diags.Error(t.pointer, "the same transition as " + it->second->pointer + " (" +
                               a.locations[t.from] + " -> " + a.locations[t.to] +
                               " with the same guard): list it once, with one duration and cost");
  }
}

}  // namespace

namespace {

// A document without templates (contract section 2).
// With `x`, the document is x's expansion: the domain keeps its templates, and its guards may be
// as long as kMaxExpandedGuard (templates.h bounds the expansion's work).
std::optional<Domain> LoadPlainDomain(const Json& j, Diagnostics& diags,
                                      const Expansion* x = nullptr) {
  std::size_t errors_before = diags.errors().size();
  ObjectReader r(j, "", diags);
  if (!r.valid()) return std::nullopt;
  r.CheckKeys({"name", "description", "time_resolution", "automata"});
  Domain d;
  if (auto n = r.String("name", true)) {
    if (!IsIdentifier(*n)) diags.Error(r.Child("name"), "domain name must be an identifier");
    d.name = *n;
  }
  if (auto desc = r.String("description", false)) d.description = *desc;
  if (r.Has("time_resolution")) {
    auto res = r.NonNegative("time_resolution", false);
    if (res && (*res < 1e-6 || *res > 1)) {
      // Finer than a microsecond cannot be counted in the solver's integers for any real plan.
      diags.Error(r.Child("time_resolution"), "time_resolution must be in [0.000001, 1] seconds");
    } else if (res) {
      if (!IsMultiple(1.0, *res))
        diags.Error(r.Child("time_resolution"), "time_resolution must divide one second");
      else
        d.time_resolution = *res;
    }
  }
  const Json* automata = r.Get("automata");
  if (!automata) {
    diags.Error(r.Child("automata"), "missing required field \"automata\"");
    return std::nullopt;
  }
  if (!automata->is_array() || automata->empty()) {
    diags.Error(r.Child("automata"), "expected a non-empty array of automata");
    return std::nullopt;
  }
  // Pass 1: names, locations and commands of every automaton (guards may read any of them).
  std::map<std::string, std::string> variable_owner;  // expression variable name -> automaton
  std::vector<const Json*> transition_lists;
  for (std::size_t i = 0; i < automata->size(); ++i) {
    std::string p = "/automata/" + std::to_string(i);
    ObjectReader ar((*automata)[i], p, diags);
    transition_lists.push_back(nullptr);
    if (!ar.valid()) continue;
    ar.CheckKeys({"name", "locations", "commands", "transitions"});
    Automaton a;
    auto name = ar.String("name", true);
    if (!name) continue;
    if (!IsIdentifier(*name)) {
      diags.Error(ar.Child("name"), "'" + *name + "' is not a valid automaton name");
      continue;
    }
    if (name->rfind(kEpisodeVarPrefix, 0) == 0 || name->rfind(kTemporalVarPrefix, 0) == 0) {
      diags.Error(ar.Child("name"), "automaton name uses a prefix reserved for state plans");
      continue;
    }
    bool clash = false;
    for (const std::string& var : {*name, *name + "l", *name + "u"}) {
      auto [it, inserted] = variable_owner.emplace(var, *name);
      if (!inserted) {
        diags.Error(ar.Child("name"), it->second == *name
                                          ? "duplicate automaton '" + *name + "'"
                                          : "automaton '" + *name + "' makes variable '" + var +
                                                "' ambiguous with automaton '" + it->second + "'");
        clash = true;
        break;
      }
    }
    if (clash) continue;
    a.name = *name;
    if (!ar.Has("locations")) diags.Error(ar.Child("locations"), "missing required field \"locations\"");
    a.locations = ReadNames(ar.Get("locations"), ar.Child("locations"), "location", true, diags);
    a.commands = ReadNames(ar.Get("commands"), ar.Child("commands"), "command", false, diags);
    if (const Json* t = ar.Get("transitions")) {
      if (!t->is_array()) diags.Error(ar.Child("transitions"), "expected an array of transitions");
      else transition_lists.back() = t;
    }
    d.automata.push_back(std::move(a));
  }
  if (diags.errors().size() > errors_before) return std::nullopt;
  // Pass 2: transitions.
  GuardLimits limits;
  limits.automaton_index = AutomatonIndexOf(d);
  if (x) {
    d.templates = x->templates;
    limits.max_length = kMaxExpandedGuard;
  }
  for (std::size_t i = 0; i < d.automata.size(); ++i) {
    const Json* list = transition_lists[i];
    if (!list) continue;
    for (std::size_t k = 0; k < list->size(); ++k)
      ReadTransition((*list)[k], "/automata/" + std::to_string(i) + "/transitions/" + std::to_string(k),
                     d, static_cast<int>(i), d.automata[i], limits, diags);
    CheckDuplicateTransitions(d.automata[i], diags);
    CheckContingentExits(d.automata[i], diags);
  }
  if (diags.errors().size() > errors_before) return std::nullopt;
  return d;
}

}  // namespace

std::optional<Domain> LoadDomain(const Json& j, Diagnostics& diags) {
  return LoadDomain(j, diags, ExpandOptions{}, nullptr);
}

std::optional<Domain> LoadDomain(const Json& j, Diagnostics& diags, const ExpandOptions& options,
                                 Expansion* expansion) {
  if (options.parameters.empty() && ObviouslyPlain(j)) {
    if (expansion) *expansion = Expansion{j, {}, false, {}};
    return LoadPlainDomain(j, diags);
  }
  auto x = ExpandTemplates(j, diags, options);
  if (!x) return std::nullopt;
  std::optional<Domain> d;
  if (!x->had_templates) {
    d = LoadPlainDomain(j, diags);
  } else {
    Diagnostics expanded;
    d = LoadPlainDomain(x->document, expanded, &*x);
    MapDiagnostics(*x, j, expanded, diags);
  }
  if (expansion) *expansion = std::move(*x);
  return d;
}

std::optional<Domain> LoadDomainFile(const std::string& path, Diagnostics& diags,
                                     const ParseLimits& limits) {
  Diagnostics local;
  auto j = ReadJsonFile(path, local, limits);
  std::optional<Domain> d;
  if (j) d = LoadDomain(*j, local);
  for (const auto& e : local.errors())
    diags.Error(e.pointer, path + ": " + e.message, e.offset);
  for (const auto& w : local.warnings())
    diags.Warning(w.pointer, path + ": " + w.message, w.offset);
  return d;
}

bool Domain::HasContingent() const {
  for (const auto& a : automata)
    for (const auto& t : a.transitions)
      if (t.contingent) return true;
  return false;
}

Domain PlanningDomain(const Domain& d, bool planner_picks) {
  Domain out = d;
  for (auto& a : out.automata)
    for (auto& t : a.transitions) {
      if (!t.contingent) continue;
      t.contingent = false;
      t.distribution.reset();
      if (planner_picks) t.controllable = true;
      else t.duration.lo = *t.duration.hi;
    }
  return out;
}

Json DomainToJson(const Domain& d) {
  Json out = {{"name", d.name}, {"description", d.description}};
  if (d.time_resolution != 1.0) out["time_resolution"] = d.time_resolution;
  Json automata = Json::array();
  for (const auto& a : d.automata) {
    Json ts = Json::array();
    for (const auto& t : a.transitions) {
      Json tj = {{"from", a.locations[t.from]}, {"to", a.locations[t.to]}, {"guard", t.guard_text},
                 {"duration", {t.duration.lo, t.duration.hi ? Json(*t.duration.hi) : Json()}},
                 {"cost", t.cost}};
      if (t.controllable) tj["controllable"] = true;
      if (t.contingent) tj["contingent"] = true;
      if (t.distribution) {
        tj["distribution"] = {{"kind", t.distribution->kind == Distribution::Kind::kNormal ? "normal" : "uniform"}};
        if (t.distribution->kind == Distribution::Kind::kNormal) {
          tj["distribution"]["mean"] = t.distribution->mean;
          tj["distribution"]["sd"] = t.distribution->sd;
        }
      }
      ts.push_back(std::move(tj));
    }
    automata.push_back({{"name", a.name}, {"locations", a.locations}, {"commands", a.commands},
                        {"transitions", std::move(ts)}});
  }
  out["automata"] = std::move(automata);
  return out;
}

}  // namespace ctb
