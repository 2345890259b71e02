#include "translator/report.h"

#include "translator/chat_loop.h"
#include "translator/extract.h"
#include "translator/pipeline.h"
#include "translator/prompt_files.h"
#include "translator/text.h"

namespace ctb {

namespace {

constexpr std::size_t kMaxPlanLines = 400;

std::string Number(double v) {
  if (v == static_cast<double>(static_cast<long>(v))) return std::to_string(static_cast<long>(v));
  return Json(v).dump();
}

struct Checked {
  Json fields = Json::object();
  std::string restatement;
  std::vector<Diagnostic> errors;
  std::vector<Diagnostic> warnings;
};

// The answer's object, its fields kept (only observed and blocked), then the caller's check.
Checked CheckAnswer(const ChatResponse& r, const ReportCheck& check) {
  Checked c;
  for (const auto& n : r.notes) c.warnings.push_back({"", std::nullopt, n});
  Extraction x = ExtractJson(r.content);
  c.warnings.insert(c.warnings.end(), x.notes.begin(), x.notes.end());
  if (!x.json) {
    c.errors = x.errors.empty() ? std::vector<Diagnostic>{{"", std::nullopt, "the answer held no JSON"}}
                                : x.errors;
    return c;
  }
  if (!x.json->is_object()) {
    c.errors.push_back({"", std::nullopt, std::string("expected a JSON object, got ") + JsonTypeName(*x.json)});
    return c;
  }
  for (const auto& [k, v] : x.json->items()) {
    if (k == "observed" || k == "blocked") {
      if (!v.is_null()) c.fields[k] = v;
    } else if (k == "restatement" && v.is_string()) {
      c.restatement = ValidUtf8(Cut(v.get<std::string>(), 1000));
    } else {
      c.errors.push_back({"/" + PointerToken(k), std::nullopt,
                          "unknown field: answer with observed, blocked and restatement only"});
    }
  }
  if (!c.fields.contains("observed") && !c.fields.contains("blocked"))
    c.errors.push_back({"", std::nullopt, "the answer has neither \"observed\" nor \"blocked\""});
  if (c.errors.empty()) c.errors = check(c.fields);
  for (auto& e : c.errors) e.message = ValidUtf8(e.message);
  return c;
}

}  // namespace

std::string PlanLines(const Json& trajectory, double now) {
  std::string out;
  if (!trajectory.is_object() || !trajectory.contains("transitions") || !trajectory["transitions"].is_array())
    return "(no plan)\n";
  std::size_t n = 0;
  for (const auto& t : trajectory["transitions"]) {
    if (++n > kMaxPlanLines) {
      out += "(and more)\n";
      break;
    }
    if (!t.is_object() || !t.contains("time") || !t["time"].is_number()) continue;
    const double time = t["time"].get<double>();
    out += "t=" + Number(time) + " s  " + ValidUtf8(t.value("automaton", "?")) + ": " +
           ValidUtf8(t.value("from", "?")) + " -> " + ValidUtf8(t.value("to", "?"));
    if (t.contains("command") && t["command"].is_string())
      out += " (command " + ValidUtf8(t["command"].get<std::string>()) + ")";
    out += time < now ? "  [done]\n" : "\n";
  }
  return out;
}

std::variant<ReportResult, Error> ReadReport(const Domain& d, const Json& trajectory, double now,
                                             const std::string& report, LlmClient& llm,
                                             const ReportCheck& check, const ReportOptions& o) {
  if (report.find_first_not_of(" \t\r\n") == std::string::npos || report.size() > 2000)
    return Error{ErrorCode::kInvalidInput, "the report must have 1 to 2000 characters",
                 {{"/command", std::nullopt, "empty or too long"}}};
  const std::string dir = o.prompts_dir.empty() ? DefaultPromptsDir() : o.prompts_dir;
  auto system = ReadPromptFile(dir + "/report.txt"), user = ReadPromptFile(dir + "/report_user.txt"),
       repair = ReadPromptFile(dir + "/report_repair.txt");
  if (!system || !user || !repair)
    return Error{ErrorCode::kInternal, "report prompt files missing in '" + dir + "'", {}};
  ReportResult result;
  ChatLoop chat(llm, o.json_mode,
                {{"system", *system},
                 {"user", FillPrompt(*user, {{"domain", DescribeDomain(d, dir)},
                                             {"plan", PlanLines(trajectory, now)},
                                             {"now", Number(now)},
                                             {"report", ValidUtf8(report)}})}});
  auto answer = chat.Ask();
  if (auto* e = std::get_if<Error>(&answer)) return *e;
  Checked c = CheckAnswer(std::get<ChatResponse>(answer), check);
  while (!c.errors.empty() && chat.repairs() < o.max_repairs) {
    answer = chat.Repair(FillPrompt(*repair, {{"errors", ListProblems(c.errors)}}));
    if (auto* e = std::get_if<Error>(&answer)) return *e;
    c = CheckAnswer(std::get<ChatResponse>(answer), check);
  }
  result.llm_calls = chat.calls();
  result.repairs = chat.repairs();
  if (!c.errors.empty())
    return Error{ErrorCode::kUnprocessable,
                 "the LLM's reading of the report is still invalid after " +
                     std::to_string(result.repairs) + " repair request(s)",
                 c.errors};
  result.fields = std::move(c.fields);
  result.restatement = std::move(c.restatement);
  result.warnings = std::move(c.warnings);
  return result;
}

}  // namespace ctb
