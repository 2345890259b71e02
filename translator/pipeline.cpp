#include "translator/pipeline.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "planner/model/state_plan.h"

#ifndef CTB_BUILTIN_PROMPTS_DIR
#define CTB_BUILTIN_PROMPTS_DIR "prompts"
#endif

namespace ctb {

std::optional<Prompting> ParsePrompting(const std::string& s) {
  if (s == "cot") return Prompting::kCot;
  if (s == "direct") return Prompting::kDirect;
  return std::nullopt;
}

std::string DefaultPromptsDir() {
  if (const char* env = std::getenv("CTB_PROMPTS_DIR"); env && *env) return env;
  std::error_code ec;
  if (std::filesystem::is_regular_file("prompts/system.txt", ec)) return "prompts";
  return CTB_BUILTIN_PROMPTS_DIR;
}

namespace {

std::optional<std::string> ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string Fill(std::string text, const std::vector<std::pair<std::string, std::string>>& vars) {
  for (const auto& [name, value] : vars) {
    const std::string key = "{{" + name + "}}";
    std::string out;
    std::size_t pos = 0, at;
    while ((at = text.find(key, pos)) != std::string::npos) {
      out += text.substr(pos, at - pos) + value;
      pos = at + key.size();
    }
    text = out + text.substr(pos);
  }
  return text;
}

std::string Seconds(double s) {
  if (s == static_cast<double>(static_cast<long>(s))) return std::to_string(static_cast<long>(s));
  return Json(s).dump();
}

}  // namespace

std::string DescribeDomain(const Domain& d) {
  std::string out = "Action model \"" + d.name + "\"" +
                    (d.description.empty() ? "" : ": " + d.description) + ".\nAutomata:\n";
  for (const auto& a : d.automata) {
    out += "- " + a.name + " (location variable " + a.name + "l";
    if (!a.commands.empty()) out += ", command variable " + a.name + "u";
    out += "): locations";
    for (std::size_t i = 0; i < a.locations.size(); ++i) out += (i ? ", " : " ") + a.locations[i];
    if (!a.commands.empty()) {
      out += "; commands";
      for (std::size_t i = 0; i < a.commands.size(); ++i) out += (i ? ", " : " ") + a.commands[i];
    }
    out += "\n";
    for (const auto& t : a.transitions) {
      out += "    " + a.locations[t.from] + " -> " + a.locations[t.to];
      if (t.guard_text != "true") out += " when " + t.guard_text;
      if (t.duration.hi && t.duration.lo == *t.duration.hi && t.duration.lo > 0)
        out += " after " + Seconds(t.duration.lo) + " s";
      else if (t.duration.lo > 0 || t.duration.hi)
        out += " after [" + Seconds(t.duration.lo) + ", " +
               (t.duration.hi ? Seconds(*t.duration.hi) : std::string("inf")) + "] s";
      out += "\n";
    }
  }
  return out;
}

std::optional<std::string> FindJson(const std::string& answer) {
  // A fenced block that holds an object.
  std::size_t pos = 0;
  while ((pos = answer.find("```", pos)) != std::string::npos) {
    std::size_t start = answer.find('\n', pos);
    if (start == std::string::npos) break;
    std::size_t end = answer.find("```", start);
    if (end == std::string::npos) break;
    std::string block = answer.substr(start + 1, end - start - 1);
    auto brace = block.find('{');
    if (brace != std::string::npos && block.find_first_not_of(" \t\r\n") == brace) return block;
    pos = end + 3;
  }
  auto first = answer.find('{');
  auto last = answer.rfind('}');
  if (first == std::string::npos || last == std::string::npos || last < first) {
    if (first != std::string::npos) return answer.substr(first);  // truncated: let the parser say
    return std::nullopt;
  }
  return answer.substr(first, last - first + 1);
}

namespace {

struct Check {
  std::optional<Json> plan;
  std::vector<Diagnostic> errors;
  std::vector<Diagnostic> warnings;
};

Check CheckAnswer(const std::string& answer, const Domain& d) {
  Check c;
  auto text = FindJson(answer);
  if (!text) {
    c.errors.push_back({"", std::nullopt, "the answer holds no JSON object"});
    return c;
  }
  Diagnostics diags;
  auto j = ParseJsonStrict(*text, diags);
  if (j) LoadStatePlan(*j, d, diags);
  c.errors = diags.errors();
  c.warnings = diags.warnings();
  if (c.errors.empty()) c.plan = j;
  return c;
}

std::string ListProblems(const Check& c) {
  std::string out;
  for (const auto& e : c.errors) out += e.ToString() + "\n";
  for (const auto& w : c.warnings) out += "warning: " + w.ToString() + "\n";
  return out;
}

}  // namespace

std::variant<TranslateResult, Error> Translate(const Domain& d, const std::string& command,
                                               LlmClient& llm, const TranslateOptions& o) {
  const std::string dir = o.prompts_dir.empty() ? DefaultPromptsDir() : o.prompts_dir;
  auto load = [&](const std::string& name) { return ReadText(dir + "/" + name); };
  auto system = load("system.txt"), extract = load("cot_extract.txt"), map = load("cot_map.txt"),
       direct = load("direct.txt"), repair = load("repair.txt"), followup = load("followup.txt");
  if (!system || !extract || !map || !direct || !repair || !followup)
    return Error{ErrorCode::kInternal, "prompt files missing in '" + dir + "'", {}};
  if (command.empty() || command.size() > 8000)
    return Error{ErrorCode::kInvalidInput, "the command must have 1 to 8000 characters",
                 {{"/command", std::nullopt, "empty or too long"}}};
  // In-context examples of the domain (a new domain works without any).
  std::string examples;
  if (auto ex = load("examples/" + d.name + ".json")) {
    Diagnostics ed;
    auto j = ParseJsonStrict(*ex, ed);
    if (j && j->is_array())
      for (const auto& pair : *j) {
        if (!pair.is_object() || !pair.contains("command") || !pair.contains("state_plan")) continue;
        examples += "Natural language input:\n" + pair["command"].get<std::string>() + "\n\n";
        if (o.prompting == Prompting::kCot && pair.contains("reasoning"))
          examples += "Extracted:\n" + pair["reasoning"].get<std::string>() + "\n\n";
        examples += "state_plan.json:\n" + pair["state_plan"].dump(2) + "\n\n";
      }
  }
  if (examples.empty()) examples = "(no examples for this domain)\n";

  TranslateResult result;
  std::vector<ChatMessage> msgs = o.history;
  if (msgs.empty())
    msgs.push_back({"system", Fill(*system, {{"domain", DescribeDomain(d)}, {"examples", examples}})});
  ChatRequest req;
  req.json_mode = false;
  auto ask = [&](bool want_json) -> std::variant<std::string, Error> {
    req.messages = msgs;
    req.json_mode = want_json && o.json_mode;
    ++result.llm_calls;
    auto r = llm.Complete(req);
    if (auto* e = std::get_if<Error>(&r)) return *e;
    std::string content = std::get<ChatResponse>(r).content;
    msgs.push_back({"assistant", content});
    return content;
  };

  std::variant<std::string, Error> answer;
  if (o.previous_state_plan) {
    msgs.push_back({"user", Fill(*followup, {{"state_plan", o.previous_state_plan->dump(2)},
                                             {"command", command}})});
    answer = ask(true);
  } else if (o.prompting == Prompting::kCot) {
    msgs.push_back({"user", Fill(*extract, {{"command", command}})});
    auto reasoning = ask(false);
    if (auto* e = std::get_if<Error>(&reasoning)) return *e;
    result.reasoning = std::get<std::string>(reasoning);
    msgs.push_back({"user", *map});
    answer = ask(true);
  } else {
    msgs.push_back({"user", Fill(*direct, {{"command", command}})});
    answer = ask(true);
  }
  if (auto* e = std::get_if<Error>(&answer)) return *e;
  Check check = CheckAnswer(std::get<std::string>(answer), d);
  while ((!check.errors.empty() || !check.warnings.empty()) && result.repairs < o.max_repairs) {
    ++result.repairs;
    msgs.push_back({"user", Fill(*repair, {{"errors", ListProblems(check)},
                                           {"answer", std::get<std::string>(answer)}})});
    answer = ask(true);
    if (auto* e = std::get_if<Error>(&answer)) return *e;
    Check next = CheckAnswer(std::get<std::string>(answer), d);
    // A repair that breaks a usable plan does not replace it.
    if (check.errors.empty() && !next.errors.empty()) break;
    check = std::move(next);
  }
  if (!check.errors.empty()) {
    Error e{ErrorCode::kUnprocessable,
            "the LLM's state plan is still invalid after " + std::to_string(result.repairs) +
                " repair request(s)",
            check.errors};
    return e;
  }
  result.state_plan = *check.plan;
  result.warnings = check.warnings;
  result.conversation = msgs;
  return result;
}

}  // namespace ctb
