// Helpers shared by the fuzz targets (docs/reliability.md). Each target reads its input as
// untrusted text exactly as the service does and checks invariants; a broken invariant is a
// finding and stops the run with __builtin_trap (libFuzzer keeps the input as a crash).
#pragma once

#include <cstddef>
#include <cstdio>
#include <cstdint>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>

#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/json_io.h"
#include "planner/model/state_plan.h"

// The source tree, for the shipped domains and examples the targets plan against.
#ifndef CTB_FUZZ_SOURCE_DIR
#error "CTB_FUZZ_SOURCE_DIR must be defined by the build"
#endif

namespace ctb::fuzz {

// Stops the run: a broken invariant. `what` is printed first so the report says which.
[[noreturn]] inline void Fail(const char* what) {
  std::fprintf(stderr, "fuzz invariant broken: %s\n", what);
  __builtin_trap();
}

inline std::string_view Text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// A JSON pointer as the loaders write them: "" (the root) or "/..." tokens.
inline bool WellFormedPointer(const std::string& p) { return p.empty() || p[0] == '/'; }

// Every diagnostic has a well-formed pointer and a message; an error list is not empty.
inline void CheckDiagnostics(const Diagnostics& d) {
  for (const auto& e : d.errors()) {
    if (!WellFormedPointer(e.pointer)) Fail("an error's pointer is not a JSON pointer");
    if (e.message.empty()) Fail("an error without a message");
  }
  for (const auto& w : d.warnings())
    if (!WellFormedPointer(w.pointer)) Fail("a warning's pointer is not a JSON pointer");
}

inline void CheckError(const Error& e) {
  if (e.message.empty()) Fail("an Error without a message");
  for (const auto& d : e.details)
    if (!WellFormedPointer(d.pointer)) Fail("an Error detail's pointer is not a JSON pointer");
  if (e.code == ErrorCode::kInvalidInput && e.details.empty())
    Fail("an invalid-input Error that points nowhere");
}

// Text that serialises as JSON without replacement: valid UTF-8 (what the service sends).
inline void CheckUtf8(const std::string& s, const char* what) {
  try {
    (void)Json(s).dump();
  } catch (...) {
    Fail(what);
  }
}

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Loads a domain of the source tree (path relative to it); traps when it does not load.
inline Domain LoadShippedDomain(const std::string& rel) {
  Diagnostics d;
  auto j = ParseJsonStrict(ReadFile(std::string(CTB_FUZZ_SOURCE_DIR) + "/" + rel), d);
  if (!j) Fail("a shipped domain does not parse");
  auto dom = LoadDomain(*j, d);
  if (!dom) Fail("a shipped domain does not load");
  return *dom;
}

inline StatePlan LoadShippedStatePlan(const std::string& rel, const Domain& dom) {
  Diagnostics d;
  auto j = ParseJsonStrict(ReadFile(std::string(CTB_FUZZ_SOURCE_DIR) + "/" + rel), d);
  if (!j) Fail("a shipped state plan does not parse");
  auto sp = LoadStatePlan(*j, dom, d);
  if (!sp) Fail("a shipped state plan does not load");
  return *sp;
}

}  // namespace ctb::fuzz
