// Small hand-written PDDL domains in the style of the IPC failures of issue 32 (an action changing
// two objects, durations from functions, a timed initial literal, a delete without a matching
// precondition), each imported, solved with the real minizinc to the optimum derived by hand, and
// compared with a direct PDDL 2.1 simulator; the plan written out as PDDL 2.1 (PddlPlan) is
// replayed by the simulator, which must accept it.
//
// The simulator (PddlSim) grounds the PDDL by itself (every binding by type) and searches the
// happenings exhaustively on integer times: one snap action (start or end) per happening,
// happenings at one time point ordered (PDDL 2.1 with epsilon taken to 0, which is how ctburton's
// events share a time), at-start conditions on the state before the start, over-all conditions on
// every state from just after the start to just before the end, at-end conditions before the end,
// ends exactly the duration after the start, a timed initial literal applied when time reaches it,
// no action overlapping itself, and the goal with nothing running. Starts happen at time 0, at an
// end or at a timed initial literal (waiting elsewhere never helps in these domains). It answers
// the least makespan, or -1 when no plan ends by `bound`.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <queue>
#include <regex>
#include <set>
#include <sstream>

#include "interchange/pddl/internal/pddl_ast.h"
#include "interchange/pddl/internal/sexpr.h"
#include "planner/search/first_plan.h"
#include "planner/solve/decompose.h"
#include "planner/verify/verify.h"
#include "tests/interchange/pddl_test_util.h"

namespace sim {

using ::ctb::pddl::Action;
using ::ctb::pddl::DomainAst;
using ::ctb::pddl::Goal;
using ::ctb::pddl::GroundKey;
using ::ctb::pddl::ProblemAst;
using ::ctb::pddl::When;

struct Snap {
  std::vector<std::pair<std::string, bool>> pre, inv, post;  // (atom, positive)
  std::vector<std::pair<std::string, bool>> eff_start, eff_end;
  int duration = 0;
  bool durative = true;
  std::string name;  // "(action arg...)"
};

struct Node {
  int time = 0;
  std::set<std::string> atoms;
  std::set<std::pair<int, int>> running;  // (end time, snap)
  auto operator<=>(const Node&) const = default;
};

class PddlSim {
 public:
  PddlSim(const DomainAst& d, const ProblemAst& p) : d_(d), p_(p) {
    std::vector<std::pair<std::string, std::vector<std::string>>> objects;
    for (const auto& c : d.constants) objects.push_back({c.name, c.types});
    for (const auto& o : p.objects) objects.push_back({o.name, o.types});
    for (const auto& a : d.actions) Ground(a, objects);
  }

  int MinMakespan(int bound) const {
    Node start;
    for (const auto& a : p_.init) start.atoms.insert(GroundKey(a.pred, a.args));
    std::priority_queue<std::pair<int, Node>, std::vector<std::pair<int, Node>>, std::greater<>>
        open;
    std::set<Node> seen;
    open.push({0, start});
    while (!open.empty()) {
      Node n = open.top().second;
      open.pop();
      if (!seen.insert(n).second) continue;
      if (n.running.empty() && Holds(*p_.goal, n.atoms)) return n.time;
      for (Node m : Next(n))
        if (m.time <= bound && !seen.count(m)) open.push({m.time, m});
    }
    return -1;
  }

 private:
  bool IsA(const std::vector<std::string>& have, const std::vector<std::string>& want) const {
    for (std::string t : have)
      for (int hops = 0; hops < 16; ++hops) {
        for (const auto& w : want)
          if (w == t || w == "object") return true;
        auto it = d_.type_parents.find(t);
        if (it == d_.type_parents.end() || it->second.empty()) break;
        t = it->second[0];
      }
    return false;
  }

  void Ground(const Action& a,
              const std::vector<std::pair<std::string, std::vector<std::string>>>& objects) {
    std::vector<std::string> b(a.params.size());
    std::function<void(std::size_t)> walk = [&](std::size_t k) {
      if (k < b.size()) {
        for (const auto& [o, types] : objects)
          if (IsA(types, a.params[k].types)) b[k] = o, walk(k + 1);
        return;
      }
      auto key = [&](const ::ctb::pddl::Atom& x) {
        std::vector<std::string> args;
        for (const auto& t : x.args) {
          std::string v = t;
          for (std::size_t i = 0; i < b.size(); ++i)
            if (a.params[i].name == t) v = b[i];
          args.push_back(v);
        }
        if (x.equality) return std::string(args[0] == args[1] ? "=true" : "=false");
        return GroundKey(x.pred, args);
      };
      Snap s;
      s.name = "(" + a.name;
      for (const auto& o : b) s.name += " " + o;
      s.name += ")";
      for (const auto& c : a.conditions) {
        auto lit = std::make_pair(key(c.lit.atom), c.lit.positive);
        (c.when == When::kStart ? s.pre : c.when == When::kOverAll ? s.inv : s.post).push_back(lit);
      }
      for (const auto& e : a.effects)
        (e.when == When::kEnd ? s.eff_end : s.eff_start)
            .push_back({key(e.lit.atom), e.lit.positive});
      s.durative = a.durative;
      if (a.durative) s.duration = static_cast<int>(Eval(*a.min_duration, a, b));
      if (s.duration < 0) return;
      snaps_.push_back(std::move(s));
    };
    walk(0);
  }

  double Eval(const ::ctb::pddl::NumExpr& e, const Action& a,
              const std::vector<std::string>& b) const {
    if (e.kind == ::ctb::pddl::NumExpr::Kind::kNumber) return e.value;
    std::vector<std::string> args;
    for (const auto& t : e.args) {
      std::string v = t;
      for (std::size_t i = 0; i < b.size(); ++i)
        if (a.params[i].name == t) v = b[i];
      args.push_back(v);
    }
    auto it = p_.init_values.find(GroundKey(e.name, args));
    return it == p_.init_values.end() ? -1 : it->second;  // -1: undefined, left out
  }

  static bool Lits(const std::vector<std::pair<std::string, bool>>& lits,
                   const std::set<std::string>& atoms) {
    for (const auto& [k, pos] : lits) {
      bool v = k == "=true" ? true : k == "=false" ? false : atoms.count(k) > 0;
      if (v != pos) return false;
    }
    return true;
  }

  static void Apply(const std::vector<std::pair<std::string, bool>>& eff,
                    std::set<std::string>& atoms) {
    for (const auto& [k, pos] : eff)
      if (!pos) atoms.erase(k);
    for (const auto& [k, pos] : eff)
      if (pos) atoms.insert(k);
  }

  bool Holds(const Goal& g, const std::set<std::string>& atoms) const {
    switch (g.kind) {
      case Goal::Kind::kLiteral:
        return (atoms.count(GroundKey(g.lit.atom.pred, g.lit.atom.args)) > 0) == g.lit.positive;
      case Goal::Kind::kAnd:
        for (const auto& k : g.kids)
          if (!Holds(k, atoms)) return false;
        return true;
      case Goal::Kind::kOr:
        for (const auto& k : g.kids)
          if (Holds(k, atoms)) return true;
        return false;
      case Goal::Kind::kNot:
        return !Holds(g.kids[0], atoms);
      case Goal::Kind::kImply:
        return !Holds(g.kids[0], atoms) || Holds(g.kids[1], atoms);
    }
    return false;
  }

  // Every running action's invariant still holds.
  bool Invariants(const Node& n) const {
    for (const auto& [end, s] : n.running)
      if (!Lits(snaps_[s].inv, n.atoms)) return false;
    return true;
  }

  std::vector<Node> Next(const Node& n) const {
    std::vector<Node> out;
    bool due = false;
    for (const auto& [end, s] : n.running) {
      if (end != n.time) continue;
      due = true;
      Node m = n;
      m.running.erase({end, s});
      if (!Lits(snaps_[s].post, m.atoms)) continue;
      Apply(snaps_[s].eff_end, m.atoms);
      if (Invariants(m)) out.push_back(m);
    }
    for (int s = 0; s < static_cast<int>(snaps_.size()); ++s) {
      bool busy = false;
      for (const auto& r : n.running) busy = busy || r.second == s;
      if (busy || !Lits(snaps_[s].pre, n.atoms)) continue;
      Node m = n;
      Apply(snaps_[s].eff_start, m.atoms);
      if (!snaps_[s].durative) {
        if (Invariants(m)) out.push_back(m);  // an instantaneous action
        continue;
      }
      if (!Lits(snaps_[s].inv, m.atoms)) continue;
      m.running.insert({n.time + snaps_[s].duration, s});
      if (Invariants(m)) out.push_back(m);
    }
    if (due) return out;  // an end due now happens before time moves on
    int next = 1 << 30;
    for (const auto& r : n.running) next = std::min(next, r.first);
    for (const auto& t : p_.tils)
      if (t.time > n.time) next = std::min(next, static_cast<int>(t.time));
    if (next == 1 << 30) return out;
    Node m = n;
    m.time = next;
    for (const auto& t : p_.tils)
      if (t.time > n.time && t.time <= next)
        Apply({{GroundKey(t.lit.atom.pred, t.lit.atom.args), t.lit.positive}}, m.atoms);
    if (Invariants(m)) out.push_back(m);
    return out;
  }

  const DomainAst& d_;
  const ProblemAst& p_;
  std::vector<Snap> snaps_;

 public:
  // Replays a PDDL plan ("T: (action args) [D]" lines) with the search's rules: at each time the
  // timed literals due, then the ends due, then the starts in the file's order; after each, every
  // running action's over-all conditions. "" when valid and every action has ended with the goal
  // true, else why not.
  std::string Replay(const std::string& plan) const {
    struct Step {
      double time = 0, duration = 0;
      int snap = -1;
    };
    std::vector<Step> steps;
    std::istringstream in(plan);
    static const std::regex kLine(R"((\d+\.\d+): (\([^)]*\))( \[(\d+\.\d+)\])?)");
    for (std::string line; std::getline(in, line);) {
      std::smatch m;
      if (!std::regex_match(line, m, kLine)) return "bad line: " + line;
      Step st{std::stod(m[1]), m[4].matched ? std::stod(m[4]) : 0.0, -1};
      for (int k = 0; k < static_cast<int>(snaps_.size()); ++k)
        if (snaps_[k].name == m[2].str()) st.snap = k;
      if (st.snap < 0) return "unknown action " + m[2].str();
      if (std::fabs(st.duration - snaps_[st.snap].duration) > 1e-6) return "duration: " + line;
      steps.push_back(st);
    }
    std::set<double> times;
    for (const auto& st : steps) times.insert({st.time, st.time + st.duration});
    for (const auto& t : p_.tils) times.insert(t.time);
    std::set<std::string> atoms;
    for (const auto& a : p_.init) atoms.insert(GroundKey(a.pred, a.args));
    std::vector<std::pair<double, int>> running;  // (end, snap)
    auto invariants = [&] {
      for (const auto& [end, s] : running)
        if (!Lits(snaps_[s].inv, atoms)) return false;
      return true;
    };
    for (double t : times) {
      for (const auto& l : p_.tils)
        if (std::fabs(l.time - t) < 1e-9)
          Apply({{GroundKey(l.lit.atom.pred, l.lit.atom.args), l.lit.positive}}, atoms);
      if (!invariants()) return "an over-all condition fails at " + std::to_string(t);
      for (auto it = running.begin(); it != running.end();) {
        if (std::fabs(it->first - t) > 1e-9) {
          ++it;
          continue;
        }
        if (!Lits(snaps_[it->second].post, atoms))
          return "at-end condition of " + snaps_[it->second].name;
        Apply(snaps_[it->second].eff_end, atoms);
        it = running.erase(it);
        if (!invariants()) return "an over-all condition fails at " + std::to_string(t);
      }
      for (const auto& st : steps) {
        if (std::fabs(st.time - t) > 1e-9) continue;
        const Snap& s = snaps_[st.snap];
        if (!Lits(s.pre, atoms)) return "at-start condition of " + s.name;
        for (const auto& r : running)
          if (r.second == st.snap) return s.name + " overlaps itself";
        Apply(s.eff_start, atoms);
        if (s.durative) running.emplace_back(t + st.duration, st.snap);
        if (!invariants()) return "an over-all condition fails at " + std::to_string(t);
      }
    }
    if (!running.empty()) return "an action has not ended";
    return Holds(*p_.goal, atoms) ? "" : "the goal does not hold";
  }
};

std::optional<PddlSim> Make(const std::string& domain, const std::string& problem,
                            std::optional<DomainAst>& d, std::optional<ProblemAst>& p) {
  std::vector<::ctb::pddl::Issue> issues;
  auto de = ::ctb::pddl::ReadSExpr(domain, "d", issues);
  auto pe = ::ctb::pddl::ReadSExpr(problem, "p", issues);
  d = ::ctb::pddl::ReadDomain(*de, "d", issues);
  p = ::ctb::pddl::ReadProblem(*pe, "p", issues);
  EXPECT_TRUE(issues.empty()) << issues[0].ToString();
  if (!d || !p) return std::nullopt;
  return PddlSim(*d, *p);
}

// "" when the simulator accepts the PDDL plan, else why not.
std::string Replay(const std::string& domain, const std::string& problem, const std::string& plan) {
  std::optional<DomainAst> d;
  std::optional<ProblemAst> p;
  auto s = Make(domain, problem, d, p);
  return s ? s->Replay(plan) : "the PDDL does not read";
}

int Simulate(const std::string& domain, const std::string& problem, int bound) {
  std::optional<DomainAst> d;
  std::optional<ProblemAst> p;
  auto s = Make(domain, problem, d, p);
  return s ? s->MinMakespan(bound) : -2;
}

}  // namespace sim

namespace ctb::pddl {
namespace {

using namespace ::ctb::pddl::testing;  // NOLINT: the helpers of these tests

// A robot drops a ball: the ball is no longer carried and is now in the room (one action, two
// objects: the ball's variable and the robot's free hand).
constexpr const char* kBallDomain = R"((define (domain ball)
  (:requirements :typing :durative-actions)
  (:types robot room ball)
  (:predicates (at-robby ?r - robot ?x - room) (at ?b - ball ?x - room)
               (carry ?r - robot ?b - ball) (free ?r - robot))
  (:durative-action move :parameters (?r - robot ?from ?to - room)
    :duration (= ?duration 3)
    :condition (at start (at-robby ?r ?from))
    :effect (and (at start (not (at-robby ?r ?from))) (at end (at-robby ?r ?to))))
  (:durative-action pick :parameters (?r - robot ?b - ball ?x - room)
    :duration (= ?duration 1)
    :condition (and (at start (at ?b ?x)) (over all (at-robby ?r ?x)) (at start (free ?r)))
    :effect (and (at start (not (at ?b ?x))) (at start (not (free ?r))) (at end (carry ?r ?b))))
  (:durative-action drop :parameters (?r - robot ?b - ball ?x - room)
    :duration (= ?duration 2)
    :condition (and (at start (carry ?r ?b)) (over all (at-robby ?r ?x)))
    :effect (and (at start (not (carry ?r ?b))) (at end (at ?b ?x)) (at end (free ?r))))))";

// pick 0-1, move 1-4, drop 4-6: 6 s (the robot may not move while it picks or drops).
constexpr const char* kBallProblem = R"((define (problem ball1) (:domain ball)
  (:objects r1 - robot a b - room ball1 - ball)
  (:init (at-robby r1 a) (at ball1 a) (free r1))
  (:goal (at ball1 b))
  (:metric minimize (total-time))))";

// Durations from static functions: a -> c directly takes 10 s, a -> b -> c takes 3 + 4 = 7 s.
constexpr const char* kDriveDomain = R"((define (domain drive)
  (:requirements :typing :durative-actions :numeric-fluents)
  (:types truck place)
  (:predicates (at ?t - truck ?p - place) (road ?a ?b - place))
  (:functions (drive-time ?a ?b - place) - number)
  (:durative-action drive :parameters (?t - truck ?a ?b - place)
    :duration (= ?duration (drive-time ?a ?b))
    :condition (and (at start (at ?t ?a)) (over all (road ?a ?b)))
    :effect (and (at start (not (at ?t ?a))) (at end (at ?t ?b))))))";

constexpr const char* kDriveProblem = R"((define (problem drive1) (:domain drive)
  (:objects t1 - truck a b c - place)
  (:init (at t1 a) (road a b) (road b c) (road a c)
         (= (drive-time a b) 3) (= (drive-time b c) 4) (= (drive-time a c) 10))
  (:goal (at t1 c))
  (:metric minimize (total-time))))";

// A door that a timed initial literal opens (or closes); through it 3 s, around it 4 + 4 s.
constexpr const char* kDoorDomain = R"((define (domain door)
  (:requirements :typing :durative-actions :timed-initial-literals)
  (:types robot room)
  (:predicates (at ?r - robot ?x - room) (door ?a ?b - room) (hall ?a ?b - room) (open))
  (:durative-action pass :parameters (?r - robot ?a ?b - room)
    :duration (= ?duration 3)
    :condition (and (at start (at ?r ?a)) (over all (door ?a ?b)) (over all (open)))
    :effect (and (at start (not (at ?r ?a))) (at end (at ?r ?b))))
  (:durative-action walk :parameters (?r - robot ?a ?b - room)
    :duration (= ?duration 4)
    :condition (and (at start (at ?r ?a)) (over all (hall ?a ?b)))
    :effect (and (at start (not (at ?r ?a))) (at end (at ?r ?b))))))";

std::string DoorProblem(const std::string& init) {
  return R"((define (problem door1) (:domain door)
  (:objects r1 - robot a b c - room)
  (:init (at r1 a) (door a b) (hall a c) (hall c b) )" +
         init + R"()
  (:goal (at r1 b))
  (:metric minimize (total-time))))";
}

// A match lights at start and goes out at its end without requiring that it is lit (a delete
// without a matching precondition); mending needs the light over all and the hand.
constexpr const char* kMatchDomain = R"((define (domain match)
  (:requirements :typing :durative-actions)
  (:types match fuse)
  (:predicates (handfree) (unused ?m - match) (mended ?f - fuse) (light ?m - match))
  (:durative-action light-match :parameters (?m - match)
    :duration (= ?duration 5)
    :condition (at start (unused ?m))
    :effect (and (at start (not (unused ?m))) (at start (light ?m)) (at end (not (light ?m)))))
  (:durative-action mend :parameters (?f - fuse ?m - match)
    :duration (= ?duration 2)
    :condition (and (at start (handfree)) (over all (light ?m)))
    :effect (and (at start (not (handfree))) (at end (mended ?f)) (at end (handfree))))))";

// Light 0-5, mend f1 0-2 and f2 2-4: 5 s (the plan ends when the match's action does).
constexpr const char* kMatchProblem = R"((define (problem match1) (:domain match)
  (:objects m1 - match f1 f2 - fuse)
  (:init (handfree) (unused m1))
  (:goal (and (mended f1) (mended f2)))
  (:metric minimize (total-time))))";

// Imports, solves with the real minizinc and checks the optimum against the simulator's.
void ExpectOptimum(const std::string& domain, const std::string& problem, int by_hand,
                   bool simulate = true) {
  if (simulate) EXPECT_EQ(sim::Simulate(domain, problem, 40), by_hand) << "the simulator disagrees";
  Imported im = MustImport(Source{"d.pddl", domain}, Source{"p.pddl", problem});
  ASSERT_TRUE(im.domain.is_object());
  Json t = SolveImported(im.domain, im.state_plan);
  ASSERT_TRUE(t.is_object());
  if (by_hand < 0) {
    EXPECT_EQ(t["status"], "infeasible") << t.dump(1);
    return;
  }
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["verified"], true);
  EXPECT_EQ(t["objective"]["value"], by_hand) << t.dump(1);
  // The plan written out as PDDL 2.1 is one the simulator accepts.
  std::string plan = PddlPlan(t, im.actions);
  EXPECT_EQ(sim::Replay(domain, problem, plan), "") << plan;
}

TEST(PddlCompile, OneActionChangesTwoObjects) { ExpectOptimum(kBallDomain, kBallProblem, 6); }

TEST(PddlCompile, DropMovesTheBallAndFreesTheHandAtOneEvent) {
  Imported im = MustImport(Source{"d.pddl", kBallDomain}, Source{"p.pddl", kBallProblem});
  const Json* ball = FindAutomaton(im.domain, "ball1");
  const Json* free = FindAutomaton(im.domain, "r1_free");
  ASSERT_TRUE(ball && free) << im.domain.dump(1);
  // At the drop's end both leave their step locations on the same command.
  const Json* b = FindTransition(*ball, "drop_r1_ball1_b", "at_b");
  const Json* f = FindTransition(*free, "drop_r1_ball1_b_not_free", "free");
  ASSERT_TRUE(b && f) << im.domain.dump(1);
  EXPECT_NE((*b)["guard"].get<std::string>().find("r1_freeu[i]==drop_r1_ball1_b"),
            std::string::npos);
  EXPECT_EQ((*b)["duration"], Json::parse("[2, 2]"));
}

TEST(PddlCompile, DurationsFromStaticFunctions) { ExpectOptimum(kDriveDomain, kDriveProblem, 7); }

// The door's timed initial literal: its automaton's locations are made before the actions that read
// it are written (they were not, and the pass's guard read 'false').
TEST(PddlCompile, TimedInitialLiteralOpensTheDoor) {
  // Closed until 2: through it 2-5 beats around it (8).
  ExpectOptimum(kDoorDomain, DoorProblem("(at 2 (open))"), 5);
}

// Over all (open) on a timed literal's atom is checked at the start and again at the end (its
// automatic transition cannot wait for the pass).
TEST(PddlCompile, TimedInitialLiteralClosesTheDoor) {
  // Open until 2 only: passing takes 3 s and needs it open throughout, so around it: 8.
  ExpectOptimum(kDoorDomain, DoorProblem("(open) (at 2 (not (open)))"), 8);
  // Open until 5: through it, 3.
  ExpectOptimum(kDoorDomain, DoorProblem("(open) (at 5 (not (open)))"), 3);
  // Opens at 1, closes at 3: a 3 s pass fits nowhere (1-4 ends after the close): 8.
  ExpectOptimum(kDoorDomain, DoorProblem("(at 1 (open)) (at 3 (not (open)))"), 8);
}

// Plans out as PDDL 2.1: each action at its start with its duration, in time order.
TEST(PddlPlanOut, TheDoorAndTheBallAsPddlPlans) {
  Imported door =
      MustImport(Source{"d.pddl", kDoorDomain}, Source{"p.pddl", DoorProblem("(at 2 (open))")});
  Json t = SolveImported(door.domain, door.state_plan);
  ASSERT_EQ(t["status"], "optimal");
  EXPECT_EQ(PddlPlan(t, door.actions), "2.000: (pass r1 a b) [3.000]\n");
  // The replay rejects what PDDL 2.1 rejects: the door still closed, an end missing.
  std::string problem = DoorProblem("(at 2 (open))");
  EXPECT_EQ(sim::Replay(kDoorDomain, problem, "2.000: (pass r1 a b) [3.000]\n"), "");
  EXPECT_NE(sim::Replay(kDoorDomain, problem, "0.000: (pass r1 a b) [3.000]\n"), "");
  EXPECT_NE(sim::Replay(kDoorDomain, problem, "0.000: (walk r1 a c) [4.000]\n"), "");
  Imported ball = MustImport(Source{"d.pddl", kBallDomain}, Source{"p.pddl", kBallProblem});
  t = SolveImported(ball.domain, ball.state_plan);
  ASSERT_EQ(t["status"], "optimal");
  EXPECT_EQ(PddlPlan(t, ball.actions),
            "0.000: (pick r1 ball1 a) [1.000]\n"
            "1.000: (move r1 a b) [3.000]\n"
            "4.000: (drop r1 ball1 b) [2.000]\n");
  // An action started but not ended, and transitions of other automata, are left out.
  Json partial = Json::parse(R"({"transitions": [
    {"automaton": "r1", "command": "move_r1_a_b", "event": 1, "from": "a", "time": 0,
     "to": "move_r1_a_b"},
    {"automaton": "run_1", "command": "move_r1_a_b", "event": 1, "from": "idle", "time": 0,
     "to": "busy"}]})");
  EXPECT_EQ(PddlPlan(partial, ball.actions), "");
  EXPECT_EQ(PddlPlan(Json(), ball.actions), "");
}

// `go` deletes (ready) at its start, which `hold` needs over all, and adds (moved) at its end: two
// state variables, (moved) a variable of its own because `crawl` adds it without touching (ready).
// While `hold` runs, the protection keeps (ready) where it is; its partner used to move on the
// command anyway (the action half applied), which let `go` run inside `hold`: 5 where PDDL 2.1
// says 6 (hold 0-5, then go 5-6; crawl takes 20).
constexpr const char* kHalfwayDomain = R"((define (domain halfway)
  (:requirements :durative-actions)
  (:predicates (ready) (moved) (held))
  (:durative-action hold :parameters () :duration (= ?duration 5)
    :condition (over all (ready)) :effect (at end (held)))
  (:durative-action go :parameters () :duration (= ?duration 1)
    :condition (at start (ready)) :effect (and (at start (not (ready))) (at end (moved))))
  (:durative-action crawl :parameters () :duration (= ?duration 20)
    :condition (at start (ready)) :effect (at end (moved)))))";

constexpr const char* kHalfwayProblem = R"((define (problem halfway1) (:domain halfway)
  (:init (ready))
  (:goal (and (moved) (held)))
  (:metric minimize (total-time))))";

TEST(PddlCompile, AProtectedStartHoldsBackTheWholeAction) {
  ExpectOptimum(kHalfwayDomain, kHalfwayProblem, 6);
  // Both transitions of go's start carry hold's protection: the (ready) one its own, the (moved)
  // one as a partner.
  Imported im = MustImport(Source{"d.pddl", kHalfwayDomain}, Source{"p.pddl", kHalfwayProblem});
  const Json* moved = FindAutomaton(im.domain, "moved");
  ASSERT_TRUE(moved) << im.domain.dump(1);
  const Json* start = FindTransition(*moved, "not_moved", "go_not_moved");
  ASSERT_TRUE(start) << moved->dump(1);
  EXPECT_NE((*start)["guard"].get<std::string>().find("heldl[i]!=hold"), std::string::npos)
      << (*start)["guard"];
}

// A crew's day in the style of IPC 2011 crew planning: one crew member whose work and sleep take
// it (available) at their start; waking moves it to the next day, so sleeping before day 1's work
// is done is a dead end the delete relaxation does not see. Reports of tasks the goal does not ask
// about cannot help (left out), and reporting a task again changes nothing (not offered).
constexpr const char* kShiftDomain = R"((define (domain shift)
  (:requirements :typing :durative-actions)
  (:types crew task day)
  (:predicates (available ?c - crew) (today ?c - crew ?d - day) (next ?a ?b - day)
               (done ?t - task ?d - day) (slept ?c - crew ?d - day) (reported ?t - task))
  (:durative-action work :parameters (?t - task ?c - crew ?d - day)
    :duration (= ?duration 2)
    :condition (and (at start (available ?c)) (over all (today ?c ?d)))
    :effect (and (at start (not (available ?c))) (at end (available ?c)) (at end (done ?t ?d))))
  (:durative-action sleep :parameters (?c - crew ?d - day)
    :duration (= ?duration 5)
    :condition (and (at start (available ?c)) (over all (today ?c ?d)))
    :effect (and (at start (not (available ?c))) (at end (slept ?c ?d))))
  (:durative-action wake :parameters (?c - crew ?a ?b - day)
    :duration (= ?duration 1)
    :condition (and (at start (slept ?c ?a)) (at start (today ?c ?a)) (over all (next ?a ?b)))
    :effect (and (at start (not (today ?c ?a))) (at end (today ?c ?b)) (at end (available ?c))))
  (:durative-action report :parameters (?t - task ?c - crew ?d - day)
    :duration (= ?duration 1)
    :condition (and (at start (done ?t ?d)) (over all (today ?c ?d)))
    :effect (at end (reported ?t)))))";

// Work t1 0-2 and t2 2-4 on day 1, sleep 4-9, wake 9-10, work t3 10-12, report it 12-13: 13.
constexpr const char* kShiftProblem = R"((define (problem shift1) (:domain shift)
  (:objects c - crew t1 t2 t3 - task d1 d2 - day)
  (:init (available c) (today c d1) (next d1 d2))
  (:goal (and (done t1 d1) (done t2 d1) (slept c d1) (done t3 d2) (reported t3)))
  (:metric minimize (total-time))))";

TEST(PddlImportRules, ActionsThatCannotHelpOrChangeNothingAreLeftOut) {
  Imported im = MustImport(Source{"d.pddl", kShiftDomain}, Source{"p.pddl", kShiftProblem});
  // Ground: work 3 x 2, sleep 2, wake 1, report 3 x 2 = 15. Five cannot help: the reports of t1
  // and t2 (nothing needs (reported t1) or (reported t2)) and sleeping on day 2 (nothing needs
  // (slept c d2), nor (available c) false).
  EXPECT_EQ(im.irrelevant_actions, 5u);
  EXPECT_EQ(im.ground_actions, 10u);
  for (const auto& a : im.actions) EXPECT_NE(a.pddl, "(sleep c d2)");
  for (const auto& a : im.actions) EXPECT_EQ(a.pddl.find("(report t1"), std::string::npos);
  // Reporting t3 again (from 'reported') changes nothing: no transition leaves 'reported'.
  const Json* t3 = FindAutomaton(im.domain, "t3");
  ASSERT_TRUE(t3) << im.domain.dump(1);
  for (const auto& t : (*t3)["transitions"]) EXPECT_NE(t["from"], "reported") << t.dump();
  // Kept with keep_irrelevant (a model to reuse with other goals).
  ImportOptions keep;
  keep.keep_irrelevant = true;
  auto all = ImportPddl(Source{"d.pddl", kShiftDomain}, Source{"p.pddl", kShiftProblem}, keep);
  ASSERT_TRUE(std::holds_alternative<Imported>(all));
  EXPECT_EQ(std::get<Imported>(all).ground_actions, 15u);
  EXPECT_EQ(std::get<Imported>(all).irrelevant_actions, 0u);
}

// The first-plan engine alone plans the shift (two events per action: more than the default 32
// events are allowed here), its plan passes the verifier and, written as PDDL 2.1, the simulator;
// it is no shorter than the simulator's optimum. The automata no action changes (the reports of
// t1 and t2 left out) do not split the problem: the engine runs on unsplit problems only.
TEST(PddlSearch, TheFirstPlanEnginePlansTheShift) {
  EXPECT_EQ(sim::Simulate(kShiftDomain, kShiftProblem, 20), 13);
  Imported im = MustImport(Source{"d.pddl", kShiftDomain}, Source{"p.pddl", kShiftProblem});
  Diagnostics diags;
  auto d = LoadDomain(im.domain, diags);
  ASSERT_TRUE(d);
  auto sp = LoadStatePlan(im.state_plan, *d, diags);
  ASSERT_TRUE(sp);
  EXPECT_LT(SplitProblem(*d, *sp).size(), 2u);
  FirstPlanOptions o;
  o.objective = Objective::kMakespan;
  o.time_limit_ms = 60000;  // a bound, not a measurement: the engine stops at its first plan
  o.improve_min_ms = 0;
  o.max_events = 64;
  FirstPlanResult r = FindFirstPlan(*d, *sp, o);
  ASSERT_TRUE(r.best) << "expanded " << r.expanded << ", generated " << r.generated;
  EXPECT_EQ(r.rejected, 0);
  EXPECT_EQ(VerifyTrajectory(*r.best, *d, *sp, std::lround(1.0 / d->time_resolution)),
            std::vector<std::string>{});
  EXPECT_GE(r.makespan, 13);
  Json t = TrajectoryToJson(*r.best, *d, *sp, std::lround(1.0 / d->time_resolution));
  std::string plan = PddlPlan(t, im.actions);
  EXPECT_EQ(sim::Replay(kShiftDomain, kShiftProblem, plan), "") << plan;
}

TEST(PddlCompile, DeleteWithoutAMatchingPrecondition) {
  ExpectOptimum(kMatchDomain, kMatchProblem, 5);
}

TEST(PddlCompile, NumericChangeIsALocatedError) {
  std::string d = kDriveDomain;
  d.replace(d.find("(at end (at ?t ?b))"), 19, "(at end (at ?t ?b)) (at end (increase (fuel) 1))");
  auto r = ImportPddl(Source{"d.pddl", d}, Source{"p.pddl", kDriveProblem});
  auto* issues = std::get_if<std::vector<Issue>>(&r);
  ASSERT_TRUE(issues);
  EXPECT_NE((*issues)[0].ToString().find("d.pddl:9:"), std::string::npos) << Issues(*issues);
  EXPECT_NE((*issues)[0].message.find("(increase (fuel) 1)"), std::string::npos);
}

}  // namespace
}  // namespace ctb::pddl
