// Errors and diagnostics shared by every ctburton library.
//
// "Could not run" is an Error (a code that maps one-to-one onto an HTTP status, a message, and
// the list of problems found, each with the JSON pointer of the offending value). "Ran and
// answered" is a result type of its own (see solve.h): an infeasible plan is not an Error.
// No function of the libraries throws across its public interface.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace ctb {

enum class ErrorCode {
  kInvalidInput,    // 400: bad JSON, bad domain or state plan, bad option
  kNotFound,        // 404: unknown domain, session or route
  kTooLarge,        // 413: body or input beyond a limit
  kUnprocessable,   // 422: the LLM's answer could not be repaired
  kBusy,            // 503 (with Retry-After): solver pool full
  kUnavailable,     // 503: no LLM endpoint configured, minizinc missing
  kUpstreamFailed,  // 502: LLM endpoint answered with an error
  kUpstreamTimeout, // 504: LLM endpoint timed out
  kInternal,        // 500: a bug (e.g. a trajectory that fails verification)
  kConflict,        // 409: a session changed meanwhile; a name that exists
  kUnauthenticated, // 401: no or a wrong API key
};

// HTTP status for a code, and the stable lower-case name used in JSON ("invalid_input", ...).
int HttpStatus(ErrorCode code);
const char* CodeName(ErrorCode code);

// One problem in an input: where (a JSON pointer, and a character offset into the string at that
// pointer when the problem is inside an expression) and what.
struct Diagnostic {
  std::string pointer;
  std::optional<std::size_t> offset;
  std::string message;

  // "<pointer>: offset N: <message>" or "<pointer>: <message>"; the root pointer prints as "/".
  std::string ToString() const;
};

// Collects errors and warnings while a loader walks its input. Loaders keep going after an error
// where they can, so that one run reports every problem.
class Diagnostics {
 public:
  void Error(std::string pointer, std::string message,
             std::optional<std::size_t> offset = std::nullopt);
  void Warning(std::string pointer, std::string message,
               std::optional<std::size_t> offset = std::nullopt);
  bool ok() const { return errors_.empty(); }
  const std::vector<Diagnostic>& errors() const { return errors_; }
  const std::vector<Diagnostic>& warnings() const { return warnings_; }
  void Append(const Diagnostics& other);

 private:
  std::vector<Diagnostic> errors_;
  std::vector<Diagnostic> warnings_;
};

// A bound an input went beyond: its name (e.g. "max_locations_per_automaton"), its value, and
// the figure the input asked for.
struct Limit {
  std::string name;
  long value = 0;
  long actual = 0;
};

struct Error {
  ErrorCode code = ErrorCode::kInternal;
  std::string message;
  std::vector<Diagnostic> details;  // every problem found, in input order
  // For kTooLarge from a budget or a size bound: the limit exceeded; else none.
  std::optional<Limit> limit = {};

  static Error FromDiagnostics(ErrorCode code, std::string message, const Diagnostics& d);
  // The message followed by one line per detail.
  std::string ToString() const;
};

// Escapes one JSON-pointer reference token (RFC 6901: "~" -> "~0", "/" -> "~1").
std::string PointerToken(const std::string& key);

// A client-supplied string cut to at most `max` bytes (on a UTF-8 boundary) with "..." appended
// when cut, for echoing in messages: a 1 MB id is never sent back whole.
std::string Echo(const std::string& s, std::size_t max = 64);

}  // namespace ctb
