// Drafting an action model from a description in words (contract section 12, POST
// /domains/draft, `ctburton domain draft`).
//
// The LLM answers {"action_model", "restatement", "questions"}; the action model is checked like
// any domain document (templates allowed, errors located by JSON pointer inside the action
// model) and sent back in a repair request quoting every error as `pointer: message`, at most
// max_repairs times; then kUnprocessable with every remaining error. The result is a draft: it
// is never stored here.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "planner/model/error.h"
#include "planner/model/json_io.h"
#include "translator/llm.h"

namespace ctb {

struct DraftOptions {
  int max_repairs = 2;
  bool json_mode = false;   // ask the endpoint for a JSON object (response_format json_object)
  std::string prompts_dir;  // empty: DefaultPromptsDir()
};

struct DraftResult {
  Json action_model;                  // as the LLM wrote it (templates kept), checked
  std::string restatement;
  std::vector<std::string> questions;
  std::vector<Diagnostic> warnings;   // normalisations applied, fields the answer lacked
  int llm_calls = 0;
  int repairs = 0;
};

// Errors: kInvalidInput (empty or over 8000 characters, pointer "/description"), the LLM
// client's errors, kUnprocessable (still invalid after the repairs: every error, pointers
// inside the action model).
std::variant<DraftResult, Error> Draft(const std::string& description, LlmClient& llm,
                                       const DraftOptions& o = {});

// {"action_model", "restatement", "questions", "warnings"?} (the answer of POST /domains/draft).
Json DraftJson(const DraftResult& r);

}  // namespace ctb
