#include "planner/model/expr_check.h"

#include <gtest/gtest.h>

#include <map>

#include "planner/expr/expr_print.h"
#include "test_util.h"

namespace ctb {
namespace {

using testing::HasError;

Scope PresentationScope() {
  return Scope{&testing::ShippedDomain("presentation"), {"ProjectorOn"}, {"OnWithin60"}};
}

std::optional<Expr> Check(const std::string& text, ExprContext ctx, Diagnostics& d,
                          ExprInfo* info = nullptr) {
  return ParseChecked(text, PresentationScope(), ctx, "/p", d, info);
}

TEST(CheckExpr, ResolvesLocationsCommandsAndSynonyms) {
  Diagnostics d;
  auto e = Check("proj[i+1]==projOn /\\ compu[i]==compTurnOff", ExprContext::kCondition, d);
  ASSERT_TRUE(e) << testing::AllErrors(d);
  const Expr& loc = e->kids[0];
  EXPECT_EQ(loc.var_kind, VarKind::kLocation);
  EXPECT_EQ(loc.target, 2);      // proj is the third automaton
  EXPECT_EQ(loc.value_code, 2);  // projOn is its third location
  const Expr& cmd = e->kids[1];
  EXPECT_EQ(cmd.var_kind, VarKind::kCommand);
  EXPECT_EQ(cmd.target, 0);
  EXPECT_EQ(cmd.value_code, 2);  // 0 is the no-op, compTurnOff the second command
}

TEST(CheckExpr, UnknownLocationSuggestsTheNearestWithOffset) {
  Diagnostics d;
  EXPECT_FALSE(Check("projl[i]==projOnn", ExprContext::kCondition, d));
  EXPECT_TRUE(HasError(d, "/p",
                       "unknown location 'projOnn' of automaton 'proj' (did you mean 'projOn'?)",
                       std::size_t{10}));
}

TEST(CheckExpr, UnknownVariableSuggestsTheNearest) {
  Diagnostics d;
  EXPECT_FALSE(Check("compl[i]==compOn /\\ prjl[i]==projOn", ExprContext::kCondition, d));
  EXPECT_TRUE(HasError(d, "/p", "unknown variable 'prjl' (did you mean 'projl'?)", std::size_t{20}));
}

TEST(CheckExpr, UnknownCommandAndWrongKindOfValue) {
  Diagnostics d;
  EXPECT_FALSE(Check("compu[i]==compOn", ExprContext::kCondition, d));
  EXPECT_TRUE(HasError(d, "/p", "unknown command 'compOn' of automaton 'comp'", std::size_t{10}));
}

TEST(CheckExpr, ReportsEveryBadAtom) {
  Diagnostics d;
  EXPECT_FALSE(Check("compl[i]==x /\\ projl[i]==y", ExprContext::kCondition, d));
  EXPECT_EQ(d.errors().size(), 2u);
}

TEST(CheckExpr, AcceptingAutomatonStates) {
  Diagnostics d;
  auto e = Check("temporalAcceptConstraint_Traj_OnWithin60[i]==tempActive /\\ "
                 "epAcceptAutomatonTraj_ProjectorOn[i]==epAccepted",
                 ExprContext::kCondition, d);
  ASSERT_TRUE(e) << testing::AllErrors(d);
  EXPECT_EQ(e->kids[0].var_kind, VarKind::kTemporalState);
  EXPECT_EQ(e->kids[0].value_code, 1);
  EXPECT_EQ(e->kids[1].var_kind, VarKind::kEpisodeState);
  EXPECT_EQ(e->kids[1].value_code, 2);
}

TEST(CheckExpr, UnknownAcceptingAutomatonAndState) {
  Diagnostics d;
  EXPECT_FALSE(Check("temporalAcceptConstraint_Traj_OnWithin6[i]==tempActive",
                     ExprContext::kCondition, d));
  EXPECT_TRUE(HasError(d, "/p", "unknown temporal constraint 'OnWithin6' (did you mean 'OnWithin60'?)",
                       std::size_t{0}));
  Diagnostics d2;
  EXPECT_FALSE(Check("epAcceptAutomatonTraj_ProjectorOn[i]==tempActive", ExprContext::kCondition, d2));
  EXPECT_TRUE(HasError(d2, "/p", "unknown state 'tempActive'", std::size_t{38}));
}

TEST(CheckExpr, AcceptingAutomataOnlyAtI) {
  Diagnostics d;
  EXPECT_FALSE(Check("temporalAcceptConstraint_Traj_OnWithin60[i+1]==tempActive",
                     ExprContext::kCondition, d));
  EXPECT_TRUE(HasError(d, "/p", "can only be read at [i]", std::size_t{41}));
}

TEST(CheckExpr, GuardsReadOnlyTheStageBefore) {
  Diagnostics d;
  EXPECT_FALSE(Check("compl[i+1]==compOff", ExprContext::kGuard, d));
  EXPECT_TRUE(HasError(d, "/p", "write 'compl[i]'", std::size_t{6}));
  Diagnostics d2;
  EXPECT_FALSE(Check("compl[0]==compOff", ExprContext::kGuard, d2));
  Diagnostics d3;
  EXPECT_FALSE(Check("temporalAcceptConstraint_Traj_OnWithin60[i]==tempActive", ExprContext::kGuard, d3));
  EXPECT_TRUE(HasError(d3, "/p", "a guard cannot read"));
}

TEST(CheckExpr, FixedStageIsAWarningInConditions) {
  Diagnostics d;
  auto e = Check("projl[0]==projOff", ExprContext::kCondition, d);
  ASSERT_TRUE(e);
  EXPECT_TRUE(d.ok());
  ASSERT_EQ(d.warnings().size(), 1u);
  EXPECT_EQ(d.warnings()[0].offset, 6u);
  EXPECT_NE(d.warnings()[0].message.find("did you mean [i]"), std::string::npos);
}

TEST(CheckExpr, ClassifiesChangeAndStateConditions) {
  Diagnostics d;
  ExprInfo change, state, self_ref;
  ASSERT_TRUE(Check("projl[i]==projOff /\\ projl[i+1]==projWarmUp", ExprContext::kCondition, d, &change));
  ASSERT_TRUE(Check("projl[i+1]==projOn", ExprContext::kCondition, d, &state));
  ASSERT_TRUE(Check("projl[i+1]==projOn /\\ temporalAcceptConstraint_Traj_OnWithin60[i]==tempActive",
                    ExprContext::kCondition, d, &self_ref));
  EXPECT_TRUE(change.IsChange());
  EXPECT_FALSE(state.IsChange());
  EXPECT_FALSE(self_ref.IsChange());  // accepting automata do not make a change condition
  EXPECT_EQ(self_ref.temporals_read.count(0), 1u);
}

TEST(PrintMiniZinc, PrintsOnlyCodesAndTheCallersTerms) {
  Diagnostics d;
  auto e = Check("not (projl[i]==projOn) /\\ compu[i]!=compTurnOn \\/ true -> connl[i+1]==connected",
                 ExprContext::kCondition, d);
  ASSERT_TRUE(e);
  auto printer = [](const Expr& atom) {
    return std::string(atom.var_kind == VarKind::kCommand ? "U" : "L") + "[" +
           std::to_string(atom.target + 1) + "," +
           (atom.index.kind == IndexKind::kIPlus1 ? "k+1" : "k") + "]";
  };
  std::string out = PrintMiniZinc(*e, printer);
  EXPECT_EQ(out, "((((not (L[3,k] = 2)) /\\ (U[1,k] != 1)) \\/ true) -> (L[2,k+1] = 1))");
  for (const char* name : {"proj", "comp", "conn", "On", "Turn"})
    EXPECT_EQ(out.find(name), std::string::npos) << name;
}

TEST(Evaluate, FollowsTheConnectives) {
  Diagnostics d;
  auto e = Check("(projl[i]==projOn <-> compl[i]==compOn) /\\ not connl[i]==connected",
                 ExprContext::kCondition, d);
  ASSERT_TRUE(e);
  std::vector<int> values = {2, 0, 2};  // comp on, conn disconnected, proj on
  auto value_of = [&](const Expr& a) { return values[a.target]; };
  EXPECT_TRUE(Evaluate(*e, value_of));
  values[1] = 1;
  EXPECT_FALSE(Evaluate(*e, value_of));
  values = {0, 0, 2};
  EXPECT_FALSE(Evaluate(*e, value_of));
}

// The coupled search_rescue as written (config/templates/search_rescue_team.json), with N robots:
// its templates (robot, door) are the ranges of quantifiers.
const Domain& Team(int n) {
  static std::map<int, Domain> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  Diagnostics d;
  auto t = ReadJsonFile(testing::ConfigDir() + "/templates/search_rescue_team.json", d);
  if (!t) abort();
  ExpandOptions o;
  o.parameters["N"] = n;
  auto dom = LoadDomain(*t, d, o);
  if (!dom) abort();
  return cache.emplace(n, std::move(*dom)).first->second;
}

std::optional<Expr> CheckTeam(const std::string& text, int n, Diagnostics& d,
                              QuantifierBudget* budget = nullptr) {
  Scope scope{&Team(n), {}, {}};
  scope.budget = budget;
  return ParseChecked(text, scope, ExprContext::kCondition, "/end_state/goal_constraint", d);
}

TEST(Quantifiers, TheDomainKeepsItsTemplates) {
  const Domain& d = Team(3);
  ASSERT_EQ(d.templates.size(), 2u);
  EXPECT_EQ(d.templates[0].name, "robot");
  EXPECT_EQ(d.templates[0].values, (std::vector<std::string>{"1", "2", "3"}));
  EXPECT_EQ(d.templates[1].name, "door");
  EXPECT_EQ(d.templates[1].values, (std::vector<std::string>{"1", "2"}));
  EXPECT_TRUE(testing::ShippedDomain("search_rescue").templates.empty());
}

TEST(Quantifiers, ExpandToTheWrittenOutConjunction) {
  Diagnostics d;
  auto q = CheckTeam("every(k in robot: robot{k}l[i+1]==rescuedPerson{k})", 3, d);
  ASSERT_TRUE(q) << testing::AllErrors(d);
  EXPECT_FALSE(HasQuantifier(*q));
  auto w = CheckTeam("robot1l[i+1]==rescuedPerson1 /\\ robot2l[i+1]==rescuedPerson2 /\\ "
                     "robot3l[i+1]==rescuedPerson3", 3, d);
  ASSERT_TRUE(w) << testing::AllErrors(d);
  // The same atoms, checked alike; the quantifier joins them as a balanced tree.
  const DomainValueNames names(Team(3));
  EXPECT_EQ(PrintSource(Normalize(*q, names.Function())), PrintSource(Normalize(*w, names.Function())));
  std::vector<const Expr*> atoms;
  Flatten(*q, Expr::Op::kAnd, atoms);
  ASSERT_EQ(atoms.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(atoms[k]->var_kind, VarKind::kLocation);
    EXPECT_EQ(atoms[k]->target, k);
    EXPECT_EQ(atoms[k]->binding, "k=" + std::to_string(k + 1));
  }
}

TEST(Quantifiers, AnyIsADisjunctionAndEmptyRangesAreConstants) {
  Diagnostics d;
  auto e = CheckTeam("every(p in 1..2: any(k in robot: robot{k}l[i+1]==rescuedPerson{p}))", 2, d);
  ASSERT_TRUE(e) << testing::AllErrors(d);
  // Persons 1 and 2 each rescued by some robot.
  std::vector<int> loc(Team(2).automata.size(), 0);
  const int p1 = Team(2).automata[0].LocationIndex("rescuedPerson1");
  const int p2 = Team(2).automata[0].LocationIndex("rescuedPerson2");
  auto value_of = [&](const Expr& a) { return loc[a.target]; };
  EXPECT_FALSE(Evaluate(*e, value_of));
  loc[1] = p1;
  EXPECT_FALSE(Evaluate(*e, value_of));
  loc[0] = p2;
  EXPECT_TRUE(Evaluate(*e, value_of));
  auto t = CheckTeam("every(k in 3..2: false) /\\ not any(k in 1..0: true)", 2, d);
  ASSERT_TRUE(t) << testing::AllErrors(d);
  EXPECT_TRUE(Evaluate(*t, value_of));
}

TEST(Quantifiers, ErrorsAreLocatedAndNameTheValues) {
  const std::string goal = "/end_state/goal_constraint";
  {
    Diagnostics d;
    EXPECT_FALSE(CheckTeam("every(k in robt: robot{k}l[i+1]==outside)", 2, d));
    EXPECT_TRUE(testing::HasError(d, goal, "unknown template 'robt' (templates: robot, door)",
                                  std::size_t{11}))
        << testing::AllErrors(d);
  }
  {
    // One error per place in the text, not one per robot, with the first value that fails.
    Diagnostics d;
    EXPECT_FALSE(CheckTeam("every(k in robot: robot{k}l[i+1]==rescuedPersn{k})", 3, d));
    ASSERT_EQ(d.errors().size(), 1u) << testing::AllErrors(d);
    EXPECT_TRUE(testing::HasError(d, goal,
                                  "unknown location 'rescuedPersn1' of automaton 'robot1' (did you "
                                  "mean 'rescuedPerson1'?) (where k=1)",
                                  std::size_t{34}))
        << testing::AllErrors(d);
  }
  {
    Diagnostics d;
    EXPECT_FALSE(CheckTeam("every(k in 1..3: robot{k}l[i+1]==outside)", 2, d));
    EXPECT_TRUE(testing::HasError(d, goal, "unknown variable 'robot3l'", std::size_t{17}))
        << testing::AllErrors(d);
  }
  {
    Scope plain{&testing::ShippedDomain("search_rescue"), {}, {}};
    Diagnostics d;
    EXPECT_FALSE(ParseChecked("every(k in robot: robot{k}l[i+1]==outside)", plain,
                              ExprContext::kCondition, goal, d));
    EXPECT_TRUE(testing::HasError(d, goal, "the domain has no templates", std::size_t{11}))
        << testing::AllErrors(d);
    // Integer ranges need no template.
    Diagnostics ok;
    EXPECT_TRUE(ParseChecked("every(k in 1..2: robot{k}l[i+1]==outside)", plain,
                             ExprContext::kCondition, goal, ok))
        << testing::AllErrors(ok);
  }
}

TEST(Quantifiers, TheExpansionIsBoundedByANodeBudget) {
  // A short text that asks for a billion nodes stops at the budget, at the quantifier that was
  // being expanded.
  Diagnostics d;
  EXPECT_FALSE(CheckTeam(
      "every(a in 1..1000: every(b in 1..1000: every(c in 1..1000: robot1l[i]==outside)))", 2, d));
  EXPECT_TRUE(testing::HasError(d, "/end_state/goal_constraint",
                                "the quantifiers expand to more than 32768 nodes", std::size_t{40}))
      << testing::AllErrors(d);
  // The budget is shared: expressions that each fit stop together at the same bound.
  QuantifierBudget shared;
  Diagnostics d2;
  const std::string text = "every(a in 1..4000: robot1l[i]==outside)";  // about 8,000 nodes
  int loaded = 0;
  for (int k = 0; k < 10; ++k)
    if (CheckTeam(text, 2, d2, &shared)) ++loaded;
  EXPECT_EQ(loaded, 4);
  EXPECT_EQ(d2.errors().size(), 6u);
  EXPECT_TRUE(testing::HasError(d2, "/end_state/goal_constraint", "more than 32768 nodes"));
  // A range alone is bounded too.
  Diagnostics d3;
  EXPECT_FALSE(CheckTeam("every(a in 0..999999: true)", 2, d3));
  EXPECT_TRUE(testing::HasError(d3, "/end_state/goal_constraint", "at most 100000 values"))
      << testing::AllErrors(d3);
}

TEST(NearestName, OnlySuggestsCloseNames) {
  EXPECT_EQ(NearestName("compOfff", {"compOff", "compOn"}), "compOff");
  EXPECT_EQ(NearestName("zzzzzz", {"compOff", "compOn"}), "");
}

}  // namespace
}  // namespace ctb
