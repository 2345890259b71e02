// Reading the JSON out of what an LLM answered, before anything is checked or repaired
// (docs/translator.md, "Extraction and normalisation"). Every change to the JSON text is
// reported as a warning (contract section 9); nothing here needs the domain.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "planner/model/error.h"
#include "planner/model/json_io.h"

namespace ctb {

// The answer without its reasoning blocks (<think>...</think>, <thinking>...</thinking>; an
// unclosed one runs to the end; a lone closing tag drops everything before it).
std::string StripThinking(std::string_view answer, bool* stripped = nullptr);

// The top-level {...} blocks of a text, found by balanced braces outside strings ("...",
// smart-quoted and, inside a block, '...'). `complete` in order of appearance; `unclosed` is a
// block still open at the end of the text (a cut-off answer).
struct JsonBlocks {
  std::vector<std::string> complete;
  std::optional<std::string> unclosed;
};
JsonBlocks FindJsonBlocks(std::string_view text);

// The JSON text of an answer: the last complete block that looks like a state plan (holds
// "initial_state" or "state_plan"), else the last complete block, else the unclosed one;
// nullopt when the answer has no '{'. Thinking blocks are stripped first.
std::optional<std::string> FindJson(const std::string& answer);

// JSON text with the usual LLM slips mended: comments, trailing commas, single and smart quotes
// as string delimiters, raw line breaks inside strings, Python's True/False/None. Each kind of
// change applied is appended to `applied` once, as a sentence.
std::string RelaxJson(std::string_view text, std::vector<std::string>& applied);

// What was read from one answer.
struct Extraction {
  std::optional<Json> json;        // the parsed value (any JSON type)
  std::vector<Diagnostic> notes;   // normalisations applied (warnings, pointer "")
  std::vector<Diagnostic> errors;  // why nothing could be read; messages quote the text
};

// Finds the JSON in an answer and parses it strictly, then tolerantly (RelaxJson) when the
// strict parse fails. A parse error names the problem and quotes the text around it (no byte
// offset); a refusal or an answer with no JSON quotes the model's own words. Never throws; every
// message is valid UTF-8.
Extraction ExtractJson(const std::string& answer);

}  // namespace ctb
