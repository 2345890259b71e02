#include <gtest/gtest.h>

#include "planner/expr/expr.h"
#include "planner/expr/expr_print.h"

namespace ctb {
namespace {

// Every expression string of the thesis' chapter 3 and 5 state plans and encodings (with our
// domain names; parse only, names are checked in expr_check_test).
const char* const kThesisExpressions[] = {
    "true",
    "compu[i]==compTurnOn",
    "connu[i]==connect /\\ compl[i]==compOff",
    "projl[i]==projOn",
    "projl[0]==projOff",
    "projl[i]==projOn /\\ projl[i+1]==projConfirm",
    "projl[i]==projOff /\\ projl[i+1]==projWarmUp",
    "projl[i+1]==projOn",
    "compl[i+1]==compOff /\\ connl[i+1]==disconnected /\\ projl[i+1]==projOff",
    "projl[i+1]==projOff /\\ connl[i+1]==disconnected /\\ compl[i+1]=compOff /\\ "
    "temporalAcceptConstraint_Traj_last600[i]==tempActive",
    "projl[i+1]==projOn /\\ temporalAcceptConstraint_Traj_first60[i]==tempActive",
    "(projl[i]==projOn /\\ compl[i]==compOn) /\\ projl[i+1]==projConfirm /\\ "
    "compl[i+1]==compBooting",
    "projl[i]==projOn \\/ compl[i]==compOn",
    "arm1l[i]==home",
    "arm1l[i]==pickingA",
    "arm1[i+1]==home /\\ arm2[i+1]==home /\\ blockA[i+1]==onFloor",
    "robot1[i+1]==rescuedPerson1 /\\ robot2[i+1]==rescuedPerson2",
    "(robot1[i+1]==rescuedPerson1 /\\ robot2[i+1]==rescuedPerson2) \\/ "
    "(robot1[i+1]==rescuedPerson2 /\\ robot2[i+1]==rescuedPerson1)",
    "robot1[i+1]==rescuedPerson1",
    "not (compl[i] != compOn) -> projl[i] = projOn <-> true",
    "compOn == compl[i]",
    "  compl [ i + 1 ] == compOff  ",
};

TEST(Parse, EveryThesisExpressionParses) {
  for (const char* text : kThesisExpressions) {
    ExprError err;
    EXPECT_TRUE(Parse(text, err)) << text << ": offset " << err.offset << ": " << err.message;
  }
}

TEST(Parse, BuildsTheExpectedTree) {
  ExprError err;
  auto e = Parse("a[i]==x /\\ b[i+1]!=y \\/ not c[3]==z", err);
  ASSERT_TRUE(e);
  ASSERT_EQ(e->op, Expr::Op::kOr);  // /\ binds tighter than \/
  const Expr& conj = e->kids[0];
  ASSERT_EQ(conj.op, Expr::Op::kAnd);
  EXPECT_EQ(conj.kids[0].var, "a");
  EXPECT_EQ(conj.kids[0].index.kind, IndexKind::kI);
  EXPECT_EQ(conj.kids[0].value, "x");
  EXPECT_EQ(conj.kids[1].index.kind, IndexKind::kIPlus1);
  EXPECT_TRUE(conj.kids[1].not_equal);
  ASSERT_EQ(e->kids[1].op, Expr::Op::kNot);
  EXPECT_EQ(e->kids[1].kids[0].index.kind, IndexKind::kFixed);
  EXPECT_EQ(e->kids[1].kids[0].index.fixed, 3);
  EXPECT_EQ(e->kids[1].kids[0].var_offset, 28u);
}

TEST(Parse, ImplicationIsRightAssociativeAndLoosest) {
  ExprError err;
  auto e = Parse("a[i]==x -> b[i]==y -> c[i]==z <-> d[i]==w", err);
  ASSERT_TRUE(e);
  ASSERT_EQ(e->op, Expr::Op::kIff);
  ASSERT_EQ(e->kids[0].op, Expr::Op::kImplies);
  EXPECT_EQ(e->kids[0].kids[1].op, Expr::Op::kImplies);
}

TEST(Parse, ValueOnTheLeftIsTheSameAtom) {
  ExprError err;
  auto e = Parse("compOn != compl[i+1]", err);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->var, "compl");
  EXPECT_EQ(e->value, "compOn");
  EXPECT_TRUE(e->not_equal);
  EXPECT_EQ(e->var_offset, 10u);
}

struct Bad {
  std::string text;
  std::size_t offset;
  std::string message_part;
};

std::vector<Bad> Hostile() {
  std::vector<Bad> v = {
      {"compl[i]==compOn;", 16, "unexpected character ';'"},
      {"\"compl[i]==compOn\"", 0, "unexpected character '\"'"},
      {"include \"/etc/passwd\"", 8, "unexpected character '\"'"},
      {"true; output [\"x\"]", 4, "unexpected character ';'"},
      {"compl[i]==compOn /\\ solve satisfy", 26, "expected '[' after variable 'solve'"},
      {"compl[i-1]==compOn", 7, "unexpected character '-'"},
      {"compl[j]==compOn", 6, "expected an index"},
      {"compl[i+2]==compOn", 8, "expected '1' after 'i+'"},
      {"compl[]==compOn", 6, "expected an index"},
      {"compl[i]", 8, "expected '==' or '!='"},
      {"compl[i]==", 10, "expected a value name"},
      {"compl[i]==compOn /\\", 19, "expected a comparison"},
      {"(compl[i]==compOn", 17, "expected ')'"},
      {"compl[i]==compOn)", 16, "expected a connective or the end"},
      {"compl[i]<compOn", 8, "unexpected character '<'"},
      {"compl[i]>=compOn", 8, "unexpected character '>'"},
      {"compl[i]==compOn && projl[i]==projOn", 17, "unexpected character '&'"},
      {"compl[i]==compOn || x", 17, "unexpected character '|'"},
      {"compl[i]==compOn \\ projl", 17, "unexpected character '\\'"},
      {"compl[i]==compOn / projl", 17, "unexpected character '/'"},
      {"forall(i in 1)(true)", 6, "expected '[' after variable 'forall'"},
      {"compl[99999999]==compOn", 6, "integer too large"},
      {"compl[i]==1", 10, "expected a value name"},
      {"1==compl[i]", 0, "expected a comparison"},
      {"not", 3, "expected a comparison"},
      {"compl[i]==compOn == x", 17, "expected a connective or the end"},
      {"compl[i]==compOn /\\ /\\ projl[i]==projOn", 20, "expected a comparison"},
      {"compl[i]=!compOn", 9, "unexpected character '!'"},
      {"compl[i]==compOn % 2", 17, "unexpected character '%'"},
      {"compl[i]==compOn -> ", 20, "expected a comparison"},
      {std::string("compl[i]==compOn") + '\0', 16, "unexpected character byte 0"},
      {"compl[i]==compOn\n;", 17, "unexpected character ';'"},
      {"compl[1e3]==compOn", 7, "unexpected character 'e' after a number"},
      {"'compOn'", 0, "unexpected character '''"},
      {"compl[i]==compOn /* c */", 17, "unexpected character '/'"},
      {"compl[i+1]==compOn\\/", 20, "expected a comparison"},
      {"", 0, "expected a comparison"},
      {"compl[i]==compOn constraint false", 17, "expected a connective or the end"},
      {"compl[i]==compOn $", 17, "unexpected character '$'"},
      {"compl[i]==\xc3\xa9t\xc3\xa9", 10, "unexpected character byte 195"},
  };
  std::string deep(200, '(');
  v.push_back({deep + "true" + std::string(200, ')'), 65, "nested too deeply"});
  std::string nots;
  for (int i = 0; i < 100; ++i) nots += "not ";
  v.push_back({nots + "true", 260, "nested too deeply"});
  v.push_back({std::string(kMaxExprLength + 1, 'a'), kMaxExprLength, "longer than"});
  return v;
}

TEST(Parse, QuantifiersParseAndPrintBack) {
  for (const std::string text :
       {"every(k in robot: robot{k}l[i+1]==rescuedPerson{k})",
        "any(k in 1..4: robot{k}[i]!=outside)",
        "every(p in 1..2: any(k in robot: robot{k}l[i+1]==rescuedPerson{p}))",
        "(door1l[i+1]==open /\\ every(k in robot: not (robot{k}u[i]==goToDoor1)))"}) {
    ExprError err;
    auto e = Parse(text, err);
    ASSERT_TRUE(e) << text << ": " << err.message;
    EXPECT_TRUE(HasQuantifier(*e));
    std::string printed = PrintSource(*e);
    auto again = Parse(printed, err);
    ASSERT_TRUE(again) << printed << ": " << err.message;
    EXPECT_EQ(PrintSource(*again), printed);
  }
  ExprError err;
  auto e = Parse("every(k in robot: robot{k}l[i+1]==rescuedPerson{k})", err);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->op, Expr::Op::kEvery);
  EXPECT_EQ(e->var, "k");
  EXPECT_EQ(e->range, "robot");
  EXPECT_EQ(e->range_offset, 11u);
  ASSERT_EQ(e->kids.size(), 1u);
  EXPECT_EQ(e->kids[0].var, "robot{k}l");
  EXPECT_EQ(e->kids[0].value, "rescuedPerson{k}");
  auto r = Parse("any(j in 2..5: x{j}[i]==a)", err);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->op, Expr::Op::kAny);
  EXPECT_TRUE(r->range.empty());
  EXPECT_EQ(r->range_lo, 2);
  EXPECT_EQ(r->range_hi, 5);
}

TEST(Parse, EveryAndAnyStayUsableNames) {
  ExprError err;
  auto e = Parse("every[i]==any /\\ any[i+1]==in", err);
  ASSERT_TRUE(e) << err.message;
  EXPECT_FALSE(HasQuantifier(*e));
  EXPECT_EQ(e->kids[0].var, "every");
  EXPECT_EQ(e->kids[1].value, "in");
}

TEST(Parse, RejectsMalformedQuantifiersWithOffset) {
  const std::vector<Bad> cases = {
      {"robot{k}l[i]==outside", 5, "placeholder '{k}' outside a quantifier"},
      {"every(k in robot: robot{j}l[i]==outside)", 23, "'{j}' names no quantifier's variable"},
      {"every(k in robot: every(k in robot: true))", 24, "already bound"},
      {"every(i in robot: true)", 6, "'i' cannot be a quantifier's variable"},
      {"every(k robot: true)", 8, "expected 'in'"},
      {"every(k in robot true)", 17, "expected ':' after the range"},
      {"every(k in 1.. : true)", 15, "expected the integer that ends the range"},
      {"every(k in 1: true)", 12, "expected '..'"},
      {"every(k in robot{k}: true)", 11, "expected a range"},
      {"every(k in robot: true", 22, "')' closing the quantifier"},
      {"every({k} in robot: true)", 6, "expected the variable"},
      {"every(k in robot: robot{k l[i]==a)", 23, "a placeholder is '{'"},
      {"every(k in robot: robot{}l[i]==a)", 23, "a placeholder is '{'"},
      {"every(k in robot: robot{1}l[i]==a)", 23, "a placeholder is '{'"},
      {"forall(k in robot: true)", 6, "a quantifier is written every(k in TEMPLATE: ...)"},
      {"exists(k in robot: true)", 6, "or any(k in TEMPLATE: ...)"},
  };
  for (const auto& c : cases) {
    ExprError err;
    EXPECT_FALSE(Parse(c.text, err)) << c.text;
    EXPECT_EQ(err.offset, c.offset) << c.text << ": " << err.message;
    EXPECT_NE(err.message.find(c.message_part), std::string::npos)
        << c.text << ": got '" << err.message << "'";
  }
  // Deep nesting of quantifiers is bounded like parentheses.
  std::string deep;
  for (int k = 0; k < 100; ++k) deep += "every(v" + std::to_string(k) + " in 1..1: ";
  deep += "true" + std::string(100, ')');
  ExprError err;
  EXPECT_FALSE(Parse(deep, err));
  EXPECT_NE(err.message.find("nested too deeply"), std::string::npos) << err.message;
}

TEST(Parse, RejectsMalformedAndHostileStringsWithOffset) {
  auto cases = Hostile();
  ASSERT_GE(cases.size(), 30u);
  for (const auto& c : cases) {
    ExprError err;
    EXPECT_FALSE(Parse(c.text, err)) << c.text;
    EXPECT_EQ(err.offset, c.offset) << c.text << ": " << err.message;
    EXPECT_NE(err.message.find(c.message_part), std::string::npos)
        << c.text << ": got '" << err.message << "'";
  }
}

}  // namespace
}  // namespace ctb
