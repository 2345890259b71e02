// The PDDL import (interchange/pddl, docs/domains.md "Importing PDDL"): a faithful PDDL of the
// thesis' search_rescue imported and solved to the shipped domain's optimum, a presentation-like
// domain from its constants, and one located error, naming the action, per unsupported feature.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "interchange/pddl/import.h"
#include "planner/model/domain.h"
#include "planner/model/state_plan.h"
#include "planner/solve/solve.h"

namespace ctb::pddl {
namespace {

std::string SourceDir() { return CTB_TEST_SOURCE_DIR; }

Source Fixture(const std::string& name) {
  std::string path = SourceDir() + "/tests/interchange/pddl/" + name;
  std::ifstream f(path);
  std::ostringstream s;
  s << f.rdbuf();
  EXPECT_FALSE(s.str().empty()) << path;
  return Source{name, s.str()};
}

std::string Issues(const std::vector<Issue>& issues) {
  std::string s;
  for (const auto& i : issues) s += i.ToString() + "\n";
  return s;
}

Imported MustImport(const Source& d, const std::optional<Source>& p) {
  auto r = ImportPddl(d, p);
  if (auto* e = std::get_if<std::vector<Issue>>(&r)) {
    ADD_FAILURE() << Issues(*e);
    return Imported{};
  }
  return std::get<Imported>(r);
}

std::vector<Issue> MustFail(const Source& d, const std::optional<Source>& p = std::nullopt) {
  auto r = ImportPddl(d, p);
  if (auto* e = std::get_if<std::vector<Issue>>(&r)) return *e;
  ADD_FAILURE() << "imported although it should not:\n" << std::get<Imported>(r).domain.dump(2);
  return {};
}

const Json* FindAutomaton(const Json& domain, const std::string& name) {
  for (const auto& a : domain["automata"])
    if (a["name"] == name) return &a;
  return nullptr;
}

const Json* FindTransition(const Json& automaton, const std::string& from, const std::string& to) {
  for (const auto& t : automaton["transitions"])
    if (t["from"] == from && t["to"] == to) return &t;
  return nullptr;
}

Json SolveImported(const Json& domain_json, const Json& plan_json, SolveOptions o = {}) {
  Diagnostics d;
  auto dom = LoadDomain(domain_json, d);
  EXPECT_TRUE(dom) << (d.errors().empty() ? "" : d.errors()[0].ToString());
  if (!dom) return Json();
  auto sp = LoadStatePlan(plan_json, *dom, d);
  EXPECT_TRUE(sp) << (d.errors().empty() ? "" : d.errors()[0].ToString());
  if (!sp) return Json();
  o.time_limit_ms = 120000;
  auto r = Solve(*dom, *sp, o);
  if (auto* e = std::get_if<Error>(&r)) {
    ADD_FAILURE() << e->ToString();
    return Json();
  }
  return std::get<Json>(r);
}

// Expectations of the one-variable compile rule (before issue 32); to be rewritten.
TEST(PddlImport, DISABLED_SearchRescueBecomesOneAutomatonPerRobotAndDoor) {
  Imported im =
      MustImport(Fixture("search_rescue_domain.pddl"), Fixture("search_rescue_problem.pddl"));
  ASSERT_TRUE(im.domain.is_object());
  EXPECT_EQ(im.domain["name"], "search_rescue");
  std::vector<std::string> names;
  for (const auto& a : im.domain["automata"]) names.push_back(a["name"]);
  EXPECT_EQ(names, (std::vector<std::string>{"robot1", "robot2", "door1", "door2", "door3"}));
  const Json* r1 = FindAutomaton(im.domain, "robot1");
  ASSERT_TRUE(r1);
  // A durative action is a command location chain: commanded into the timed location, then
  // automatic to the new value after the duration.
  const Json* start = FindTransition(*r1, "outside", "drive_robot1_outside_at_door2");
  const Json* end = FindTransition(*r1, "drive_robot1_outside_at_door2", "at_door2");
  ASSERT_TRUE(start && end) << r1->dump(2);
  EXPECT_EQ((*start)["guard"], "robot1u[i]==drive_robot1_outside_at_door2");
  EXPECT_EQ((*end)["duration"], Json::parse("[10, 10]"));
  EXPECT_FALSE(end->contains("guard"));
  // An instantaneous action is one commanded transition; its fluent condition a guard.
  const Json* pass = FindTransition(*r1, "at_door1", "room1");
  ASSERT_TRUE(pass);
  EXPECT_EQ((*pass)["guard"], "robot1u[i]==pass_robot1_door1_at_door1_room1 /\\ door1l[i]==open");
  // The door's opening reads the robot over all: the robot may not leave meanwhile.
  const Json* d1 = FindAutomaton(im.domain, "door1");
  ASSERT_TRUE(d1);
  const Json* open = FindTransition(*d1, "closed", "open_door_robot2_door1_at_door1");
  ASSERT_TRUE(open) << d1->dump(2);
  EXPECT_EQ((*open)["guard"],
            "door1u[i]==open_door_robot2_door1_at_door1 /\\ robot2l[i]==at_door1");
  // The drive away from the door would be protected; the pass needs the door open already.
  const Json* d3 = FindAutomaton(im.domain, "door3");
  ASSERT_TRUE(d3);
  EXPECT_EQ((*d3)["locations"], Json::parse(R"(["open"])"));
  EXPECT_EQ(im.state_plan["initial_state"],
            Json::parse(R"({"robot1": "outside", "robot2": "outside", "door1": "closed",
                            "door2": "closed", "door3": "open"})"));
  EXPECT_EQ(im.state_plan["end_state"]["goal_constraint"],
            "((robot1l[i+1]==person1 /\\ robot2l[i+1]==person2) \\/ "
            "(robot1l[i+1]==person2 /\\ robot2l[i+1]==person1))");
  EXPECT_EQ(im.state_plan["objective"], "makespan");
}

// The optimum of the shipped search_rescue for this goal is 11 s (tests/planner/solve_test.cpp,
// the thesis 5.3.2): both robots through door 1, one opening it.
TEST(PddlImport, SearchRescueSolvesToTheShippedOptimum) {
  Imported im =
      MustImport(Fixture("search_rescue_domain.pddl"), Fixture("search_rescue_problem.pddl"));
  Json t = SolveImported(im.domain, im.state_plan);
  ASSERT_TRUE(t.is_object());
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["verified"], true);
  EXPECT_EQ(t["objective"]["kind"], "makespan");
  EXPECT_EQ(t["objective"]["value"], 11);
  int opened = 0;
  for (const auto& tr : t["transitions"])
    if (tr["automaton"] == "door1" && tr["to"] == "open") ++opened;
  EXPECT_EQ(opened, 1);
  // The same optimum found and proven by MiniZinc with Gecode alone (no first-plan engine, no
  // static lower bound).
  SolveOptions exact;
  exact.search = "g_first";
  exact.first_plan_ms = 0;
  exact.static_analysis = false;
  Json g = SolveImported(im.domain, im.state_plan, exact);
  ASSERT_TRUE(g.is_object());
  EXPECT_EQ(g["status"], "optimal");
  EXPECT_EQ(g["verified"], true);
  EXPECT_EQ(g["objective"]["value"], 11);
  EXPECT_EQ(g["stats"]["solver"], "gecode");
}

TEST(PddlImport, OneRobotRescuingPersonOneTakes11Seconds) {
  Source p = Fixture("search_rescue_problem.pddl");
  auto at = p.text.find("(:goal");
  auto end = p.text.find("(:metric");
  p.text.replace(at, end - at, "(:goal (at robot1 person1))\n  ");
  Imported im = MustImport(Fixture("search_rescue_domain.pddl"), p);
  EXPECT_EQ(im.state_plan["end_state"]["goal_constraint"].get<std::string>().rfind(
                "(robot1l[i+1]==person1) /\\ ", 0),
            0u);
  Json t = SolveImported(im.domain, im.state_plan);
  ASSERT_TRUE(t.is_object());
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["objective"]["value"], 11);
}

// Expectations of the one-variable compile rule (before issue 32); to be rewritten.
TEST(PddlImport, DISABLED_PresentationFromConstantsWithoutAProblem) {
  Imported im = MustImport(Fixture("presentation_domain.pddl"), std::nullopt);
  EXPECT_TRUE(im.state_plan.is_null());
  std::vector<std::string> names;
  for (const auto& a : im.domain["automata"]) names.push_back(a["name"]);
  EXPECT_EQ(names, (std::vector<std::string>{"comp", "conn", "proj"}));
  const Json* proj = FindAutomaton(im.domain, "proj");
  ASSERT_TRUE(proj);
  EXPECT_EQ((*proj)["locations"], Json::parse(R"(["proj_off", "proj_on", "warm_up_proj_conn",
                                                   "cool_down_proj"])"));
  // (>= ?duration 60) (<= ?duration 90): the planner picks the end within the bounds.
  const Json* cool = FindTransition(*proj, "cool_down_proj", "proj_off");
  ASSERT_TRUE(cool);
  EXPECT_EQ((*cool)["duration"], Json::parse("[60, 90]"));
  EXPECT_EQ((*cool)["controllable"], true);
  // Over all (connected conn): the cable may not be disconnected while the projector warms up.
  const Json* conn = FindAutomaton(im.domain, "conn");
  ASSERT_TRUE(conn);
  const Json* disconnect = FindTransition(*conn, "connected", "disconnected");
  ASSERT_TRUE(disconnect);
  EXPECT_EQ((*disconnect)["guard"], "connu[i]==disconnect_conn /\\ projl[i]!=warm_up_proj_conn");
  EXPECT_EQ((*disconnect)["cost"], 2);
  // Connect first (the computer must be off), then warm up: on at 30 s.
  Json plan = Json::parse(R"({
    "initial_state": {"comp": "comp_off", "conn": "disconnected", "proj": "proj_off"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint": "projl[i+1]==proj_on"},
    "objective": "makespan"})");
  Json t = SolveImported(im.domain, plan);
  ASSERT_TRUE(t.is_object());
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["objective"]["value"], 30);
}

// One-argument and 0-ary predicates that actions switch alone are boolean variables; a negative
// over-all condition keeps the value away (and the actions heading for it); durations of 0.5 s
// and 2.25 s set the time resolution; a duration range lets the planner pick the end.
constexpr const char* kLab = R"((define (domain Lab)
  (:requirements :typing :durative-actions :negative-preconditions)
  (:types arm door)
  (:constants a1 a2 - arm d - door)
  (:predicates (lit) (busy ?a - arm) (idle ?a - arm) (open ?d - door) (locked ?d - door))
  (:durative-action switch-on :parameters () :duration (= ?duration 0.5)
     :condition (over all (not (open d))) :effect (at end (lit)))
  (:durative-action lock :parameters (?d - door) :duration (= ?duration 2.25)
     :condition (at start (not (open ?d))) :effect (at end (locked ?d)))
  (:durative-action open-it :parameters (?d - door) :duration (= ?duration 1)
     :condition (at start (not (locked ?d))) :effect (at end (open ?d)))
  (:durative-action work :parameters (?a - arm)
     :duration (and (>= ?duration 1) (<= ?duration 3))
     :condition (and (at start (idle ?a)) (over all (lit)))
     :effect (and (at start (not (idle ?a))) (at end (busy ?a))))
  (:action finish :parameters (?a - arm)
     :precondition (busy ?a) :effect (and (not (busy ?a)) (idle ?a)))))";

// Expectations of the one-variable compile rule (before issue 32); to be rewritten.
TEST(PddlImport, DISABLED_BooleanFluentsNegativeOverAllAndFineDurations) {
  Source p{"lab_problem.pddl", R"((define (problem p) (:domain lab) (:objects a3 - arm)
    (:init (idle a1) (idle a2))
    (:goal (and (busy a1) (not (open d))))
    (:metric minimize (total-time))))"};
  auto r = ImportPddl(Source{"lab.pddl", kLab}, p);
  ASSERT_TRUE(std::holds_alternative<Imported>(r)) << Issues(std::get<std::vector<Issue>>(r));
  const Imported& im = std::get<Imported>(r);
  EXPECT_EQ(im.domain["name"], "lab");
  EXPECT_EQ(im.domain["time_resolution"], 0.01);
  std::vector<std::string> names;
  for (const auto& a : im.domain["automata"]) names.push_back(a["name"]);
  EXPECT_EQ(names, (std::vector<std::string>{"lit", "a1", "a2", "d_open", "d_locked"}));
  // a3 has no value of idle/busy: left out, with a warning.
  ASSERT_EQ(im.warnings.size(), 1u);
  EXPECT_NE(im.warnings[0].message.find("'a3' has no initial value"), std::string::npos);
  const Json* lit = FindAutomaton(im.domain, "lit");
  ASSERT_TRUE(lit);
  EXPECT_EQ((*lit)["locations"], Json::parse(R"(["not_lit", "lit", "switch_on"])"));
  const Json* on = FindTransition(*lit, "not_lit", "switch_on");
  ASSERT_TRUE(on);
  EXPECT_EQ((*on)["guard"], "litu[i]==switch_on /\\ d_openl[i]!=open /\\ d_openl[i]!=open_it_d");
  EXPECT_EQ((*FindTransition(*lit, "switch_on", "lit"))["duration"], Json::parse("[0.5, 0.5]"));
  const Json* door = FindAutomaton(im.domain, "d_open");
  ASSERT_TRUE(door);
  EXPECT_EQ((*FindTransition(*door, "not_open", "open_it_d"))["guard"],
            "d_openu[i]==open_it_d /\\ d_lockedl[i]!=locked /\\ litl[i]!=switch_on");
  EXPECT_EQ(im.state_plan["initial_state"],
            Json::parse(R"({"lit": "not_lit", "a1": "idle", "a2": "idle", "d_open": "not_open",
                            "d_locked": "not_locked"})"));
  EXPECT_EQ(im.state_plan["end_state"]["goal_constraint"],
            "(a1l[i+1]==busy /\\ (not d_openl[i+1]==open))");
  // Light on at 0.5 s, work for the shortest allowed 1 s: 1.5 s.
  Json t = SolveImported(im.domain, im.state_plan);
  ASSERT_TRUE(t.is_object());
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["objective"]["value"], 1.5);
}

// ---- What cannot be mapped: one issue naming the action, at the line of the construct. ----

// The presentation domain with `extra` added as its last action; its first line is `line`.
Source WithAction(const std::string& extra, int* line = nullptr) {
  Source s = Fixture("presentation_domain.pddl");
  auto close = s.text.rfind(')');
  if (line)
    *line = 1 + static_cast<int>(std::count(s.text.begin(), s.text.begin() + close, '\n')) + 1;
  s.text.insert(close, "\n" + extra);
  return s;
}

void ExpectOneIssue(const std::vector<Issue>& issues, const std::string& action, int line,
                    const std::string& part) {
  ASSERT_FALSE(issues.empty());
  bool found = false;
  for (const auto& i : issues)
    found = found ||
            (i.action == action && i.line == line && i.message.find(part) != std::string::npos);
  EXPECT_TRUE(found) << "want action '" << action << "' line " << line << " '" << part << "' in\n"
                     << Issues(issues);
  EXPECT_NE(issues[0].ToString().find("presentation_domain.pddl:" + std::to_string(line) + ":"),
            std::string::npos)
      << issues[0].ToString();
}

// Expectations of the one-variable compile rule (before issue 32); to be rewritten.
TEST(PddlImportErrors, DISABLED_ActionChangingTwoStateVariables) {
  int line = 0;
  auto issues = MustFail(WithAction(R"((:durative-action boot-and-connect
    :parameters (?c - computer ?k - cable)
    :duration (= ?duration 15)
    :condition (and (at start (comp-off ?c)) (at start (disconnected ?k)))
    :effect (and (at start (not (comp-off ?c))) (at end (comp-on ?c))
                 (at start (not (disconnected ?k))) (at end (connected ?k)))))",
                                    &line));
  ExpectOneIssue(issues, "boot-and-connect", line + 5, "changes two state variables at once");
  EXPECT_NE(issues[0].message.find("(comp-off ?c) of ?c"), std::string::npos) << issues[0].message;
  EXPECT_NE(issues[0].message.find("of ?k"), std::string::npos) << issues[0].message;
}

TEST(PddlImportErrors, NumericFluentEffect) {
  int line = 0;
  auto issues = MustFail(WithAction(R"((:durative-action charge
    :parameters (?c - computer)
    :duration (= ?duration 5)
    :condition (at start (comp-on ?c))
    :effect (and (at end (increase (energy ?c) 10)))))",
                                    &line));
  ExpectOneIssue(issues, "charge", line + 4, "numeric fluents");
}

TEST(PddlImportErrors, NumericCondition) {
  int line = 0;
  auto issues = MustFail(WithAction(R"((:durative-action boot-fast
    :parameters (?c - computer)
    :duration (= ?duration 5)
    :condition (and (at start (comp-off ?c)) (at start (>= (energy ?c) 10)))
    :effect (and (at start (not (comp-off ?c))) (at end (comp-on ?c)))))",
                                    &line));
  ExpectOneIssue(issues, "boot-fast", line + 3, "numeric fluents");
}

TEST(PddlImportErrors, DisjunctiveCondition) {
  int line = 0;
  auto issues = MustFail(WithAction(R"((:action connect-either
    :parameters (?k - cable ?c - computer)
    :precondition (and (disconnected ?k)
                       (or (comp-off ?c) (comp-on ?c)))
    :effect (and (not (disconnected ?k)) (connected ?k))))",
                                    &line));
  ExpectOneIssue(issues, "connect-either", line + 3, "cannot be mapped");
}

// Expectations of the one-variable compile rule (before issue 32); to be rewritten.
TEST(PddlImportErrors, DISABLED_AtEndCondition) {
  int line = 0;
  auto issues = MustFail(WithAction(R"((:durative-action boot-connected
    :parameters (?c - computer ?k - cable)
    :duration (= ?duration 15)
    :condition (and (at start (comp-off ?c))
                    (at end (connected ?k)))
    :effect (and (at start (not (comp-off ?c))) (at end (comp-on ?c)))))",
                                    &line));
  ExpectOneIssue(issues, "boot-connected", line + 4, "(at end (connected ?k)) cannot be mapped");
}

TEST(PddlImportErrors, ConditionalAndUniversalEffects) {
  int line = 0;
  auto issues = MustFail(WithAction(R"((:action reset
    :parameters (?c - computer)
    :precondition (comp-on ?c)
    :effect (and (not (comp-on ?c)) (comp-off ?c)
                 (when (connected conn) (disconnected conn)))))",
                                    &line));
  ExpectOneIssue(issues, "reset", line + 4, "conditional effect");
  issues = MustFail(WithAction(R"((:action reset-all
    :parameters ()
    :precondition ()
    :effect (forall (?c - computer) (and (not (comp-on ?c)) (comp-off ?c)))))",
                               &line));
  ExpectOneIssue(issues, "reset-all", line + 3, "quantified");
}

// Expectations of the one-variable compile rule (before issue 32); to be rewritten.
TEST(PddlImportErrors, DISABLED_DeleteWithoutRequiringIt) {
  int line = 0;
  auto issues = MustFail(WithAction(R"((:durative-action force-on
    :parameters (?c - computer)
    :duration (= ?duration 1)
    :condition ()
    :effect (and (at start (not (comp-off ?c))) (at end (comp-on ?c)))))",
                                    &line));
  ExpectOneIssue(issues, "force-on", line + 4, "without requiring it");
}

// Expectations of the one-variable compile rule (before issue 32); to be rewritten.
TEST(PddlImportErrors, DISABLED_AddingAValueAloneBreaksMutualExclusion) {
  int line = 0;
  auto issues = MustFail(WithAction(R"((:action wake
    :parameters (?c - computer)
    :precondition ()
    :effect (comp-on ?c)))",
                                    &line));
  ExpectOneIssue(issues, "wake", line + 3, "without deleting another value");
}

// Expectations of the one-variable compile rule (before issue 32); to be rewritten.
TEST(PddlImportErrors, DISABLED_StaticPredicateNeedsTheProblem) {
  auto issues = MustFail(Fixture("search_rescue_domain.pddl"));
  bool statics = false, functions = false;
  for (const auto& i : issues) {
    statics = statics || (i.action == "open-door" &&
                          i.message.find("static predicate 'in-front'") != std::string::npos);
    functions = functions ||
                (i.action == "drive" && i.message.find("reads a function") != std::string::npos);
  }
  EXPECT_TRUE(statics && functions) << Issues(issues);
}

// Expectations of the one-variable compile rule (before issue 32); to be rewritten.
TEST(PddlImportErrors, DISABLED_ProblemConstructs) {
  Source d = Fixture("search_rescue_domain.pddl");
  Source p = Fixture("search_rescue_problem.pddl");
  Source til = p;
  til.text.replace(til.text.find("(open door3)"), 12, "(at 5 (open door3))");
  auto issues = MustFail(d, til);
  ASSERT_FALSE(issues.empty());
  EXPECT_NE(issues[0].message.find("timed initial literal"), std::string::npos) << Issues(issues);
  EXPECT_EQ(issues[0].line, 10);
  Source metric = p;
  metric.text.replace(metric.text.find("(total-time)"), 12, "(energy)");
  issues = MustFail(d, metric);
  ASSERT_FALSE(issues.empty());
  EXPECT_NE(issues[0].message.find("metric"), std::string::npos) << Issues(issues);
  Source twice = p;
  twice.text.replace(twice.text.find("(closed door1)"), 14, "(closed door1) (open door1)");
  issues = MustFail(d, twice);
  ASSERT_FALSE(issues.empty());
  EXPECT_NE(issues[0].message.find("two initial values"), std::string::npos) << Issues(issues);
}

TEST(PddlImportErrors, SyntaxErrorsAreLocated) {
  Source s{"broken.pddl",
           "(define (domain x)\n  (:predicates (p ?a))\n  (:action a :parameters (?a)\n"};
  auto issues = MustFail(s);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].ToString(), "broken.pddl:3:3: '(' is never closed");
  s.text = "(define (domain x)) (extra)";
  issues = MustFail(s);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].ToString(), "broken.pddl:1:21: text after the end of the PDDL definition");
  s.text = std::string(100, '(');
  issues = MustFail(s);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_NE(issues[0].message.find("nested more than"), std::string::npos);
}

TEST(PddlImportErrors, DerivedPredicates) {
  Source s = WithAction("(:derived (ready ?c - computer) (comp-on ?c))");
  auto issues = MustFail(s);
  ASSERT_FALSE(issues.empty());
  EXPECT_NE(issues[0].message.find("derived predicates"), std::string::npos) << Issues(issues);
}

TEST(PddlImportErrors, TooManyGroundActionsIsRefused) {
  Source d = Fixture("search_rescue_domain.pddl");
  ImportOptions o;
  o.max_ground_actions = 3;
  auto r = ImportPddl(d, Fixture("search_rescue_problem.pddl"), o);
  auto* issues = std::get_if<std::vector<Issue>>(&r);
  ASSERT_TRUE(issues);
  EXPECT_NE(Issues(*issues).find("more than 3 ground actions"), std::string::npos)
      << Issues(*issues);
}

}  // namespace
}  // namespace ctb::pddl
#include "pddl_semantics_test.inc"
