// Automaton templates (planner/model/templates.h): expansion, any/every, loops, and errors that
// point at the template and name the instance.
#include "planner/model/templates.h"

#include <gtest/gtest.h>

#include "planner/model/domain.h"
#include "test_util.h"

namespace ctb {
namespace {

using testing::AllErrors;
using testing::HasError;
using testing::MustParse;

Json Team() {
  return MustParse(R"J({
    "name": "team",
    "parameters": {"N": 3},
    "automata": [
      {"template": "drone", "parameter": "k", "instances": "1..N",
       "locations": ["parked", "flying", {"for": "w", "in": ["A", "B"], "each": "at{w}"}],
       "commands": ["takeOff", {"for": "w", "in": ["A", "B"], "each": "flyTo{w}"}],
       "transitions": [
         {"from": "parked", "to": "flying", "guard": "{self}u[i]==takeOff /\\ hangarl[i]==open"},
         {"for": "w", "in": ["A", "B"], "each":
           {"from": "flying", "to": "at{w}", "guard": "drone{k}u[i]==flyTo{w}", "duration": [20, 20]}}]},
      {"name": "hangar", "locations": ["shut", "open"], "commands": ["openIt"],
       "transitions": [
         {"from": "shut", "to": "open", "guard": "hangaru[i]==openIt"},
         {"from": "open", "to": "shut", "guard": "every(k in drone: drone{k}l[i]!=parked)"}]},
      {"template": "beacon", "parameter": "b", "instances": "2..N-1",
       "locations": ["dark", "lit"],
       "transitions": [{"from": "dark", "to": "lit", "guard": "any(k in 1..{b}: drone{k}l[i]==atA)"}]}
    ]})J");
}

TEST(Templates, ExpandsInstancesLoopsAndQuantifiers) {
  Diagnostics d;
  auto x = ExpandTemplates(Team(), d);
  ASSERT_TRUE(x) << AllErrors(d);
  EXPECT_TRUE(x->had_templates);
  const Json& a = x->document["automata"];
  ASSERT_EQ(a.size(), 5u);  // drone1..3, hangar, beacon2
  EXPECT_EQ(a[0]["name"], "drone1");
  EXPECT_EQ(a[2]["name"], "drone3");
  EXPECT_EQ(a[3]["name"], "hangar");
  EXPECT_EQ(a[4]["name"], "beacon2");
  EXPECT_EQ(a[1]["locations"], Json({"parked", "flying", "atA", "atB"}));
  EXPECT_EQ(a[1]["commands"], Json({"takeOff", "flyToA", "flyToB"}));
  EXPECT_EQ(a[1]["transitions"][0]["guard"], "drone2u[i]==takeOff /\\ hangarl[i]==open");
  EXPECT_EQ(a[1]["transitions"][2]["to"], "atB");
  EXPECT_EQ(a[1]["transitions"][2]["guard"], "drone2u[i]==flyToB");
  EXPECT_EQ(a[3]["transitions"][1]["guard"],
            "((drone1l[i]!=parked) /\\ (drone2l[i]!=parked) /\\ (drone3l[i]!=parked))");
  EXPECT_EQ(a[4]["transitions"][0]["guard"], "((drone1l[i]==atA) \\/ (drone2l[i]==atA))");
  EXPECT_FALSE(x->document.contains("parameters"));
  // The expanded document loads, and so does the template through LoadDomain.
  auto dom = LoadDomain(Team(), d);
  ASSERT_TRUE(dom) << AllErrors(d);
  EXPECT_EQ(dom->automata.size(), 5u);
  EXPECT_TRUE(dom->automata[0].transitions[0].commanded);
}

TEST(Templates, OverridesTheParameter) {
  Diagnostics d;
  ExpandOptions o;
  o.parameters["N"] = 6;
  auto x = ExpandTemplates(Team(), d, o);
  ASSERT_TRUE(x) << AllErrors(d);
  EXPECT_EQ(x->document["automata"].size(), 6u + 1 + 4);
  o.parameters = {{"M", 2}};
  EXPECT_FALSE(ExpandTemplates(Team(), d, o));
  EXPECT_TRUE(HasError(d, "/parameters", "no parameter 'M'"));
}

TEST(Templates, EmptyRangesGiveFalseAndTrue) {
  Json j = Team();
  j["parameters"]["N"] = 0;
  j["automata"][1]["transitions"][0]["guard"] = "any(k in drone: drone{k}l[i]==parked)";
  Diagnostics d;
  auto x = ExpandTemplates(j, d);
  ASSERT_TRUE(x) << AllErrors(d);
  EXPECT_EQ(x->document["automata"].size(), 1u);
  EXPECT_EQ(x->document["automata"][0]["transitions"][0]["guard"], "false");
  EXPECT_EQ(x->document["automata"][0]["transitions"][1]["guard"], "true");
}

TEST(Templates, PlainDocumentsAreLeftAlone) {
  Diagnostics d;
  Json plain = testing::MustParse(R"J({"name": "p", "automata": [
      {"name": "lamp", "locations": ["off", "on"], "transitions": [{"from": "off", "to": "on"}]}]})J");
  auto x = ExpandTemplates(plain, d);
  ASSERT_TRUE(x);
  EXPECT_FALSE(x->had_templates);
  EXPECT_EQ(x->document, plain);
  EXPECT_FALSE(UsesTemplates(plain));
  EXPECT_TRUE(UsesTemplates(Team()));
  for (const char* name : {"presentation", "search_rescue", "assembly"}) {
    auto j = ReadJsonFile(testing::ConfigDir() + "/domains/" + name + ".json", d);
    ASSERT_TRUE(j);
    EXPECT_FALSE(UsesTemplates(*j)) << name;
  }
}

TEST(Templates, ErrorsInAnInstancePointAtTheTemplateAndNameTheInstance) {
  Json j = Team();
  // Only drone3's guard is wrong: there is no drone4.
  j["automata"][0]["transitions"][0]["guard"] = "{self}u[i]==takeOff /\\ drone{k+1}l[i]!=flying";
  Diagnostics d;
  EXPECT_FALSE(LoadDomain(j, d));
  ASSERT_EQ(d.errors().size(), 1u) << AllErrors(d);
  const Diagnostic& e = d.errors()[0];
  EXPECT_EQ(e.pointer, "/automata/0/transitions/0/guard");
  EXPECT_NE(e.message.find("in instance 'drone3' (k=3)"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("drone4"), std::string::npos) << e.message;
  EXPECT_FALSE(e.offset);  // the offset is of the expanded guard, which the message quotes
  EXPECT_NE(e.message.find("expanded text \"drone3u[i]==takeOff"), std::string::npos);
}

TEST(Templates, ErrorsInsideALoopNameTheLoopValue) {
  Json j = Team();
  j["automata"][0]["transitions"][1]["each"]["to"] = "at{w}x";
  Diagnostics d;
  EXPECT_FALSE(LoadDomain(j, d));
  EXPECT_TRUE(HasError(d, "/automata/0/transitions/1/each/to", "in instance 'drone1' (k=1, w=A)"))
      << AllErrors(d);
  EXPECT_TRUE(HasError(d, "/automata/0/transitions/1/each/to", "unknown location 'atAx'"));
}

TEST(Templates, ATransitionListedTwiceInATemplateIsAnErrorAtTheTemplate) {
  Json j = Team();
  j["automata"][0]["transitions"].push_back(j["automata"][0]["transitions"][0]);
  Diagnostics d;
  EXPECT_FALSE(LoadDomain(j, d));
  EXPECT_TRUE(HasError(d, "/automata/0/transitions/2", "the same transition as")) << AllErrors(d);
}

TEST(Templates, AnUnchangedGuardKeepsItsOffset) {
  Json j = Team();
  j["automata"][1]["transitions"][0]["guard"] = "hangaru[i]==openItt";
  Diagnostics d;
  EXPECT_FALSE(LoadDomain(j, d));
  ASSERT_FALSE(d.errors().empty());
  EXPECT_EQ(d.errors()[0].pointer, "/automata/1/transitions/0/guard");
  EXPECT_TRUE(d.errors()[0].offset.has_value()) << AllErrors(d);
}

TEST(Templates, ExpansionErrorsAreLocated) {
  struct Case {
    std::string pointer, value, want_pointer, want;
  };
  std::vector<Case> cases = {
      {"/automata/0/instances", "\"1..Q\"", "/automata/0/instances", "unknown name 'Q'"},
      {"/automata/0/instances", "\"robot\"", "/automata/0/instances", "neither a range"},
      {"/automata/0/instances", "\"1..5000\"", "/automata/0/instances", "at most 1000"},
      {"/automata/0/transitions/0/guard", "\"{self}u[i]==takeOff /\\\\ {z}\"",
       "/automata/0/transitions/0/guard", "unknown name 'z'"},
      {"/automata/1/transitions/1/guard", "\"any(k drone: x)\"", "/automata/1/transitions/1/guard",
       "VAR in RANGE"},
      {"/automata/0/locations/2/in", "\"1..\"", "/automata/0/locations/2/in", "expected a number"},
      {"/parameters/N", "1.5", "/parameters/N", "integer"},
      {"/automata/0/parameter", "\"N\"", "/automata/0/parameter", "parameter of the domain"},
  };
  for (const auto& c : cases) {
    Json j = Team();
    j[Json::json_pointer(c.pointer)] = MustParse(c.value);
    Diagnostics d;
    EXPECT_FALSE(LoadDomain(j, d)) << c.pointer;
    EXPECT_TRUE(HasError(d, c.want_pointer, c.want)) << c.pointer << ": " << AllErrors(d);
  }
}

// A door any of 1,000 robots opens: its guard expands to about 30,000 characters, more than a
// guard as written may have (kMaxExprLength), and loads; the domain keeps its templates.
TEST(Templates, ALongExpandedGuardLoadsAndTheTemplatesAreKept) {
  Json j = MustParse(R"J({"name": "crowd", "parameters": {"N": 1000}, "automata": [
      {"template": "robot", "parameter": "k", "instances": "1..N",
       "locations": ["outside", "atDoor"], "commands": ["go"],
       "transitions": [{"from": "outside", "to": "atDoor", "guard": "{self}u[i]==go"}]},
      {"name": "door", "locations": ["closed", "open"],
       "transitions": [{"from": "closed", "to": "open",
                        "guard": "any(k in robot: robot{k}l[i]==atDoor)"}]}]})J");
  Diagnostics d;
  auto dom = LoadDomain(j, d);
  ASSERT_TRUE(dom) << AllErrors(d);
  ASSERT_EQ(dom->automata.size(), 1001u);
  EXPECT_GT(dom->automata[1000].transitions[0].guard_text.size(), kMaxExprLength);
  ASSERT_EQ(dom->templates.size(), 1u);
  EXPECT_EQ(dom->templates[0].name, "robot");
  EXPECT_EQ(dom->templates[0].values.size(), 1000u);
  EXPECT_EQ(dom->templates[0].values.back(), "1000");
}

// A short guard whose any/every would write a billion copies stops at the expansion's bound.
TEST(Templates, GuardExpansionIsBoundedByWork) {
  Json j = Team();
  j["automata"][1]["transitions"][1]["guard"] =
      "every(a in 1..1000: every(b in 1..1000: every(c in 1..1000: hangarl[i]==shut)))";
  Diagnostics d;
  EXPECT_FALSE(LoadDomain(j, d));
  EXPECT_TRUE(HasError(d, "/automata/1/transitions/1/guard", "more than 65536 characters"))
      << AllErrors(d);
}

TEST(Templates, TheShippedTemplateWithTwoRobotsIsTheShippedDomain) {
  Diagnostics d;
  auto t = ReadJsonFile(testing::ConfigDir() + "/templates/search_rescue_team.json", d);
  ASSERT_TRUE(t) << AllErrors(d);
  auto dom = LoadDomain(*t, d);
  ASSERT_TRUE(dom) << AllErrors(d);
  const Domain& shipped = testing::ShippedDomain("search_rescue");
  ASSERT_EQ(dom->automata.size(), shipped.automata.size());
  for (std::size_t i = 0; i < shipped.automata.size(); ++i) {
    EXPECT_EQ(dom->automata[i].name, shipped.automata[i].name);
    EXPECT_EQ(dom->automata[i].locations, shipped.automata[i].locations);
    EXPECT_EQ(dom->automata[i].commands, shipped.automata[i].commands);
    EXPECT_EQ(dom->automata[i].transitions.size(), shipped.automata[i].transitions.size());
  }
  EXPECT_EQ(dom->description.rfind("2 ground robots rescue 2 persons", 0), 0u);
}

}  // namespace
}  // namespace ctb
