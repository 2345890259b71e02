// The coupled search_rescue written as a template (config/templates/search_rescue_team.json)
// against the generated copies (tools/gen_domains.py --robots N, what bench/gen_scaled.py and
// bench/coupled.py use): the same automata for N = 2..8, and the same answers where solved.
#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>

#include "planner/expr/expr_print.h"
#include "planner/model/templates.h"
#include "planner/solve/solve.h"
#include "test_util.h"

namespace ctb {
namespace {

using testing::AllErrors;

std::optional<Domain> FromTemplate(int n) {
  Diagnostics d;
  auto t = ReadJsonFile(testing::ConfigDir() + "/templates/search_rescue_team.json", d);
  EXPECT_TRUE(t) << AllErrors(d);
  if (!t) return std::nullopt;
  ExpandOptions o;
  o.parameters["N"] = n;
  auto x = ExpandTemplates(*t, d, o);
  EXPECT_TRUE(x) << AllErrors(d);
  if (!x) return std::nullopt;
  auto dom = LoadDomain(x->document, d);
  EXPECT_TRUE(dom) << AllErrors(d);
  return dom;
}

std::optional<Domain> Generated(int n) {
  auto dir = std::filesystem::temp_directory_path() /
             ("ctb_tmpl_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::string file = (dir / ("r" + std::to_string(n) + ".json")).string();
  std::string cmd = "python3 " + testing::SourceDir() + "/tools/gen_domains.py --robots " +
                    std::to_string(n) + " " + file;
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  Diagnostics d;
  auto dom = LoadDomainFile(file, d);
  EXPECT_TRUE(dom) << AllErrors(d);
  std::filesystem::remove_all(dir);
  return dom;
}

// Everything the planner reads, with guards compared as parsed trees.
void ExpectSameAutomata(const Domain& a, const Domain& b) {
  ASSERT_EQ(a.automata.size(), b.automata.size());
  for (std::size_t i = 0; i < a.automata.size(); ++i) {
    const Automaton& x = a.automata[i];
    const Automaton& y = b.automata[i];
    SCOPED_TRACE(x.name);
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.locations, y.locations);
    EXPECT_EQ(x.commands, y.commands);
    ASSERT_EQ(x.transitions.size(), y.transitions.size());
    for (std::size_t k = 0; k < x.transitions.size(); ++k) {
      const Transition& s = x.transitions[k];
      const Transition& t = y.transitions[k];
      EXPECT_EQ(s.from, t.from);
      EXPECT_EQ(s.to, t.to);
      EXPECT_EQ(PrintSource(s.guard), PrintSource(t.guard)) << s.guard_text << " vs " << t.guard_text;
      EXPECT_EQ(s.duration.lo, t.duration.lo);
      EXPECT_EQ(s.duration.hi, t.duration.hi);
      EXPECT_EQ(s.cost, t.cost);
      EXPECT_EQ(s.controllable, t.controllable);
      EXPECT_EQ(s.commanded, t.commanded);
      EXPECT_EQ(s.command, t.command);
    }
  }
}

// bench/gen_scaled.py's rescue_plan(n): robot k rescues person k.
Json RescuePlan(int n) {
  Json init = Json::object();
  std::string goal;
  for (int r = 1; r <= n; ++r) {
    init["robot" + std::to_string(r)] = "outside";
    goal += (r > 1 ? " /\\ " : "") + ("robot" + std::to_string(r) + "[i+1]==rescuedPerson" +
                                      std::to_string(r));
  }
  init["door1"] = "closed";
  init["door2"] = "closed";
  init["door3"] = "open";
  return {{"initial_state", init},
          {"end_state", {{"maintenance_constraint", "true"}, {"goal_constraint", goal}}}};
}

Json SolveRescue(const Domain& dom, int n, Objective objective) {
  Diagnostics d;
  auto sp = LoadStatePlan(RescuePlan(n), dom, d);
  EXPECT_TRUE(sp) << AllErrors(d);
  if (!sp) return Json();
  SolveOptions o;
  o.objective = objective;
  o.time_limit_ms = 120000;
  auto r = SolveDocument(dom, *sp, o);
  if (auto* e = std::get_if<Error>(&r)) {
    ADD_FAILURE() << e->ToString();
    return Json();
  }
  return std::get<Json>(r);
}

TEST(TemplateDifferential, SearchRescueTemplateExpandsToTheGeneratedCopies) {
  for (int n = 2; n <= 8; ++n) {
    SCOPED_TRACE("N = " + std::to_string(n));
    auto t = FromTemplate(n);
    auto g = Generated(n);
    ASSERT_TRUE(t && g);
    ExpectSameAutomata(*t, *g);
  }
}

TEST(TemplateDifferential, SearchRescueTemplateSolvesLikeTheGeneratedCopies) {
  struct Case {
    int n;
    Objective objective;
  };
  // Small N only (a few seconds each); larger N are compared structurally above.
  for (const Case& c : {Case{2, Objective::kMakespan}, Case{3, Objective::kCost}}) {
    SCOPED_TRACE("N = " + std::to_string(c.n));
    auto t = FromTemplate(c.n);
    auto g = Generated(c.n);
    ASSERT_TRUE(t && g);
    Json a = SolveRescue(*t, c.n, c.objective);
    Json b = SolveRescue(*g, c.n, c.objective);
    ASSERT_TRUE(a.is_object() && b.is_object());
    EXPECT_EQ(a["status"], "optimal");
    EXPECT_EQ(a["status"], b["status"]);
    EXPECT_EQ(a["objective"], b["objective"]);
    EXPECT_EQ(a["goal_reached_at"], b["goal_reached_at"]);
    EXPECT_EQ(a["verified"], true);
    EXPECT_EQ(b["verified"], true);
    if (c.objective == Objective::kMakespan) {
      EXPECT_EQ(a["objective"]["value"], 11);  // the thesis' optimum (5.3.2)
    }
  }
}

}  // namespace
}  // namespace ctb
