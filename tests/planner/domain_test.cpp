#include "planner/model/domain.h"

#include <cmath>

#include <gtest/gtest.h>

#include "test_util.h"

namespace ctb {
namespace {

using testing::HasError;
using testing::MustParse;

Json Minimal() {
  return MustParse(R"({
    "name": "d",
    "automata": [
      {"name": "lamp", "locations": ["off", "on"], "commands": ["press"],
       "transitions": [
         {"from": "off", "to": "on", "guard": "lampu[i]==press"},
         {"from": "on", "to": "off", "duration": [5, 5]}]},
      {"name": "door", "locations": ["shut", "ajar"],
       "transitions": [{"from": "shut", "to": "ajar", "guard": "lampl[i]==on"}]}
    ]})");
}

std::optional<Domain> Load(const Json& j, Diagnostics& d) { return LoadDomain(j, d); }

TEST(LoadDomain, LoadsAndDerivesCommandedTransitions) {
  Diagnostics d;
  auto dom = Load(Minimal(), d);
  ASSERT_TRUE(dom) << testing::AllErrors(d);
  const auto& lamp = dom->automata[0];
  EXPECT_TRUE(lamp.transitions[0].commanded);
  EXPECT_EQ(lamp.transitions[0].command, 1);
  EXPECT_FALSE(lamp.transitions[1].commanded);
  EXPECT_EQ(lamp.transitions[1].duration.lo, 5);
  EXPECT_EQ(*lamp.transitions[1].duration.hi, 5);
  EXPECT_FALSE(dom->automata[1].transitions[0].commanded);
  EXPECT_FALSE(dom->automata[1].transitions[0].duration.hi.has_value());
  EXPECT_EQ(dom->automata[1].transitions[0].cost, 1);
}

// Issue 30: an action model that lists a transition twice was accepted, and every solve with it
// failed verification. Now the second listing is an error that names the first.
TEST(LoadDomain, ATransitionListedTwiceIsAnErrorNamingTheFirst) {
  Json j = Minimal();
  j["automata"][0]["transitions"].push_back(
      MustParse(R"({"from": "off", "to": "on", "guard": "lampu[i] == press"})"));
  Diagnostics d;
  EXPECT_FALSE(Load(j, d));
  ASSERT_EQ(d.errors().size(), 1u) << testing::AllErrors(d);
  EXPECT_TRUE(HasError(d, "/automata/0/transitions/2", "the same transition as /automata/0/transitions/0"))
      << testing::AllErrors(d);
  // Same ends with another guard, or another target: two transitions, both kept.
  Json other = Minimal();
  other["automata"][1]["transitions"].push_back(
      MustParse(R"({"from": "shut", "to": "ajar", "guard": "lampl[i]==off"})"));
  Diagnostics d2;
  auto dom = Load(other, d2);
  ASSERT_TRUE(dom) << testing::AllErrors(d2);
  EXPECT_EQ(dom->automata[1].transitions.size(), 2u);
}

struct Case {
  const char* what;
  std::function<void(Json&)> mutate;
  std::string pointer;
  std::string message_part;
};

// Contract section 13: a contingent transition (nature picks when it fires in [lo, hi]).
TEST(LoadDomain, ContingentTransitionsAndTheirErrors) {
  Json ok = Minimal();
  ok["automata"][0]["transitions"][1] = MustParse(
      R"({"from": "on", "to": "off", "duration": [4, 6], "contingent": true,
          "distribution": {"kind": "normal", "mean": 5, "sd": 0.5}})");
  Diagnostics d;
  auto dom = Load(ok, d);
  ASSERT_TRUE(dom) << testing::AllErrors(d);
  const Transition& t = dom->automata[0].transitions[1];
  EXPECT_TRUE(t.contingent);
  ASSERT_TRUE(t.distribution);
  EXPECT_EQ(t.distribution->kind, Distribution::Kind::kNormal);
  EXPECT_TRUE(dom->HasContingent());
  // Planned at its longest duration, or as the planner's choice with controllability "none".
  const Transition& worst = PlanningDomain(*dom, false).automata[0].transitions[1];
  EXPECT_FALSE(worst.contingent);
  EXPECT_EQ(worst.duration.lo, 6);
  EXPECT_FALSE(worst.controllable);
  const Transition& picked = PlanningDomain(*dom, true).automata[0].transitions[1];
  EXPECT_TRUE(picked.controllable);
  EXPECT_EQ(picked.duration.lo, 4);
  EXPECT_EQ(DomainToJson(*dom)["automata"][0]["transitions"][1]["contingent"], true);

  const std::string t1 = "/automata/0/transitions/1";
  std::vector<Case> cases = {
      {"commanded", [](Json& j) { j["automata"][0]["transitions"][0]["contingent"] = true; },
       "/automata/0/transitions/0/contingent", "a commanded transition cannot be contingent"},
      {"both", [](Json& j) { j["automata"][0]["transitions"][1]["controllable"] = true; },
       t1 + "/contingent", "not both"},
      {"guard", [](Json& j) { j["automata"][0]["transitions"][1]["guard"] = "doorl[i]==ajar"; },
       t1 + "/guard", "guard must be true"},
      {"open", [](Json& j) { j["automata"][0]["transitions"][1]["duration"] = {4, nullptr}; },
       t1 + "/duration", "finite upper bound"},
      {"kind", [](Json& j) { j["automata"][0]["transitions"][1]["distribution"] = {{"kind", "beta"}}; },
       t1 + "/distribution/kind", "unknown distribution 'beta'"},
      {"sd", [](Json& j) { j["automata"][0]["transitions"][1]["distribution"]["sd"] = 0; },
       t1 + "/distribution/sd", "sd must be positive"},
      {"uniform with mean",
       [](Json& j) { j["automata"][0]["transitions"][1]["distribution"] = {{"kind", "uniform"}, {"mean", 5}}; },
       t1 + "/distribution/mean", "no mean or sd"},
      {"not contingent", [](Json& j) { j["automata"][0]["transitions"][1].erase("contingent"); },
       t1 + "/distribution", "only a contingent transition"},
      {"another exit",
       [](Json& j) {
         j["automata"][0]["locations"].push_back("broken");
         j["automata"][0]["transitions"].push_back({{"from", "on"}, {"to", "broken"}});
       },
       "/automata/0/transitions/2", "it can have no other transition out"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.what);
    Json j = ok;
    c.mutate(j);
    Diagnostics dd;
    EXPECT_FALSE(Load(j, dd));
    EXPECT_TRUE(HasError(dd, c.pointer, c.message_part)) << testing::AllErrors(dd);
  }
}

TEST(LoadDomain, EachErrorKindIsReportedAtItsPointer) {
  std::vector<Case> cases = {
      {"unknown top field", [](Json& j) { j["colour"] = "red"; }, "/colour", "unknown field"},
      {"unknown transition field", [](Json& j) { j["automata"][0]["transitions"][0]["when"] = 1; },
       "/automata/0/transitions/0/when", "unknown field \"when\""},
      {"name wrong type", [](Json& j) { j["automata"][0]["name"] = 3; }, "/automata/0/name",
       "expected a string, got number"},
      {"locations wrong type", [](Json& j) { j["automata"][0]["locations"] = "off"; },
       "/automata/0/locations", "expected an array"},
      {"automata missing", [](Json& j) { j.erase("automata"); }, "/automata", "missing required"},
      {"automata empty", [](Json& j) { j["automata"] = Json::array(); }, "/automata", "non-empty"},
      {"duplicate automaton", [](Json& j) { j["automata"][1]["name"] = "lamp"; },
       "/automata/1/name", "duplicate automaton 'lamp'"},
      {"ambiguous variable", [](Json& j) { j["automata"][1]["name"] = "lampl"; },
       "/automata/1/name", "ambiguous"},
      {"duplicate location", [](Json& j) { j["automata"][0]["locations"][1] = "off"; },
       "/automata/0/locations/1", "duplicate location 'off'"},
      {"duplicate command",
       [](Json& j) { j["automata"][0]["commands"] = {"press", "press"}; },
       "/automata/0/commands/1", "duplicate command"},
      {"bad location name", [](Json& j) { j["automata"][0]["locations"][1] = "o n;"; },
       "/automata/0/locations/1", "not a valid location name"},
      {"no locations", [](Json& j) { j["automata"][1]["locations"] = Json::array(); },
       "/automata/1/locations", "at least one"},
      {"unknown from", [](Json& j) { j["automata"][0]["transitions"][0]["from"] = "of"; },
       "/automata/0/transitions/0/from", "unknown location 'of' of automaton 'lamp' (did you mean 'off'?)"},
      {"unknown to", [](Json& j) { j["automata"][0]["transitions"][1]["to"] = "gone"; },
       "/automata/0/transitions/1/to", "unknown location 'gone'"},
      {"self loop", [](Json& j) { j["automata"][0]["transitions"][1]["to"] = "on"; },
       "/automata/0/transitions/1/to", "must change location"},
      {"guard does not parse",
       [](Json& j) { j["automata"][0]["transitions"][0]["guard"] = "lampu[i]==press;"; },
       "/automata/0/transitions/0/guard", "unexpected character ';'"},
      {"guard names unknown automaton",
       [](Json& j) { j["automata"][1]["transitions"][0]["guard"] = "lmpl[i]==on"; },
       "/automata/1/transitions/0/guard", "did you mean 'lampl'?"},
      {"guard names unknown location",
       [](Json& j) { j["automata"][1]["transitions"][0]["guard"] = "lampl[i]==onn"; },
       "/automata/1/transitions/0/guard", "unknown location 'onn'"},
      {"guard reads the next stage",
       [](Json& j) { j["automata"][1]["transitions"][0]["guard"] = "lampl[i+1]==on"; },
       "/automata/1/transitions/0/guard", "read on the stage before"},
      {"duration lo > hi",
       [](Json& j) { j["automata"][0]["transitions"][1]["duration"] = {7, 5}; },
       "/automata/0/transitions/1/duration", "greater than upper bound"},
      {"duration negative",
       [](Json& j) { j["automata"][0]["transitions"][1]["duration"] = {-1, 5}; },
       "/automata/0/transitions/1/duration/0", "must not be negative"},
      {"duration NaN",
       [](Json& j) { j["automata"][0]["transitions"][1]["duration"] = {NAN, 5}; },
       "/automata/0/transitions/1/duration/0", "not finite"},
      {"duration infinite",
       [](Json& j) { j["automata"][0]["transitions"][1]["duration"] = {1, INFINITY}; },
       "/automata/0/transitions/1/duration/1", "not finite"},
      {"duration shape", [](Json& j) { j["automata"][0]["transitions"][1]["duration"] = 5; },
       "/automata/0/transitions/1/duration", "expected [lo, hi]"},
      {"duration string",
       [](Json& j) { j["automata"][0]["transitions"][1]["duration"] = {"5", 5}; },
       "/automata/0/transitions/1/duration/0", "expected a number, got string"},
      {"fractional duration", [](Json& j) { j["automata"][0]["transitions"][1]["duration"] = {0.5, 1}; },
       "/automata/0/transitions/1/duration/0", "time_resolution"},
      {"cost negative", [](Json& j) { j["automata"][0]["transitions"][1]["cost"] = -2; },
       "/automata/0/transitions/1/cost", "between 0 and"},
      {"cost fractional", [](Json& j) { j["automata"][0]["transitions"][1]["cost"] = 1.5; },
       "/automata/0/transitions/1/cost", "non-negative integer"},
      {"controllable commanded",
       [](Json& j) { j["automata"][0]["transitions"][0]["controllable"] = true; },
       "/automata/0/transitions/0/controllable", "cannot also be controllable"},
      {"controllable wrong type",
       [](Json& j) { j["automata"][0]["transitions"][1]["controllable"] = "yes"; },
       "/automata/0/transitions/1/controllable", "expected a boolean"},
      {"bad resolution", [](Json& j) { j["time_resolution"] = 0; }, "/time_resolution", "[0.000001, 1]"},
      {"not an object", [](Json& j) { j["automata"][1] = Json::array(); }, "/automata/1",
       "expected an object, got array"},
  };
  for (const auto& c : cases) {
    Json j = Minimal();
    c.mutate(j);
    Diagnostics d;
    EXPECT_FALSE(Load(j, d)) << c.what;
    EXPECT_TRUE(HasError(d, c.pointer, c.message_part))
        << c.what << "; got:\n" << testing::AllErrors(d);
  }
}

TEST(LoadDomain, FinerTimeResolutionAllowsFractions) {
  Json j = Minimal();
  j["time_resolution"] = 0.5;
  j["automata"][0]["transitions"][1]["duration"] = {0.5, 1.5};
  Diagnostics d;
  EXPECT_TRUE(Load(j, d)) << testing::AllErrors(d);
}

// The shipped domains against the facts of domains.md.
struct Fact {
  std::string automaton;
  std::vector<std::string> locations;
  std::vector<std::string> commands;
};

void ExpectAutomaton(const Domain& d, const Fact& f) {
  int a = d.AutomatonIndex(f.automaton);
  ASSERT_GE(a, 0) << f.automaton;
  EXPECT_EQ(d.automata[a].locations, f.locations) << f.automaton;
  EXPECT_EQ(d.automata[a].commands, f.commands) << f.automaton;
}

// The duration of the automatic transition from -> to, or -1.
double AfterSeconds(const Domain& d, const std::string& automaton, const std::string& from,
                    const std::string& to) {
  const auto& a = d.automata[d.AutomatonIndex(automaton)];
  for (const auto& t : a.transitions)
    if (a.locations[t.from] == from && a.locations[t.to] == to && !t.commanded && t.duration.hi &&
        t.duration.lo == *t.duration.hi)
      return t.duration.lo;
  return -1;
}

const Transition* Find(const Domain& d, const std::string& automaton, const std::string& from,
                       const std::string& to) {
  const auto& a = d.automata[d.AutomatonIndex(automaton)];
  for (const auto& t : a.transitions)
    if (a.locations[t.from] == from && a.locations[t.to] == to) return &t;
  return nullptr;
}

TEST(ShippedDomains, PresentationMatchesDomainsMd) {
  const Domain& d = testing::ShippedDomain("presentation");
  ASSERT_EQ(d.automata.size(), 3u);
  ExpectAutomaton(d, {"comp", {"compOff", "compBooting", "compOn", "compShutdown"},
                      {"compTurnOn", "compTurnOff"}});
  ExpectAutomaton(d, {"conn", {"disconnected", "connected"}, {"connect", "disconnect"}});
  ExpectAutomaton(d, {"proj", {"projOff", "projWarmUp", "projOn", "projConfirm", "projCoolDown"},
                      {"projTurnOn", "projTurnOff"}});
  EXPECT_EQ(AfterSeconds(d, "comp", "compBooting", "compOn"), 15);
  EXPECT_EQ(AfterSeconds(d, "comp", "compShutdown", "compOff"), 30);
  EXPECT_EQ(AfterSeconds(d, "proj", "projWarmUp", "projOn"), 30);
  EXPECT_EQ(AfterSeconds(d, "proj", "projCoolDown", "projOff"), 60);
  EXPECT_EQ(Find(d, "conn", "disconnected", "connected")->guard_text,
            "connu[i]==connect /\\ compl[i]==compOff");
  EXPECT_TRUE(Find(d, "proj", "projConfirm", "projCoolDown"));
  const Transition* auto_cool = nullptr;
  for (const auto& t : d.automata[2].transitions)
    if (!t.commanded && d.automata[2].locations[t.from] == "projOn") auto_cool = &t;
  ASSERT_TRUE(auto_cool);
  EXPECT_EQ(auto_cool->guard_text, "connl[i]==disconnected");
  for (const auto& a : d.automata)
    for (const auto& t : a.transitions) EXPECT_EQ(t.cost, 1);
}

TEST(ShippedDomains, SearchRescueMatchesDomainsMd) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  ASSERT_EQ(d.automata.size(), 5u);
  for (const char* r : {"robot1", "robot2"}) {
    ExpectAutomaton(d, {r,
                        {"outside", "goingToDoor1", "atDoor1", "door1Opening", "insideRoom1",
                         "goingToDoor3", "atDoor3", "goingDoor3Person1", "goingDoor3Person2",
                         "goingToDoor2", "atDoor2", "door2Opening", "insideRoom2",
                         "goingRoom2Person1", "goingRoom2Person2", "rescuedPerson1",
                         "rescuedPerson2"},
                        {"goToDoor1", "openDoor1", "enterRoom1", "goToDoor3", "goToPerson1",
                         "goToPerson2", "goToDoor2", "openDoor2", "enterRoom2"}});
    EXPECT_EQ(AfterSeconds(d, r, "goingToDoor1", "atDoor1"), 1);
    EXPECT_EQ(AfterSeconds(d, r, "goingToDoor3", "atDoor3"), 4);
    EXPECT_EQ(AfterSeconds(d, r, "goingDoor3Person1", "rescuedPerson1"), 5);
    EXPECT_EQ(AfterSeconds(d, r, "goingToDoor2", "atDoor2"), 10);
    EXPECT_EQ(AfterSeconds(d, r, "goingRoom2Person2", "rescuedPerson2"), 2);
    EXPECT_FALSE(Find(d, r, "door1Opening", "insideRoom1")->commanded);
    // rescued is final
    const auto& a = d.automata[d.AutomatonIndex(r)];
    for (const auto& t : a.transitions)
      EXPECT_NE(a.locations[t.from].rfind("rescued", 0), 0u) << a.locations[t.from];
  }
  for (const char* door : {"door1", "door2", "door3"})
    ExpectAutomaton(d, {door, {"closed", "opening", "open"}, {}});
  EXPECT_EQ(AfterSeconds(d, "door1", "opening", "open"), 1);
  EXPECT_EQ(Find(d, "door2", "closed", "opening")->guard_text,
            "robot1l[i]==door2Opening \\/ robot2l[i]==door2Opening");
  EXPECT_TRUE(d.automata[d.AutomatonIndex("door3")].transitions.empty());
}

TEST(ShippedDomains, AssemblyMatchesDomainsMd) {
  const Domain& d = testing::ShippedDomain("assembly");
  ASSERT_EQ(d.automata.size(), 5u);
  const auto& arm = d.automata[d.AutomatonIndex("arm1")];
  EXPECT_EQ(arm.locations.size(), 1u + 3 + 3 + 9);
  EXPECT_EQ(arm.commands.size(), 3u + 9);
  EXPECT_GE(arm.LocationIndex("placingBonA"), 0);
  EXPECT_LT(arm.LocationIndex("placingAonA"), 0);
  EXPECT_GE(arm.CommandCode("placeConFloor"), 1);
  ExpectAutomaton(d, {"blockA", {"onFloor", "onB", "onC", "inArm1", "inArm2"}, {}});
  ExpectAutomaton(d, {"blockC", {"onFloor", "onA", "onB", "inArm1", "inArm2"}, {}});
  EXPECT_EQ(AfterSeconds(d, "arm2", "pickingB", "holdingB"), 1);
  EXPECT_EQ(AfterSeconds(d, "arm2", "placingBonA", "home"), 2);
  EXPECT_EQ(Find(d, "blockB", "onC", "inArm2")->guard_text, "arm2l[i]==holdingB");
  EXPECT_EQ(Find(d, "blockB", "inArm1", "onA")->guard_text, "arm1l[i]==placingBonA");
  const std::string& pick = Find(d, "arm1", "home", "pickingB")->guard_text;
  for (const char* part : {"arm1u[i]==pickB", "blockAl[i]!=onB", "blockCl[i]!=onB",
                           "blockBl[i]!=inArm1", "blockBl[i]!=inArm2", "arm2l[i]!=pickingB",
                           "arm2l[i]!=holdingB", "arm2l[i]!=placingAonB", "arm2l[i]!=placingConB"})
    EXPECT_NE(pick.find(part), std::string::npos) << part;
  EXPECT_EQ(pick.find("arm2u[i]"), std::string::npos) << "arm 1 has priority";
  // Arm 2 also reads arm 1's command at the same stage (domains.md, turn 3).
  const std::string& pick2 = Find(d, "arm2", "home", "pickingB")->guard_text;
  for (const char* part : {"arm1l[i]!=holdingB", "arm1l[i]!=placingConB", "arm1u[i]!=pickB",
                           "arm1u[i]!=placeAonB", "arm1u[i]!=placeConB"})
    EXPECT_NE(pick2.find(part), std::string::npos) << part;
  const std::string& place = Find(d, "arm2", "holdingA", "placingAonB")->guard_text;
  for (const char* part : {"arm2u[i]==placeAonB", "blockCl[i]!=onB", "blockBl[i]!=inArm1",
                           "arm1l[i]!=placingConB", "arm1l[i]!=pickingB", "arm1l[i]!=holdingB",
                           "arm1u[i]!=placeConB", "arm1u[i]!=pickB"})
    EXPECT_NE(place.find(part), std::string::npos) << part;
}

TEST(LoadDomainFile, NamesTheFileInErrors) {
  Diagnostics d;
  EXPECT_FALSE(LoadDomainFile("/nonexistent.json", d));
  EXPECT_NE(d.errors().at(0).message.find("/nonexistent.json"), std::string::npos);
}

TEST(LoadDomainByNameOrPath, RejectsTraversalAndUnknownNames) {
  Diagnostics d;
  bool not_found = false;
  EXPECT_FALSE(LoadDomainByNameOrPath("nosuch", testing::ConfigDir(), d, &not_found));
  EXPECT_TRUE(not_found);
  EXPECT_TRUE(HasError(d, "/domain", "unknown domain 'nosuch'"));
  Diagnostics d2;
  EXPECT_FALSE(LoadDomainByNameOrPath("..", testing::ConfigDir(), d2));
}

}  // namespace
}  // namespace ctb
