// PDDL domains and problems as read (internal to ctb_pddl): only what the import can map; every
// other construct is refused by the reader with an Issue.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "interchange/pddl/import.h"
#include "interchange/pddl/internal/sexpr.h"

namespace ctb::pddl {

// A parameter, constant or object with its type; `types` has several entries for (either ...).
struct TypedName {
  std::string name;
  std::vector<std::string> types{"object"};
  Pos pos;
};

// (pred t1 .. tn), or with `equality` set (= t1 t2). Terms are "?var" or object names.
struct Atom {
  std::string pred;
  std::vector<std::string> args;
  bool equality = false;
  Pos pos;
};

struct Literal {
  Atom atom;
  bool positive = true;
  Pos pos;
  std::string text;  // as written, for messages
};

enum class When { kStart, kOverAll, kEnd };
const char* WhenName(When w);

struct TimedLiteral {
  When when = When::kStart;
  Literal lit;
};

// A number, a function term (f t1 .. tn), or (op a b) with op one of + - * /.
struct NumExpr {
  enum class Kind { kNumber, kFunction, kOp } kind = Kind::kNumber;
  double value = 0;
  std::string name;  // function or operator
  std::vector<std::string> args;
  std::vector<NumExpr> kids;
  Pos pos;
};

struct Action {
  std::string name;
  bool durative = false;
  std::vector<TypedName> params;
  std::optional<NumExpr> min_duration;   // nullopt: 0
  std::optional<NumExpr> max_duration;   // nullopt: unbounded
  std::vector<TimedLiteral> conditions;  // an instantaneous action's are all kStart
  std::vector<TimedLiteral> effects;     // kStart or kEnd (kStart for instantaneous actions)
  Pos pos;
};

struct Signature {
  std::string name;
  std::vector<TypedName> params;
  Pos pos;
};

struct DomainAst {
  std::string file;
  std::string name;
  std::map<std::string, std::vector<std::string>> type_parents;  // "object" has none
  std::vector<TypedName> constants;
  std::vector<Signature> predicates;
  std::vector<Signature> functions;
  std::vector<Action> actions;

  const Signature* Predicate(const std::string& n) const;
  const Signature* Function(const std::string& n) const;
};

// A goal: a literal or a connective over goals.
struct Goal {
  enum class Kind { kLiteral, kAnd, kOr, kNot, kImply } kind = Kind::kAnd;
  Literal lit;
  std::vector<Goal> kids;
  Pos pos;
};

// A timed initial literal (at TIME LITERAL) of a problem's :init.
struct Til {
  double time = 0;
  Literal lit;
};

struct ProblemAst {
  std::string file;
  std::string name;
  std::string domain_name;
  Pos domain_pos;
  std::vector<TypedName> objects;
  std::vector<Atom> init;
  std::map<std::string, double> init_values;  // "f a b" -> value
  std::vector<Til> tils;                       // in file order
  std::optional<Goal> goal;
  Pos goal_pos;
  bool minimize_total_time = false;
};

// The key of a function or predicate applied to objects: "name a b".
std::string GroundKey(const std::string& name, const std::vector<std::string>& args);

// On error nullopt, with every issue found appended.
std::optional<DomainAst> ReadDomain(const SExpr& e, const std::string& file,
                                    std::vector<Issue>& issues);
std::optional<ProblemAst> ReadProblem(const SExpr& e, const std::string& file,
                                      std::vector<Issue>& issues);

}  // namespace ctb::pddl
