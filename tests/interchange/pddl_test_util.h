// Helpers of the PDDL tests (pddl_import_test.cpp, pddl_semantics_test.cpp): fixtures, imports
// that must succeed or fail, lookups in an imported model, and a solve with the real minizinc.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "interchange/pddl/import.h"
#include "planner/model/domain.h"
#include "planner/model/state_plan.h"
#include "planner/solve/solve.h"

namespace ctb::pddl::testing {

inline std::string SourceDir() { return CTB_TEST_SOURCE_DIR; }

inline Source Fixture(const std::string& name) {
  std::string path = SourceDir() + "/tests/interchange/pddl/" + name;
  std::ifstream f(path);
  std::ostringstream s;
  s << f.rdbuf();
  EXPECT_FALSE(s.str().empty()) << path;
  return Source{name, s.str()};
}

inline std::string Issues(const std::vector<Issue>& issues) {
  std::string s;
  for (const auto& i : issues) s += i.ToString() + "\n";
  return s;
}

inline Imported MustImport(const Source& d, const std::optional<Source>& p) {
  auto r = ImportPddl(d, p);
  if (auto* e = std::get_if<std::vector<Issue>>(&r)) {
    ADD_FAILURE() << Issues(*e);
    return Imported{};
  }
  return std::get<Imported>(r);
}

inline std::vector<Issue> MustFail(const Source& d, const std::optional<Source>& p = std::nullopt) {
  auto r = ImportPddl(d, p);
  if (auto* e = std::get_if<std::vector<Issue>>(&r)) return *e;
  ADD_FAILURE() << "imported although it should not:\n" << std::get<Imported>(r).domain.dump(2);
  return {};
}

inline const Json* FindAutomaton(const Json& domain, const std::string& name) {
  for (const auto& a : domain["automata"])
    if (a["name"] == name) return &a;
  return nullptr;
}

inline const Json* FindTransition(const Json& automaton, const std::string& from,
                                  const std::string& to) {
  for (const auto& t : automaton["transitions"])
    if (t["from"] == from && t["to"] == to) return &t;
  return nullptr;
}

inline Json SolveImported(const Json& domain_json, const Json& plan_json, SolveOptions o = {}) {
  Diagnostics d;
  auto dom = LoadDomain(domain_json, d);
  EXPECT_TRUE(dom) << (d.errors().empty() ? "" : d.errors()[0].ToString());
  if (!dom) return Json();
  auto sp = LoadStatePlan(plan_json, *dom, d);
  EXPECT_TRUE(sp) << (d.errors().empty() ? "" : d.errors()[0].ToString());
  if (!sp) return Json();
  o.time_limit_ms = 120000;
  auto r = SolveDocument(*dom, *sp, o);
  if (auto* e = std::get_if<Error>(&r)) {
    ADD_FAILURE() << e->ToString();
    return Json();
  }
  return std::get<Json>(r);
}

}  // namespace ctb::pddl::testing
