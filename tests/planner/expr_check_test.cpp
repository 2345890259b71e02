#include "planner/model/expr_check.h"

#include <gtest/gtest.h>

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

TEST(NearestName, OnlySuggestsCloseNames) {
  EXPECT_EQ(NearestName("compOfff", {"compOff", "compOn"}), "compOff");
  EXPECT_EQ(NearestName("zzzzzz", {"compOff", "compOn"}), "");
}

}  // namespace
}  // namespace ctb
