// The normalisation pass (planner/expr/normalize.h): equivalent forms an LLM writes come out
// alike, and the normalised tree has the truth value of the original on every assignment.
#include "planner/expr/normalize.h"

#include <gtest/gtest.h>

#include "planner/expr/expr_print.h"
#include "planner/model/expr_check.h"
#include "planner/solve/decompose.h"
#include "test_util.h"

namespace ctb {
namespace {

Expr Checked(const std::string& text, const Domain& d) {
  Diagnostics diags;
  Scope scope{&d, {}, {}};
  auto e = ParseChecked(text, scope, ExprContext::kCondition, "/x", diags);
  EXPECT_TRUE(e) << testing::AllErrors(diags);
  return e ? *e : Expr{};
}

std::string Norm(const std::string& text) {
  const Domain& d = testing::ShippedDomain("presentation");
  DomainValueNames names(d);
  return PrintSource(Normalize(Checked(text, d), names.Function()));
}

TEST(Normalize, FoldsConstantsAndDoubleNegation) {
  EXPECT_EQ(Norm("(true) /\\ (true)"), "true");
  EXPECT_EQ(Norm("not not true"), "true");
  EXPECT_EQ(Norm("false -> true"), "true");
  EXPECT_EQ(Norm("true \\/ compl[i]==compOff"), "true");
  EXPECT_EQ(Norm("not not (projl[i+1]==projOn)"), "projl[i+1]==projOn");
  EXPECT_EQ(Norm("true -> (projl[i+1]==projOn)"), "projl[i+1]==projOn");
  EXPECT_EQ(Norm("(projl[i+1]==projOn) \\/ false"), "projl[i+1]==projOn");
  EXPECT_EQ(Norm("not (projl[i]==projOn)"), "projl[i]!=projOn");
  EXPECT_EQ(Norm("true <-> (projl[i]==projOn)"), "projl[i]==projOn");
}

TEST(Normalize, TautologiesAndContradictionsOverOneVariable) {
  EXPECT_EQ(Norm("compl[i]==compOff \\/ compl[i]!=compOff"), "true");
  EXPECT_EQ(Norm("compl[i]==compOff /\\ compl[i]==compOn"), "false");
  EXPECT_EQ(Norm("projl[i+1]==projOn /\\ (compl[i+1]==compOn \\/ not (compl[i+1]==compOn))"),
            "projl[i+1]==projOn");
  // Every location of the connection listed: a tautology.
  EXPECT_EQ(Norm("connl[i]==connected \\/ connl[i]==disconnected"), "true");
  // Different stages are different variables.
  EXPECT_EQ(Norm("compl[i]==compOff \\/ compl[i+1]!=compOff"),
            "(compl[i]==compOff \\/ compl[i+1]!=compOff)");
}

TEST(Normalize, FlattensNestedConjunctions) {
  EXPECT_EQ(Norm("(compl[i+1]==compOff /\\ (connl[i+1]==disconnected /\\ true)) /\\ "
                 "projl[i+1]==projOff"),
            "((compl[i+1]==compOff /\\ connl[i+1]==disconnected) /\\ projl[i+1]==projOff)");
}

// Exhaustive: on every assignment of the presentation's three locations at [i] and [i+1], the
// normalised form of each sample has the original's truth value.
TEST(Normalize, KeepsTheTruthValueOnEveryAssignment) {
  const Domain& d = testing::ShippedDomain("presentation");
  DomainValueNames names(d);
  const char* samples[] = {
      "not (compl[i]==compOn /\\ connl[i]==disconnected) \\/ projl[i+1]==projOff",
      "(compl[i]==compOff \\/ compl[i]==compOn) -> not (projl[i]!=projOn)",
      "(compl[i]==compOff <-> projl[i+1]==projOn) /\\ true",
      "compl[i]!=compOff /\\ compl[i]!=compOn /\\ compl[i]!=compBooting",
      "not not (connl[i]==connected \\/ false) /\\ (projl[i]==projOn \\/ projl[i]==projOff)",
  };
  for (const char* s : samples) {
    Expr raw = Checked(s, d);
    Expr norm = Normalize(raw, names.Function());
    int checked = 0;
    for (int c0 = 0; c0 < 4; ++c0)
      for (int c1 = 0; c1 < 4; ++c1)
        for (int n0 = 0; n0 < 2; ++n0)
          for (int p0 = 0; p0 < 5; ++p0)
            for (int p1 = 0; p1 < 5; ++p1) {
              auto value = [&](const Expr& a) {
                const bool next = a.index.kind == IndexKind::kIPlus1;
                if (a.target == 0) return next ? c1 : c0;
                if (a.target == 1) return n0;
                return next ? p1 : p0;
              };
              ASSERT_EQ(Evaluate(raw, value), Evaluate(norm, value)) << s;
              ++checked;
            }
    EXPECT_EQ(checked, 4 * 4 * 2 * 5 * 5);
  }
}

// The split sees through rewritten maintenance constraints and goals.
TEST(Normalize, RewritingsDoNotDefeatTheSplit) {
  Diagnostics dd;
  auto dom = LoadDomainByNameOrPath(testing::SourceDir() + "/tests/data/presentation_x2.json",
                                    testing::ConfigDir(), dd);
  ASSERT_TRUE(dom) << testing::AllErrors(dd);
  const Domain& d = *dom;
  const char* maintenance[] = {"true", "(true) /\\ (true)", "not not true", "false -> true",
                               "true \\/ comp1l[i]==compOff"};
  const char* goals[] = {"G", "not not (G)", "true -> (G)", "(G) \\/ false"};
  const std::string g = "comp1l[i+1]==compOn /\\ proj2l[i+1]==projOn /\\ "
                        "(conn2l[i+1]==connected \\/ conn2l[i+1]!=connected)";
  for (const char* m : maintenance)
    for (const char* gf : goals) {
      std::string goal = gf;
      goal.replace(goal.find('G'), 1, g);
      Json j = {{"initial_state", {{"comp1", "compOff"}, {"conn1", "disconnected"},
                                   {"proj1", "projOff"}, {"comp2", "compOff"},
                                   {"conn2", "disconnected"}, {"proj2", "projOff"}}},
                {"end_state", {{"maintenance_constraint", m}, {"goal_constraint", goal}}}};
      Diagnostics diags;
      auto sp = LoadStatePlan(j, d, diags);
      ASSERT_TRUE(sp) << testing::AllErrors(diags);
      EXPECT_EQ(SplitProblem(d, *sp).size(), 2u) << m << " / " << goal;
    }
}

}  // namespace
}  // namespace ctb
