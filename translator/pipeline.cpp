#include "translator/pipeline.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "planner/model/state_plan.h"
#include "translator/guards.h"
#include "translator/normalize_answer.h"
#include "translator/prompt_files.h"
#include "translator/schema.h"
#include "translator/text.h"

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

std::string Seconds(double s) {
  if (s == static_cast<double>(static_cast<long>(s))) return std::to_string(static_cast<long>(s));
  return Json(s).dump();
}

// One example pair as the prompt shows it.
std::string ExamplePair(const Json& pair, Prompting prompting) {
  std::string out = "Natural language input:\n" + pair["command"].get<std::string>() + "\n\n";
  if (prompting == Prompting::kCot && pair.contains("reasoning") && pair["reasoning"].is_string())
    out += "Extracted:\n" + pair["reasoning"].get<std::string>() + "\n\n";
  return out + "state_plan.json:\n" + pair["state_plan"].dump(2) + "\n\n";
}

// The pairs of prompts/examples/<name>.json that are usable.
std::vector<Json> ExamplePairs(const std::string& path) {
  std::vector<Json> out;
  auto text = ReadPromptFile(path);
  if (!text) return out;
  Diagnostics ed;
  auto j = ParseJsonStrict(*text, ed);
  if (!j || !j->is_array()) return out;
  for (const auto& pair : *j)
    if (pair.is_object() && pair.contains("command") && pair["command"].is_string() &&
        pair.contains("state_plan") && pair["state_plan"].is_object())
      out.push_back(pair);
  return out;
}

// Per automaton: the index of the first instance of its template when it is the same automaton
// up to its name (locations, commands, and transitions with the instance's name in its guards);
// -1 otherwise (and for the first instance itself).
std::vector<int> SameAsFirstInstance(const Domain& d) {
  std::vector<int> out(d.automata.size(), -1);
  // The guard with the automaton's own variables (from, fromL, fromU as whole names) renamed.
  auto rename = [](const std::string& s, const std::string& from, const std::string& to) {
    std::string out;
    auto name_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    for (std::size_t k = 0; k < s.size();) {
      if (!name_char(s[k])) {
        out += s[k++];
        continue;
      }
      std::size_t e = k;
      while (e < s.size() && name_char(s[e])) ++e;
      const std::string word = s.substr(k, e - k);
      if (word == from || word == from + "l" || word == from + "u") out += to + word.substr(from.size());
      else out += word;
      k = e;
    }
    return out;
  };
  for (const auto& t : d.templates) {
    int first = -1;
    for (const auto& v : t.values) {
      const int a = d.AutomatonIndex(t.name + v);
      if (a < 0) break;
      if (first < 0) {
        first = a;
        continue;
      }
      const Automaton& x = d.automata[first];
      const Automaton& y = d.automata[a];
      bool same = x.locations == y.locations && x.commands == y.commands &&
                  x.transitions.size() == y.transitions.size();
      for (std::size_t k = 0; same && k < x.transitions.size(); ++k) {
        const Transition& s = x.transitions[k];
        const Transition& u = y.transitions[k];
        same = s.from == u.from && s.to == u.to && s.duration.lo == u.duration.lo &&
               s.duration.hi == u.duration.hi &&
               rename(s.guard_text, x.name, y.name) == u.guard_text;
      }
      if (same) out[a] = first;
    }
  }
  return out;
}

// What the expression language lets a state plan say of a team (expr.h), from
// prompts_dir/teams.txt with this domain's templates as the examples; "" when the file is missing.
std::string QuantifierNote(const Domain& d, const std::string& prompts_dir) {
  auto text = ReadPromptFile(prompts_dir + "/teams.txt");
  if (!text) return "";
  std::string teams;
  for (const auto& t : d.templates) {
    teams += (teams.empty() ? "" : " ") + t.name + " = ";
    if (t.values.empty()) teams += "(none)";
    else if (t.values.size() <= 3)
      for (std::size_t k = 0; k < t.values.size(); ++k) teams += (k ? ", " : "") + t.name + t.values[k];
    else teams += t.name + t.values.front() + " .. " + t.name + t.values.back();
    teams += " (" + std::to_string(t.values.size()) + ");";
  }
  const auto& t = d.templates.front();
  return FillPrompt(*text, {{"teams", teams},
                            {"template", t.name},
                            {"first", t.name + (t.values.empty() ? "1" : t.values.front())}});
}

}  // namespace

std::string PromptExamples(const Domain& d, const std::string& prompts_dir, Prompting prompting) {
  std::string examples;
  for (const auto& pair : ExamplePairs(prompts_dir + "/examples/" + d.name + ".json"))
    examples += ExamplePair(pair, prompting);
  if (!examples.empty()) return examples;
  // A domain nobody wrote examples for: the first example of every shipped domain, each
  // introduced by a label naming its domain and its automata (contract section 12).
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(prompts_dir + "/examples", ec))
    if (entry.path().extension() == ".json") files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  for (const auto& file : files) {
    std::string other = std::filesystem::path(file).stem().string();
    if (other == d.name) continue;
    auto pairs = ExamplePairs(file);
    if (pairs.empty()) continue;
    std::string automata;
    if (pairs[0]["state_plan"].contains("initial_state") &&
        pairs[0]["state_plan"]["initial_state"].is_object())
      for (const auto& [k, v] : pairs[0]["state_plan"]["initial_state"].items())
        automata += (automata.empty() ? "" : ", ") + k;
    examples += "Example from another domain, \"" + other + "\" (its automata " + automata +
                " belong to that domain only, not to \"" + d.name + "\"):\n\n" +
                ExamplePair(pairs[0], prompting);
  }
  if (examples.empty()) return "(no examples for this domain)\n";
  return "The domain \"" + d.name +
         "\" has no examples of its own. The examples below come from other domains and show the "
         "format only: use only the automata, locations and commands of \"" + d.name +
         "\" described above.\n\n" + examples;
}

std::string DescribeDomain(const Domain& d, const std::string& prompts_dir) {
  std::string out = "Action model \"" + d.name + "\"" +
                    (d.description.empty() ? "" : ": " + d.description) + ".\nAutomata:\n";
  // Runs of at least kMinCompactRun instances the same as their template's first are said in one
  // line (a team of hundreds would fill the prompt); a smaller team is described in full.
  constexpr std::size_t kMinCompactRun = 8;
  std::vector<int> same = SameAsFirstInstance(d);
  for (std::size_t i = 0; i < same.size();) {
    std::size_t e = i + 1;
    while (e < same.size() && same[i] >= 0 && same[e] == same[i]) ++e;
    if (same[i] >= 0 && e - i < kMinCompactRun) std::fill(same.begin() + i, same.begin() + e, -1);
    i = e;
  }
  for (std::size_t i = 0; i < d.automata.size(); ++i) {
    const Automaton& a = d.automata[i];
    if (same[i] >= 0) {
      // Instances equal to their template's first, up to their name: a run of them said once.
      if (i + 1 < d.automata.size() && same[i + 1] == same[i]) continue;
      std::size_t first = i;
      while (first > 0 && same[first - 1] == same[i]) --first;
      out += "- " + d.automata[first].name + (first == i ? "" : " .. " + a.name) +
             ": the same as " + d.automata[same[i]].name + ", each with its own variables (" +
             d.automata[first].name + "l" + (a.commands.empty() ? "" : ", " + d.automata[first].name + "u") +
             ", ...)\n";
      continue;
    }
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
  if (!d.templates.empty())
    out += QuantifierNote(d, prompts_dir.empty() ? DefaultPromptsDir() : prompts_dir);
  return out;
}

Json WarningsJson(const std::vector<Diagnostic>& warnings) {
  Json out = Json::array();
  for (const auto& w : warnings) {
    Json x = {{"message", ValidUtf8(w.message)}};
    if (!w.pointer.empty()) x["path"] = ValidUtf8(w.pointer);
    out.push_back(std::move(x));
  }
  return out;
}

namespace {

// An answer quoted back in the conversation is cut to this many bytes (head and tail).
constexpr std::size_t kMaxQuotedAnswer = 8000;
// At most this many problems go into one repair request.
constexpr std::size_t kMaxListedProblems = 40;

struct Check {
  std::optional<Json> json;          // the normalised answer, when JSON could be read
  std::optional<Json> plan;          // the same, when nothing blocks it
  std::vector<Diagnostic> errors;    // blocking: syntax, checker, guards of meaning
  std::vector<Diagnostic> warnings;  // doubts asked about in a repair, reported if they stay
  std::vector<Diagnostic> notes;     // normalisations applied
};

// A checker's message quotes the expression it is about (cut to 200 characters).
Diagnostic Quoted(const Diagnostic& d, const Json& plan) {
  Diagnostic out = d;
  out.message = ValidUtf8(out.message);
  if (!d.offset || d.pointer.empty()) return out;
  try {
    Json::json_pointer ptr(d.pointer);
    if (plan.contains(ptr) && plan.at(ptr).is_string())
      out.message += " (in \"" + Cut(plan.at(ptr).get<std::string>(), 200) + "\")";
  } catch (const std::exception&) {
  }
  return out;
}

Check CheckAnswer(const ChatResponse& r, const Domain& d, const std::string& command) {
  Check c;
  for (const auto& n : r.notes) c.notes.push_back({"", std::nullopt, n});
  const bool blank = r.content.find_first_not_of(" \t\r\n") == std::string::npos;
  if (blank) {
    if (!r.refusal.empty())
      c.errors.push_back({"", std::nullopt, "the model refused: \"" + Cut(r.refusal, 200) + "\""});
    else
      c.errors.push_back({"", std::nullopt, "the answer was empty" +
                                                (r.finish_reason.empty() || r.finish_reason == "stop"
                                                     ? std::string()
                                                     : " (finish_reason \"" + Cut(r.finish_reason, 40) + "\")")});
    return c;
  }
  Extraction x = ExtractJson(r.content);
  c.notes.insert(c.notes.end(), x.notes.begin(), x.notes.end());
  if (!x.json) {
    c.errors = x.errors;
    if (!r.refusal.empty())
      c.errors.push_back({"", std::nullopt, "the model refused: \"" + Cut(r.refusal, 200) + "\""});
    return c;
  }
  Json j = NormalizeAnswer(std::move(*x.json), d, c.notes);
  Diagnostics diags;
  auto sp = LoadStatePlan(j, d, diags);
  for (const auto& e : diags.errors()) c.errors.push_back(Quoted(e, j));
  for (const auto& w : diags.warnings()) c.warnings.push_back(Quoted(w, j));
  if (sp) {
    MeaningFindings f = CheckMeaning(j, *sp, d, command);
    c.errors.insert(c.errors.end(), f.blocking.begin(), f.blocking.end());
    c.warnings.insert(c.warnings.end(), f.doubtful.begin(), f.doubtful.end());
  } else {
    for (auto& w : DefaultedStateConstraints(j)) c.warnings.push_back(std::move(w));
  }
  c.json = j;
  if (c.errors.empty()) c.plan = std::move(j);
  return c;
}

std::string ListProblems(const Check& c) {
  std::string out;
  std::size_t listed = 0, total = c.errors.size() + c.warnings.size();
  for (const auto& e : c.errors)
    if (listed++ < kMaxListedProblems) out += Cut(e.ToString(), 400) + "\n";
  for (const auto& w : c.warnings)
    if (listed++ < kMaxListedProblems) out += "warning: " + Cut(w.ToString(), 400) + "\n";
  if (total > kMaxListedProblems)
    out += "(and " + std::to_string(total - kMaxListedProblems) + " more)\n";
  return out;
}

}  // namespace

std::variant<TranslateResult, Error> Translate(const Domain& d, const std::string& command,
                                               LlmClient& llm, const TranslateOptions& o) {
  const std::string dir = o.prompts_dir.empty() ? DefaultPromptsDir() : o.prompts_dir;
  auto load = [&](const std::string& name) { return ReadPromptFile(dir + "/" + name); };
  auto system = load("system.txt"), extract = load("cot_extract.txt"), map = load("cot_map.txt"),
       direct = load("direct.txt"), repair = load("repair.txt"), followup = load("followup.txt");
  if (!system || !extract || !map || !direct || !repair || !followup)
    return Error{ErrorCode::kInternal, "prompt files missing in '" + dir + "'", {}};
  if (command.empty() || command.size() > 8000)
    return Error{ErrorCode::kInvalidInput, "the command must have 1 to 8000 characters",
                 {{"/command", std::nullopt, "empty or too long"}}};
  std::string examples = PromptExamples(d, dir, o.prompting);
  TranslateResult result;
  std::vector<ChatMessage> msgs = o.history;
  if (msgs.empty())
    msgs.push_back({"system", FillPrompt(*system, {{"domain", DescribeDomain(d, dir)}, {"examples", examples}})});
  const Json json_format = ResponseFormatMember(o.response_format, d);
  auto ask = [&](bool want_json) -> std::variant<ChatResponse, Error> {
    ChatRequest req;
    req.messages = msgs;
    if (want_json) req.response_format = json_format;
    ++result.llm_calls;
    auto r = llm.Complete(req);
    if (auto* e = std::get_if<Error>(&r)) return *e;
    if (o.progress) o.progress->tokens += std::get<ChatResponse>(r).tokens;
    // The answer is quoted back once, bounded: a huge answer does not grow every later request.
    msgs.push_back({"assistant", Excerpt(std::get<ChatResponse>(r).content, kMaxQuotedAnswer)});
    return r;
  };

  std::variant<ChatResponse, Error> answer;
  if (o.previous_state_plan) {
    msgs.push_back({"user", FillPrompt(*followup, {{"state_plan", o.previous_state_plan->dump(2)},
                                             {"command", command}})});
    answer = ask(true);
  } else if (o.prompting == Prompting::kCot) {
    msgs.push_back({"user", FillPrompt(*extract, {{"command", command}})});
    auto reasoning = ask(false);
    if (auto* e = std::get_if<Error>(&reasoning)) return *e;
    const ChatResponse& rr = std::get<ChatResponse>(reasoning);
    if (rr.content.find_first_not_of(" \t\r\n") == std::string::npos && !rr.refusal.empty())
      return Error{ErrorCode::kUnprocessable, "the model refused: \"" + Cut(rr.refusal, 200) + "\"", {}};
    result.reasoning = rr.content;
    msgs.push_back({"user", *map});
    answer = ask(true);
  } else {
    msgs.push_back({"user", FillPrompt(*direct, {{"command", command}})});
    answer = ask(true);
  }
  if (auto* e = std::get_if<Error>(&answer)) return *e;
  Check check = CheckAnswer(std::get<ChatResponse>(answer), d, command);
  std::optional<Json> first = check.json;  // the first answer read as JSON
  if (o.progress && first) o.progress->read_json = true;
  while ((!check.errors.empty() || !check.warnings.empty()) && result.repairs < o.max_repairs) {
    ++result.repairs;
    msgs.push_back({"user", FillPrompt(*repair, {{"errors", ListProblems(check)}})});
    answer = ask(true);
    if (auto* e = std::get_if<Error>(&answer)) {
      if (!check.plan) return *e;
      check.notes.push_back({"", std::nullopt, "a repair request failed (" + Cut(e->message, 200) +
                                                   "); the answer before it was kept"});
      break;
    }
    Check next = CheckAnswer(std::get<ChatResponse>(answer), d, command);
    // A repair that drops constraints or goal parts is not taken silently: after a usable answer
    // it is not taken at all; otherwise (compared with the first answer read) it is asked about
    // again and reported if it stays.
    bool goal_flagged = false;  // the repair was asked to change the goal
    for (const auto* list : {&check.errors, &check.warnings})
      for (const auto& p : *list) goal_flagged |= p.pointer.rfind("/end_state", 0) == 0;
    bool blocked = false;
    if (check.plan && next.json)
      for (auto& dropped : Dropped(*check.json, *next.json, goal_flagged)) {
        next.errors.push_back(std::move(dropped));
        blocked = true;
      }
    if (!blocked && first && next.json)
      for (auto& dropped : Dropped(*first, *next.json, goal_flagged))
        next.warnings.push_back(std::move(dropped));
    if (!first && next.json) first = next.json;
    if (o.progress && next.json) o.progress->read_json = true;
    if (check.plan && !next.errors.empty()) {
      std::string why = next.errors.front().ToString();
      check.notes.push_back({"", std::nullopt, "a repaired answer was not taken (" + Cut(why, 300) +
                                                   "); the earlier, usable answer was kept"});
      break;
    }
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
  result.warnings = check.notes;
  result.warnings.insert(result.warnings.end(), check.warnings.begin(), check.warnings.end());
  result.conversation = msgs;
  return result;
}

}  // namespace ctb
