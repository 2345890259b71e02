// Subcommands of the `ctburton` executable. Each registers its options on the CLI11 app and
// returns the process exit code when run.
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

#include "planner/model/error.h"

namespace ctb::cli {

using Runner = std::function<int()>;

// Prints "error (<code>): <message>" and one line per detail to stderr.
void PrintError(const Error& e);

// The one exit-code map of the commands that report an Error: 1 bad input (or unknown name),
// 4 the LLM's answer could not be repaired, 3 anything else (endpoint, solver, server failed).
// (`solve` and `validate` also use 2 for a domain file that does not load.)
int ExitCodeFor(ErrorCode code);

// PrintError(e), then its exit code (ExitCodeFor).
int Fail(const Error& e);

// `ctburton validate --domain NAME|PATH FILE`: exit 0 and "valid" (warnings after it) or exit 1
// and one line per error: "<json pointer>: <offset if any>: <message>".
Runner AddValidate(CLI::App& app);

// `ctburton solve --domain NAME|PATH FILE [...]`: the trajectory JSON on stdout, exit 0 for
// optimal/feasible/infeasible/unknown answers; 1 bad input, 2 bad domain, 3 solver failure.
Runner AddSolve(CLI::App& app);

// `ctburton translate --domain NAME "command" [--prompting cot|direct]`: prints
// {"state_plan", "reasoning"}; 1 bad input, 3 LLM endpoint missing/failed/timed out, 4 the
// answer could not be repaired.
Runner AddTranslate(CLI::App& app);

// `ctburton plan [--server URL] --domain NAME "command" [--session ID]`: translate and solve,
// locally or through a running server; prints {state_plan, reasoning, trajectory[, session]}.
Runner AddPlan(CLI::App& app);

// `ctburton eval --suite FILE [--json] [--time-limit-ms N]` (contract section 15): each item's
// verdict, then the totals and rates; with --json one object a line, then the totals line.
Runner AddEval(CLI::App& app);

// `ctburton schema --domain NAME|PATH`: prints the JSON Schema of the domain's state plans (the
// one sent with CTB_LLM_RESPONSE_FORMAT=json_schema); 2 for a bad domain.
Runner AddSchema(CLI::App& app);

// `ctburton replan --domain NAME|PATH FILE --trajectory PLAN --now T [--executed J] [--observed J]
// [--blocked J] [--keep K]`: one replan (contract section 11); the answer JSON on stdout; 1 bad
// input, 3 solver failure.
Runner AddReplan(CLI::App& app);

// `ctburton execute --domain NAME|PATH FILE [--speed N] [--fault SPEC]... [--faults-stdin]`:
// dispatches the plan on a clock, prints each transition when due, injects faults, replans and
// goes on; 0 when the goal is reached, 1 when a replan is infeasible or fails, 2 bad usage.
Runner AddExecute(CLI::App& app);

// `ctburton domain check|expand|draw FILE [--set N=8]`, `ctburton domain draft "words"` and
// `ctburton domain import-pddl DOMAIN.pddl [PROBLEM.pddl]`: check prints "valid: ..." or one
// located error a line (exit 1); expand prints the document with its templates expanded; draw
// prints SVG; draft prints {action_model, restatement, questions}; import-pddl prints the action
// model (issues on stderr, exit 1).
Runner AddDomain(CLI::App& app);

// `ctburton network check FILE`: prints {"consistent", "strong", "dynamic", "conflict"?, "ms"}
// (the answer of POST /networks/check), exit 0; or the located errors and exit 1.
Runner AddNetwork(CLI::App& app);

// `ctburton serve [--port N] [--config FILE]`: the HTTP service until SIGTERM/SIGINT. Only in
// ctburton-server, which links the server (gRPC, MQTT, HTTP).
Runner AddServe(CLI::App& app);

// In `ctburton`: replaces the process with ctburton-server from the same folder, with the same
// arguments (same pid, so signals reach the service); returns 3 with a message if it cannot.
int ExecServer(char** argv);
// In `ctburton`: lists `serve` in --help (the call itself never gets here: main execs first).
void AddServeEntry(CLI::App& app);

}  // namespace ctb::cli
