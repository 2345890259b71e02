// SVG diagrams of action models (planner/diagram): well-formed XML, every name as text.
#include "planner/diagram/diagram.h"

#include <gtest/gtest.h>

#include "test_util.h"

namespace ctb {
namespace {

// A small well-formedness check: tags nest and close, attributes are quoted, entities are the
// five of XML, and no raw '<' or '&' appears in text.
bool WellFormed(const std::string& s, std::string& why) {
  std::vector<std::string> stack;
  std::size_t i = 0;
  while (i < s.size()) {
    if (s[i] == '&') {
      std::size_t semi = s.find(';', i);
      std::string ent = semi == std::string::npos ? "" : s.substr(i, semi - i + 1);
      if (ent != "&amp;" && ent != "&lt;" && ent != "&gt;" && ent != "&quot;" && ent != "&apos;") {
        why = "bad entity at " + std::to_string(i);
        return false;
      }
      i = semi + 1;
      continue;
    }
    if (s[i] != '<') {
      ++i;
      continue;
    }
    std::size_t end = i + 1;
    char quote = 0;
    while (end < s.size() && (quote || s[end] != '>')) {
      if (quote && s[end] == quote) quote = 0;
      else if (!quote && (s[end] == '"' || s[end] == '\'')) quote = s[end];
      else if (!quote && s[end] == '<') {
        why = "'<' inside a tag at " + std::to_string(end);
        return false;
      }
      ++end;
    }
    if (end >= s.size()) {
      why = "unterminated tag";
      return false;
    }
    std::string tag = s.substr(i + 1, end - i - 1);
    if (tag.empty()) {
      why = "empty tag";
      return false;
    }
    if (tag[0] == '/') {
      std::string name = tag.substr(1);
      if (stack.empty() || stack.back() != name) {
        why = "mismatched </" + name + ">";
        return false;
      }
      stack.pop_back();
    } else if (tag.back() != '/') {
      stack.push_back(tag.substr(0, tag.find_first_of(" \n")));
    }
    i = end + 1;
  }
  if (!stack.empty()) {
    why = "unclosed <" + stack.back() + ">";
    return false;
  }
  return true;
}

TEST(Diagram, EveryShippedDomainIsWellFormedAndNamesEverything) {
  for (const char* name : {"presentation", "search_rescue", "assembly"}) {
    SCOPED_TRACE(name);
    const Domain& d = testing::ShippedDomain(name);
    std::string svg = DomainSvg(d);
    EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0), 0u);
    std::string why;
    EXPECT_TRUE(WellFormed(svg, why)) << why;
    for (const auto& a : d.automata) {
      EXPECT_NE(svg.find(">automaton " + a.name + "<"), std::string::npos) << a.name;
      for (const auto& l : a.locations)
        EXPECT_NE(svg.find(">" + l + "</text>"), std::string::npos) << a.name << "." << l;
    }
  }
}

TEST(Diagram, LabelsSayCommandGuardAndDuration) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  const Automaton& r = d.automata[0];
  EXPECT_EQ(TransitionLabel(d, r, r.transitions[0]), "goToDoor1");
  EXPECT_EQ(TransitionLabel(d, r, r.transitions[1]), "after 1 s");
  EXPECT_EQ(TransitionLabel(d, r, r.transitions[2]), "openDoor1 · door1l[i]==closed");
  EXPECT_EQ(TransitionLabel(d, r, r.transitions[3]), "door1l[i]==open");
  const Automaton& door = d.automata[2];
  EXPECT_EQ(TransitionLabel(d, door, door.transitions[0]),
            "robot1l[i]==door1Opening \\/ robot2l[i]==door1Opening");
  std::string svg = DomainSvg(d);
  EXPECT_NE(svg.find(">after 4 s</text>"), std::string::npos);
  EXPECT_NE(svg.find("openDoor1 · door1l[i]==closed"), std::string::npos);
}

TEST(Diagram, EscapesAndCutsLongLabels) {
  Diagnostics diags;
  auto d = LoadDomain(testing::MustParse(R"J({"name": "x", "description": "a <b> & c",
      "automata": [{"name": "lamp", "locations": ["off", "on", "broken"], "commands": ["press"],
        "transitions": [
          {"from": "off", "to": "on", "guard": "lampu[i]==press /\\ (lampl[i]!=broken \\/ lampl[i]!=on) /\\ lampl[i]!=broken /\\ lampl[i]!=on"},
          {"from": "on", "to": "off", "duration": [2, 10], "cost": 3}]}]})J"),
                      diags);
  ASSERT_TRUE(d) << testing::AllErrors(diags);
  std::string svg = DomainSvg(*d);
  std::string why;
  EXPECT_TRUE(WellFormed(svg, why)) << why;
  EXPECT_NE(svg.find("<title>press · (lampl[i]!=broken \\/ lampl[i]!=on) /\\ "), std::string::npos);  // the full label
  EXPECT_NE(svg.find("...</text>"), std::string::npos);                        // the cut one
  EXPECT_NE(svg.find("[2, 10] s · cost 3"), std::string::npos);
  EXPECT_NE(svg.find(">broken</text>"), std::string::npos);  // unreached, still drawn
}

}  // namespace
}  // namespace ctb
