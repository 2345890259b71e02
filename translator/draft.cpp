#include "translator/draft.h"

#include "planner/model/domain.h"
#include "translator/chat_loop.h"
#include "translator/extract.h"
#include "translator/pipeline.h"
#include "translator/prompt_files.h"
#include "translator/text.h"

namespace ctb {

namespace {

struct Checked {
  std::optional<Json> model;         // the action model, when it loads
  Json answer;                       // the wrapper object, when one was read
  std::vector<Diagnostic> errors;    // pointers inside the action model ("" for the answer)
  std::vector<Diagnostic> warnings;
};

Checked CheckDraft(const ChatResponse& r) {
  Checked c;
  for (const auto& n : r.notes) c.warnings.push_back({"", std::nullopt, n});
  if (r.content.find_first_not_of(" \t\r\n") == std::string::npos) {
    c.errors.push_back({"", std::nullopt,
                        r.refusal.empty() ? "the answer was empty"
                                          : "the model refused: \"" + Cut(r.refusal, 200) + "\""});
    return c;
  }
  Extraction x = ExtractJson(r.content);
  c.warnings.insert(c.warnings.end(), x.notes.begin(), x.notes.end());
  if (!x.json) {
    c.errors = x.errors;
    return c;
  }
  if (!x.json->is_object()) {
    c.errors.push_back({"", std::nullopt, std::string("expected a JSON object, got ") +
                                              JsonTypeName(*x.json)});
    return c;
  }
  Json model;
  if (x.json->contains("action_model")) {
    c.answer = *x.json;
    model = (*x.json)["action_model"];
  } else if (x.json->contains("automata")) {
    // The model alone: taken, and said.
    model = *x.json;
    c.answer = {{"action_model", model}};
    c.warnings.push_back({"", std::nullopt,
                          "the answer held the action model alone, without restatement or questions"});
  } else {
    c.errors.push_back({"", std::nullopt, "the answer has no \"action_model\""});
    return c;
  }
  Diagnostics diags;
  auto d = LoadDomain(model, diags);
  for (const auto& e : diags.errors()) {
    Diagnostic q = e;
    q.message = ValidUtf8(q.message);
    c.errors.push_back(std::move(q));
  }
  for (const auto& w : diags.warnings()) c.warnings.push_back(w);
  if (d && diags.ok()) c.model = model;
  return c;
}

}  // namespace

std::variant<DraftResult, Error> Draft(const std::string& description, LlmClient& llm,
                                       const DraftOptions& o) {
  if (description.find_first_not_of(" \t\r\n") == std::string::npos || description.size() > 8000)
    return Error{ErrorCode::kInvalidInput, "the description must have 1 to 8000 characters",
                 {{"/description", std::nullopt, "empty or too long"}}};
  const std::string dir = o.prompts_dir.empty() ? DefaultPromptsDir() : o.prompts_dir;
  auto system = ReadPromptFile(dir + "/draft.txt"), user = ReadPromptFile(dir + "/draft_user.txt"),
       repair = ReadPromptFile(dir + "/draft_repair.txt");
  if (!system || !user || !repair)
    return Error{ErrorCode::kInternal, "draft prompt files missing in '" + dir + "'", {}};
  DraftResult result;
  ChatLoop chat(llm, o.json_mode,
                {{"system", *system},
                 {"user", FillPrompt(*user, {{"description", ValidUtf8(description)}})}});
  auto answer = chat.Ask();
  if (auto* e = std::get_if<Error>(&answer)) return *e;
  Checked c = CheckDraft(std::get<ChatResponse>(answer));
  while (!c.errors.empty() && chat.repairs() < o.max_repairs) {
    answer = chat.Repair(FillPrompt(*repair, {{"errors", ListProblems(c.errors)}}));
    if (auto* e = std::get_if<Error>(&answer)) return *e;
    c = CheckDraft(std::get<ChatResponse>(answer));
  }
  result.llm_calls = chat.calls();
  result.repairs = chat.repairs();
  if (!c.errors.empty())
    return Error{ErrorCode::kUnprocessable,
                 "the LLM's action model is still invalid after " + std::to_string(result.repairs) +
                     " repair request(s)",
                 c.errors};
  result.action_model = *c.model;
  result.warnings = c.warnings;
  const Json& a = c.answer;
  if (a.contains("restatement") && a["restatement"].is_string()) {
    result.restatement = ValidUtf8(a["restatement"].get<std::string>());
  } else {
    result.warnings.push_back({"/restatement", std::nullopt, "the answer had no restatement"});
  }
  if (a.contains("questions") && a["questions"].is_array()) {
    for (const auto& q : a["questions"])
      if (q.is_string() && !q.get<std::string>().empty())
        result.questions.push_back(ValidUtf8(Cut(q.get<std::string>(), 1000)));
  } else if (a.contains("questions")) {
    result.warnings.push_back({"/questions", std::nullopt, "questions was not a list; ignored"});
  }
  return result;
}

Json DraftJson(const DraftResult& r) {
  Json out = {{"action_model", r.action_model},
              {"restatement", r.restatement},
              {"questions", r.questions}};
  if (!r.warnings.empty()) out["warnings"] = WarningsJson(r.warnings);
  return out;
}

}  // namespace ctb
