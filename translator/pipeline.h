// Natural language to a checked state plan (contract section 7, thesis chapter 4).
//
// Chain of thought (default): the LLM first extracts initial state, end state, episodes and
// temporal constraints as text, then maps that text to the JSON. Direct: the JSON at once. The
// answer's JSON is found and normalised (extract.h, normalize_answer.h: each change a warning),
// checked against the domain and by the meaning guards (guards.h); errors and doubts go back in
// a repair request quoting them verbatim, at most max_repairs times; then kUnprocessable with
// every remaining error. A repair that drops what a usable answer had is not taken.
#pragma once

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "planner/model/domain.h"
#include "translator/extract.h"
#include "translator/llm.h"

namespace ctb {

enum class Prompting { kCot, kDirect };
std::optional<Prompting> ParsePrompting(const std::string& s);

struct TranslateOptions {
  Prompting prompting = Prompting::kCot;
  int max_repairs = 2;
  ResponseFormat response_format = ResponseFormat::kNone;  // for the requests that want JSON
  std::string prompts_dir;  // empty: DefaultPromptsDir()
  // A follow-up in a dialogue: the previous exchange and the state plan to edit.
  std::vector<ChatMessage> history;
  std::optional<Json> previous_state_plan;
  // Filled as the translation goes, also when it fails (ctburton eval): whether any answer
  // could be read as JSON, and the tokens the endpoint reported.
  struct Progress {
    bool read_json = false;
    long tokens = 0;
  };
  Progress* progress = nullptr;
};

struct TranslateResult {
  Json state_plan;
  std::string reasoning;
  int llm_calls = 0;
  int repairs = 0;
  std::vector<Diagnostic> warnings;  // normalisations applied, doubts left (contract section 9)
  std::vector<ChatMessage> conversation;  // for follow-ups (long answers as bounded excerpts)
};

std::string DefaultPromptsDir();

// The compact description of a domain given to the LLM, generated from its JSON. A domain
// written with templates ends with its teams and the quantifiers a condition may use over them
// (prompts_dir/teams.txt; the default prompts directory when empty); eight or more consecutive
// instances the same as their template's first are said in one line.
std::string DescribeDomain(const Domain& d, const std::string& prompts_dir = "");

// The in-context examples of the prompt: the domain's own (prompts_dir/examples/<name>.json), or,
// for a domain with none, the first example of each other domain there, each introduced by a
// label naming that domain and its automata.
std::string PromptExamples(const Domain& d, const std::string& prompts_dir, Prompting prompting);

// The warnings of a result as the contract's JSON: [{"path"?, "message"}].
Json WarningsJson(const std::vector<Diagnostic>& warnings);

std::variant<TranslateResult, Error> Translate(const Domain& d, const std::string& command,
                                               LlmClient& llm, const TranslateOptions& o);

}  // namespace ctb
