// Helpers shared by the planner tests.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "planner/model/catalog.h"
#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb::testing {

inline std::string SourceDir() { return CTB_TEST_SOURCE_DIR; }
inline std::string ConfigDir() { return SourceDir() + "/config"; }

// Loads a shipped domain; aborts the test binary when it does not load (a broken fixture).
inline const Domain& ShippedDomain(const std::string& name) {
  static std::map<std::string, Domain> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  Diagnostics d;
  auto dom = LoadDomainByNameOrPath(name, ConfigDir(), d);
  if (!dom) {
    for (auto& e : d.errors()) fprintf(stderr, "%s\n", e.ToString().c_str());
    abort();
  }
  return cache.emplace(name, std::move(*dom)).first->second;
}

inline Json MustParse(const std::string& text) {
  Diagnostics d;
  auto j = ParseJsonStrict(text, d);
  if (!j) abort();
  return *j;
}

// True when diags holds an error at exactly this pointer whose message contains `part`.
inline bool HasError(const Diagnostics& d, const std::string& pointer, const std::string& part,
                     std::optional<std::size_t> offset = std::nullopt) {
  for (const auto& e : d.errors())
    if (e.pointer == pointer && e.message.find(part) != std::string::npos &&
        (!offset || e.offset == offset))
      return true;
  return false;
}

inline std::string AllErrors(const Diagnostics& d) {
  std::string s;
  for (const auto& e : d.errors()) s += e.ToString() + "\n";
  return s;
}

// Loads a state-plan file against a shipped domain; a test failure naming the file when it does
// not load (then an empty state plan).
inline StatePlan ShippedStatePlan(const std::string& domain, const std::string& path) {
  Diagnostics d;
  auto j = ReadJsonFile(path, d);
  auto sp = j ? LoadStatePlan(*j, ShippedDomain(domain), d) : std::nullopt;
  if (!sp) {
    ADD_FAILURE() << path << AllErrors(d);
    return StatePlan{};
  }
  return *sp;
}

}  // namespace ctb::testing
