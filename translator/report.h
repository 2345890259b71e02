// What happened during execution, told in words (contract section 11: "robot 2 cannot open door
// 1", "the projector took two minutes to warm up"), turned by the LLM into the replanning fields
// `observed` and `blocked`.
//
// The LLM sees the domain, the plan being executed (its transitions with their times), `now` and
// the report, and answers {"observed"?, "blocked"?, "restatement"}. The caller's check reads the
// fields like a replanning request (errors at /observed/robot2/location, /blocked/0/to, ...);
// they go back to the LLM in a repair request quoting every error as `pointer: message`, at most
// max_repairs times; then kUnprocessable with every remaining error. Never throws.
#pragma once

#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/json_io.h"
#include "translator/llm.h"

namespace ctb {

struct ReportOptions {
  int max_repairs = 2;
  bool json_mode = false;
  std::string prompts_dir;  // empty: DefaultPromptsDir()
};

struct ReportResult {
  Json fields = Json::object();  // {"observed"?, "blocked"?}: checked
  std::string restatement;       // the report as the LLM understood it
  std::vector<Diagnostic> warnings;
  int llm_calls = 0;
  int repairs = 0;
};

// The errors of the fields (pointers relative to the replanning request: /observed/..., /blocked/k).
using ReportCheck = std::function<std::vector<Diagnostic>(const Json& fields)>;

// Errors: kInvalidInput (an empty report or one over 2000 characters, pointer "/command"), the LLM
// client's errors, kUnprocessable (still invalid after the repairs).
std::variant<ReportResult, Error> ReadReport(const Domain& d, const Json& trajectory, double now,
                                             const std::string& report, LlmClient& llm,
                                             const ReportCheck& check, const ReportOptions& o = {});

// The plan as the prompt shows it: one line per transition, "t=12 s  robot1: atDoor1 ->
// door1Opening (command openDoor1)", those before now marked as done.
std::string PlanLines(const Json& trajectory, double now);

}  // namespace ctb
