// PDDL 2.1 domains and problems from s-expressions: the subset the import maps, and an Issue
// naming the action and the line for everything else.
#include <cstdlib>
#include <set>

#include "interchange/pddl/internal/pddl_ast.h"

namespace ctb::pddl {

const char* WhenName(When w) {
  switch (w) {
    case When::kStart:
      return "at start";
    case When::kOverAll:
      return "over all";
    case When::kEnd:
      return "at end";
  }
  return "";
}

const Signature* DomainAst::Predicate(const std::string& n) const {
  for (const auto& p : predicates)
    if (p.name == n) return &p;
  return nullptr;
}

const Signature* DomainAst::Function(const std::string& n) const {
  for (const auto& f : functions)
    if (f.name == n) return &f;
  return nullptr;
}

std::string GroundKey(const std::string& name, const std::vector<std::string>& args) {
  std::string k = name;
  for (const auto& a : args) k += " " + a;
  return k;
}

namespace {

bool IsNumber(const std::string& s, double* v = nullptr) {
  if (s.empty()) return false;
  char* end = nullptr;
  double d = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size()) return false;
  if (v) *v = d;
  return true;
}

// Reads one domain or problem; `action_` names the action being read, for every issue.
class Reader {
 public:
  Reader(std::string file, std::vector<Issue>& issues) : file_(std::move(file)), issues_(issues) {}

  std::optional<DomainAst> Domain(const SExpr& e);
  std::optional<ProblemAst> Problem(const SExpr& e);

 private:
  void Fail(Pos p, std::string message) {
    issues_.push_back(Issue{file_, p.line, p.column, action_, std::move(message)});
    ++errors_;
  }
  bool Expect(bool ok, const SExpr& e, const std::string& what) {
    if (!ok) Fail(e.pos, "expected " + what + ", got " + e.ToString());
    return ok;
  }

  std::vector<TypedName> TypedList(const SExpr& list, std::size_t from, bool variables);
  void Types(const SExpr& e, DomainAst& d);
  void Signatures(const SExpr& e, std::vector<Signature>& out, bool functions);
  void ReadAction(const SExpr& e, bool durative, DomainAst& d);
  void Duration(const SExpr& e, Action& a);
  std::optional<NumExpr> Number(const SExpr& e);
  void TimedConditions(const SExpr& e, std::vector<TimedLiteral>& out);
  void Literals(const SExpr& e, When when, std::vector<TimedLiteral>& out, bool effect);
  std::optional<Literal> ReadLiteral(const SExpr& e, bool effect);
  void TimedEffects(const SExpr& e, std::vector<TimedLiteral>& out);
  std::optional<Goal> ReadGoal(const SExpr& e);
  void CheckAction(const Action& a, const DomainAst& d);
  void CheckAtom(const Atom& a, const Action& act, const DomainAst& d);

  std::string file_;
  std::vector<Issue>& issues_;
  std::string action_;
  int errors_ = 0;
};

std::vector<TypedName> Reader::TypedList(const SExpr& list, std::size_t from, bool variables) {
  std::vector<TypedName> out;
  std::size_t untyped = 0;  // out[untyped..] wait for a type
  for (std::size_t i = from; i < list.items.size(); ++i) {
    const SExpr& it = list.items[i];
    if (it.IsAtom("-")) {
      if (i + 1 >= list.items.size() || untyped == out.size()) {
        Fail(it.pos, "'-' must follow names and precede a type");
        return out;
      }
      const SExpr& t = list.items[++i];
      std::vector<std::string> types;
      if (t.IsAtom()) {
        types.push_back(t.atom);
      } else if (t.HasHead("either") && t.items.size() > 1) {
        for (std::size_t k = 1; k < t.items.size(); ++k)
          if (Expect(t.items[k].IsAtom(), t.items[k], "a type name"))
            types.push_back(t.items[k].atom);
      } else {
        Expect(false, t, "a type or (either ...)");
        continue;
      }
      for (; untyped < out.size(); ++untyped) out[untyped].types = types;
      continue;
    }
    if (!Expect(it.IsAtom(), it, variables ? "a ?variable" : "a name")) continue;
    if (variables != (it.atom[0] == '?')) {
      Fail(it.pos, variables ? "expected a ?variable, got '" + it.atom + "'"
                             : "expected a name, got the variable '" + it.atom + "'");
      continue;
    }
    out.push_back(TypedName{it.atom, {"object"}, it.pos});
  }
  return out;
}

void Reader::Types(const SExpr& e, DomainAst& d) {
  for (const TypedName& t : TypedList(e, 1, false)) {
    if (t.types.size() != 1) {
      Fail(t.pos, "type '" + t.name + "': (either ...) as a supertype cannot be mapped");
      continue;
    }
    if (t.name == "object") continue;
    d.type_parents[t.name] = t.types;
    if (!d.type_parents.count(t.types[0]) && t.types[0] != "object")
      d.type_parents[t.types[0]] = {"object"};
  }
}

void Reader::Signatures(const SExpr& e, std::vector<Signature>& out, bool functions) {
  for (std::size_t i = 1; i < e.items.size(); ++i) {
    const SExpr& s = e.items[i];
    if (functions && s.IsAtom("-")) {  // "- number" after a function
      if (i + 1 < e.items.size() && !e.items[i + 1].IsAtom("number"))
        Fail(e.items[i + 1].pos,
             "function type '" + e.items[i + 1].ToString() + "' cannot be mapped (only number)");
      ++i;
      continue;
    }
    if (!Expect(s.is_list && !s.items.empty() && s.items[0].IsAtom(), s,
                functions ? "(function ?args)" : "(predicate ?args)"))
      continue;
    out.push_back(Signature{s.items[0].atom, TypedList(s, 1, true), s.pos});
  }
}

std::optional<NumExpr> Reader::Number(const SExpr& e) {
  NumExpr n;
  n.pos = e.pos;
  if (e.IsAtom()) {
    if (IsNumber(e.atom, &n.value)) return n;
    Fail(e.pos, "duration '" + e.atom + "' is not a number or a function term (f ...)");
    return std::nullopt;
  }
  std::string head = e.Head();
  if (head.empty()) {
    Expect(false, e, "a number or (f ...)");
    return std::nullopt;
  }
  if (head == "+" || head == "-" || head == "*" || head == "/") {
    if (e.items.size() < 2 || e.items.size() > 3 || (head != "-" && e.items.size() != 3)) {
      Expect(false, e, "(" + head + " a b)");
      return std::nullopt;
    }
    n.kind = NumExpr::Kind::kOp;
    n.name = head;
    for (std::size_t i = 1; i < e.items.size(); ++i) {
      auto k = Number(e.items[i]);
      if (!k) return std::nullopt;
      n.kids.push_back(std::move(*k));
    }
    return n;
  }
  n.kind = NumExpr::Kind::kFunction;
  n.name = head;
  for (std::size_t i = 1; i < e.items.size(); ++i) {
    if (!Expect(e.items[i].IsAtom(), e.items[i], "a term")) return std::nullopt;
    n.args.push_back(e.items[i].atom);
  }
  return n;
}

void Reader::Duration(const SExpr& e, Action& a) {
  if (e.HasHead("and")) {
    for (std::size_t i = 1; i < e.items.size(); ++i) Duration(e.items[i], a);
    return;
  }
  std::string op = e.Head();
  bool ok = e.items.size() == 3 && e.items[1].IsAtom("?duration") &&
            (op == "=" || op == "<=" || op == ">=");
  if (!ok) {
    Fail(e.pos,
         "duration constraint " + e.ToString() +
             " cannot be mapped: write (= ?duration D), (>= ?duration D) or (<= ?duration D)");
    return;
  }
  auto v = Number(e.items[2]);
  if (!v) return;
  if (op != "<=") a.min_duration = *v;
  if (op != ">=") a.max_duration = *v;
}

std::optional<Literal> Reader::ReadLiteral(const SExpr& e, bool effect) {
  Literal l;
  l.pos = e.pos;
  l.text = e.ToString();
  const SExpr* atom = &e;
  if (e.HasHead("not")) {
    if (e.items.size() != 2) {
      Expect(false, e, "(not X)");
      return std::nullopt;
    }
    l.positive = false;
    atom = &e.items[1];
  }
  std::string head = atom->Head();
  static const std::set<std::string> kNumeric = {
      "<", ">", "<=", ">=", "increase", "decrease", "assign", "scale-up", "scale-down"};
  static const std::set<std::string> kConnectives = {"and",    "or",   "imply", "exists",
                                                     "forall", "when", "not"};
  if (kNumeric.count(head) || (head == "=" && atom->items.size() == 3 &&
                               (atom->items[1].is_list || atom->items[2].is_list))) {
    Fail(e.pos, std::string(effect ? "effect " : "condition ") + l.text +
                    " uses numeric fluents, which cannot be mapped (automata have no numbers)");
    return std::nullopt;
  }
  if (head.empty() || kConnectives.count(head)) {
    if (head == "when")
      Fail(e.pos, "conditional effect " + l.text + " cannot be mapped");
    else if (head == "forall" || head == "exists")
      Fail(e.pos, std::string(effect ? "effect " : "condition ") + l.text +
                      " is quantified, which cannot be mapped");
    else
      Fail(e.pos,
           std::string(effect ? "effect " : "condition ") + l.text +
               " cannot be mapped: only conjunctions of literals (p ...) and (not (p ...)) are");
    return std::nullopt;
  }
  l.atom.pred = head;
  l.atom.pos = atom->pos;
  l.atom.equality = head == "=";
  for (std::size_t i = 1; i < atom->items.size(); ++i) {
    if (!Expect(atom->items[i].IsAtom(), atom->items[i], "a term (?variable or name)"))
      return std::nullopt;
    l.atom.args.push_back(atom->items[i].atom);
  }
  if (l.atom.equality && l.atom.args.size() != 2) {
    Expect(false, *atom, "(= a b)");
    return std::nullopt;
  }
  if (effect && l.atom.equality) {
    Fail(e.pos, "effect " + l.text + " cannot be mapped");
    return std::nullopt;
  }
  return l;
}

void Reader::Literals(const SExpr& e, When when, std::vector<TimedLiteral>& out, bool effect) {
  if (e.is_list && e.items.empty()) return;  // ()
  if (e.HasHead("and")) {
    for (std::size_t i = 1; i < e.items.size(); ++i) Literals(e.items[i], when, out, effect);
    return;
  }
  if (auto l = ReadLiteral(e, effect)) out.push_back(TimedLiteral{when, std::move(*l)});
}

// (at start X), (over all X) or (at end X); nullopt otherwise.
std::optional<When> TimeSpecifier(const SExpr& e) {
  if (!e.is_list || e.items.size() != 3 || !e.items[1].IsAtom()) return std::nullopt;
  if (e.items[0].IsAtom("at") && e.items[1].IsAtom("start")) return When::kStart;
  if (e.items[0].IsAtom("at") && e.items[1].IsAtom("end")) return When::kEnd;
  if (e.items[0].IsAtom("over") && e.items[1].IsAtom("all")) return When::kOverAll;
  return std::nullopt;
}

void Reader::TimedConditions(const SExpr& e, std::vector<TimedLiteral>& out) {
  if (e.is_list && e.items.empty()) return;
  if (e.HasHead("and")) {
    for (std::size_t i = 1; i < e.items.size(); ++i) TimedConditions(e.items[i], out);
    return;
  }
  if (auto w = TimeSpecifier(e)) return Literals(e.items[2], *w, out, false);
  if (e.HasHead("forall") || e.HasHead("exists") || e.HasHead("or") || e.HasHead("imply"))
    return Fail(e.pos, "condition " + e.ToString() +
                           " cannot be mapped: only conjunctions of literals are");
  if (e.HasHead("preference")) return Fail(e.pos, "preferences (PDDL3) cannot be mapped");
  Fail(e.pos, "condition " + e.ToString() +
                  " has no time specifier: write (at start ...), (over all ...) or (at end ...)");
}

void Reader::TimedEffects(const SExpr& e, std::vector<TimedLiteral>& out) {
  if (e.is_list && e.items.empty()) return;
  if (e.HasHead("and")) {
    for (std::size_t i = 1; i < e.items.size(); ++i) TimedEffects(e.items[i], out);
    return;
  }
  auto w = TimeSpecifier(e);
  if (w && *w != When::kOverAll) return Literals(e.items[2], *w, out, true);
  static const std::set<std::string> kNumeric = {"increase", "decrease", "assign", "scale-up",
                                                 "scale-down"};
  if (kNumeric.count(e.Head()))
    return Fail(e.pos,
                "effect " + e.ToString() +
                    " uses numeric fluents, which cannot be mapped (automata have no numbers)");
  if (e.HasHead("forall") || e.HasHead("when"))
    return Fail(e.pos, "effect " + e.ToString() + " cannot be mapped (" +
                           (e.HasHead("when") ? "conditional" : "universal") + " effect)");
  Fail(e.pos,
       "effect " + e.ToString() + " has no time specifier: write (at start ...) or (at end ...)");
}

void Reader::ReadAction(const SExpr& e, bool durative, DomainAst& d) {
  Action a;
  a.durative = durative;
  a.pos = e.pos;
  if (e.items.size() < 2 || !e.items[1].IsAtom()) {
    Fail(e.pos, "an action needs a name");
    return;
  }
  a.name = action_ = e.items[1].atom;
  for (std::size_t i = 2; i < e.items.size(); i += 2) {
    const SExpr& key = e.items[i];
    if (!Expect(key.IsAtom() && key.atom[0] == ':', key, "a :keyword")) break;
    if (i + 1 >= e.items.size()) {
      Fail(key.pos, key.atom + " has no value");
      break;
    }
    const SExpr& v = e.items[i + 1];
    if (key.atom == ":parameters") {
      if (Expect(v.is_list, v, "a parameter list")) a.params = TypedList(v, 0, true);
    } else if (durative && key.atom == ":duration") {
      Duration(v, a);
    } else if (durative && key.atom == ":condition") {
      TimedConditions(v, a.conditions);
    } else if (durative && key.atom == ":effect") {
      TimedEffects(v, a.effects);
    } else if (!durative && key.atom == ":precondition") {
      Literals(v, When::kStart, a.conditions, false);
    } else if (!durative && key.atom == ":effect") {
      Literals(v, When::kStart, a.effects, true);
    } else {
      Fail(key.pos, "unknown or unsupported action field " + key.atom);
    }
  }
  CheckAction(a, d);
  d.actions.push_back(std::move(a));
  action_.clear();
}

void Reader::CheckAtom(const Atom& a, const Action& act, const DomainAst& d) {
  for (const auto& t : a.args) {
    if (t[0] == '?') {
      bool found = false;
      for (const auto& p : act.params) found = found || p.name == t;
      if (!found) Fail(a.pos, "variable '" + t + "' is not a parameter of the action");
    } else {
      bool found = false;
      for (const auto& c : d.constants) found = found || c.name == t;
      if (!found) Fail(a.pos, "'" + t + "' is not a constant of the domain");
    }
  }
  if (a.equality) return;
  const Signature* s = d.Predicate(a.pred);
  if (!s)
    Fail(a.pos, "unknown predicate '" + a.pred + "'");
  else if (s->params.size() != a.args.size())
    Fail(a.pos, "predicate '" + a.pred + "' takes " + std::to_string(s->params.size()) +
                    " arguments, got " + std::to_string(a.args.size()));
}

void Reader::CheckAction(const Action& a, const DomainAst& d) {
  std::set<std::string> seen;
  for (const auto& p : a.params)
    if (!seen.insert(p.name).second) Fail(p.pos, "duplicate parameter '" + p.name + "'");
  for (const auto& c : a.conditions) CheckAtom(c.lit.atom, a, d);
  for (const auto& c : a.effects) CheckAtom(c.lit.atom, a, d);
  if (a.durative && !a.min_duration && !a.max_duration)
    Fail(a.pos, "a durative action needs :duration");
}

std::optional<DomainAst> Reader::Domain(const SExpr& e) {
  DomainAst d;
  d.file = file_;
  if (!e.HasHead("define") || e.items.size() < 2 || !e.items[1].HasHead("domain") ||
      e.items[1].items.size() != 2 || !e.items[1].items[1].IsAtom()) {
    Fail(e.pos, "expected (define (domain NAME) ...)");
    return std::nullopt;
  }
  d.name = e.items[1].items[1].atom;
  // Declarations first (actions may precede them in the file), then the actions.
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t i = 2; i < e.items.size(); ++i) {
      const SExpr& s = e.items[i];
      std::string head = s.Head();
      bool action = head == ":durative-action" || head == ":action";
      if (pass == 0 && action) continue;
      if (pass == 1) {
        if (action) ReadAction(s, head == ":durative-action", d);
        continue;
      }
      if (head == ":requirements") continue;
      if (head == ":types")
        Types(s, d);
      else if (head == ":constants")
        d.constants = TypedList(s, 1, false);
      else if (head == ":predicates")
        Signatures(s, d.predicates, false);
      else if (head == ":functions")
        Signatures(s, d.functions, true);
      else if (head == ":derived")
        Fail(s.pos, "derived predicates (:derived) cannot be mapped");
      else if (head == ":constraints")
        Fail(s.pos, "constraints (:constraints, PDDL3) cannot be mapped");
      else
        Fail(s.pos, "unknown or unsupported domain section " + s.ToString(40));
    }
  }
  for (const auto& c : d.constants)
    for (const auto& t : c.types)
      if (t != "object" && !d.type_parents.count(t))
        Fail(c.pos, "constant '" + c.name + "' has the undeclared type '" + t + "'");
  if (d.actions.empty() && errors_ == 0) Fail(e.pos, "the domain has no actions");
  if (errors_) return std::nullopt;
  return d;
}

std::optional<Goal> Reader::ReadGoal(const SExpr& e) {
  Goal g;
  g.pos = e.pos;
  std::string head = e.Head();
  if (head == "and" || head == "or" || head == "not" || head == "imply") {
    g.kind = head == "and"   ? Goal::Kind::kAnd
             : head == "or"  ? Goal::Kind::kOr
             : head == "not" ? Goal::Kind::kNot
                             : Goal::Kind::kImply;
    if ((head == "not" && e.items.size() != 2) || (head == "imply" && e.items.size() != 3)) {
      Expect(false, e, head == "not" ? "(not X)" : "(imply X Y)");
      return std::nullopt;
    }
    for (std::size_t i = 1; i < e.items.size(); ++i) {
      auto k = ReadGoal(e.items[i]);
      if (!k) return std::nullopt;
      g.kids.push_back(std::move(*k));
    }
    return g;
  }
  if (e.is_list && e.items.empty()) return g;  // () = true
  if (head == "forall" || head == "exists" || head == "preference") {
    Fail(e.pos, "goal " + e.ToString() + " cannot be mapped (quantifiers and preferences are not)");
    return std::nullopt;
  }
  auto l = ReadLiteral(e, false);
  if (!l) return std::nullopt;
  g.kind = Goal::Kind::kLiteral;
  g.lit = std::move(*l);
  return g;
}

std::optional<ProblemAst> Reader::Problem(const SExpr& e) {
  ProblemAst p;
  p.file = file_;
  if (!e.HasHead("define") || e.items.size() < 2 || !e.items[1].HasHead("problem") ||
      e.items[1].items.size() != 2 || !e.items[1].items[1].IsAtom()) {
    Fail(e.pos, "expected (define (problem NAME) ...)");
    return std::nullopt;
  }
  p.name = e.items[1].items[1].atom;
  for (std::size_t i = 2; i < e.items.size(); ++i) {
    const SExpr& s = e.items[i];
    std::string head = s.Head();
    if (head == ":domain") {
      if (Expect(s.items.size() == 2 && s.items[1].IsAtom(), s, "(:domain NAME)"))
        p.domain_name = s.items[1].atom;
      p.domain_pos = s.pos;
    } else if (head == ":requirements") {
      continue;
    } else if (head == ":objects") {
      p.objects = TypedList(s, 1, false);
    } else if (head == ":init") {
      for (std::size_t k = 1; k < s.items.size(); ++k) {
        const SExpr& f = s.items[k];
        double v = 0;
        if (f.HasHead("=") && f.items.size() == 3 && f.items[1].is_list && f.items[2].IsAtom() &&
            IsNumber(f.items[2].atom, &v)) {
          auto fn = Number(f.items[1]);
          if (fn && fn->kind == NumExpr::Kind::kFunction)
            p.init_values[GroundKey(fn->name, fn->args)] = v;
          else
            Expect(false, f, "(= (f objects) NUMBER)");
        } else if (f.HasHead("at") && f.items.size() == 3 && f.items[1].IsAtom() &&
                   IsNumber(f.items[1].atom, &v)) {
          if (v < 0) Fail(f.pos, "timed initial literal " + f.ToString() + " at a negative time");
          if (auto l = ReadLiteral(f.items[2], true); l && v >= 0)
            p.tils.push_back(Til{v, std::move(*l)});
        } else if (f.HasHead("not")) {
          continue;  // closed world: already false
        } else if (!Expect(f.is_list && !f.Head().empty(), f, "an atom (predicate objects)")) {
          continue;
        } else if (auto l = ReadLiteral(f, true)) {
          p.init.push_back(l->atom);
        }
      }
    } else if (head == ":goal") {
      p.goal_pos = s.pos;
      if (Expect(s.items.size() == 2, s, "(:goal G)")) p.goal = ReadGoal(s.items[1]);
    } else if (head == ":metric") {
      bool tt =
          s.items.size() == 3 && s.items[1].IsAtom("minimize") &&
          (s.items[2].IsAtom("total-time") || (s.items[2].is_list && s.items[2].items.size() == 1 &&
                                               s.items[2].items[0].IsAtom("total-time")));
      if (tt)
        p.minimize_total_time = true;
      else
        Fail(s.pos,
             "metric " + s.ToString() + " cannot be mapped (only (:metric minimize (total-time)))");
    } else if (head == ":constraints") {
      Fail(s.pos, "constraints (:constraints, PDDL3) cannot be mapped");
    } else {
      Fail(s.pos, "unknown or unsupported problem section " + s.ToString(40));
    }
  }
  if (!p.goal && errors_ == 0) Fail(e.pos, "the problem has no :goal");
  if (errors_) return std::nullopt;
  return p;
}

}  // namespace

std::optional<DomainAst> ReadDomain(const SExpr& e, const std::string& file,
                                    std::vector<Issue>& issues) {
  return Reader(file, issues).Domain(e);
}

std::optional<ProblemAst> ReadProblem(const SExpr& e, const std::string& file,
                                      std::vector<Issue>& issues) {
  return Reader(file, issues).Problem(e);
}

}  // namespace ctb::pddl
