// Fuzz target: reading an LLM's answers and the repair loop (translator/: extract.h,
// normalize_answer.h, guards.h, pipeline.h). The input stands for what a chat-completions
// endpoint answers: the first byte picks the domain (its value modulo 4: 0 and 3 presentation, 1
// search_rescue, 2 assembly) and, by bit 2, chain-of-thought (set) or direct prompting; the rest
// is the answers to successive calls, separated by a line "@@@" (after the last one the endpoint
// fails). Checked: Translate never crashes; a translation is a state plan that loads against the
// domain; an error or warning carries a JSON pointer and valid UTF-8 text; ExtractJson's messages
// are valid UTF-8 on every answer.
#include <cstdint>

#include "translator/extract.h"
#include "translator/llm.h"
#include "translator/pipeline.h"
#include "tests/fuzz/fuzz_util.h"

namespace {

using namespace ctb;

// Answers with the given texts in turn, then fails as an unreachable endpoint.
class ScriptedLlm : public LlmClient {
 public:
  explicit ScriptedLlm(std::vector<std::string> answers) : answers_(std::move(answers)) {}
  std::variant<ChatResponse, Error> Complete(const ChatRequest&) override {
    if (next_ >= answers_.size())
      return Error{ErrorCode::kUpstreamFailed, "the scripted endpoint has no more answers", {}};
    ChatResponse r;
    r.content = answers_[next_++];
    r.finish_reason = "stop";
    return r;
  }
  std::string model() const override { return "fuzz"; }

 private:
  std::vector<std::string> answers_;
  std::size_t next_ = 0;
};

std::vector<std::string> Split(std::string_view text) {
  static const std::string_view kSep = "\n@@@\n";
  std::vector<std::string> out;
  for (;;) {
    std::size_t at = text.find(kSep);
    if (at == std::string_view::npos) break;
    out.emplace_back(text.substr(0, at));
    text.remove_prefix(at + kSep.size());
    if (out.size() == 8) return out;  // more calls than any pipeline makes
  }
  out.emplace_back(text);
  return out;
}

void CheckNotes(const std::vector<Diagnostic>& notes) {
  for (const auto& n : notes) {
    if (!fuzz::WellFormedPointer(n.pointer)) fuzz::Fail("a note's pointer is not a JSON pointer");
    fuzz::CheckUtf8(n.message, "a note is not valid UTF-8");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const Domain domains[] = {
      fuzz::LoadShippedDomain("config/domains/presentation.json"),
      fuzz::LoadShippedDomain("config/domains/search_rescue.json"),
      fuzz::LoadShippedDomain("config/domains/assembly.json"),
  };
  if (size == 0) return 0;
  const int which = data[0] % 4;
  const Domain& dom = domains[which == 3 ? 0 : which];
  const std::vector<std::string> answers = Split(fuzz::Text(data + 1, size - 1));

  for (const auto& a : answers) {
    Extraction x = ExtractJson(a);
    CheckNotes(x.notes);
    CheckNotes(x.errors);
    if (!x.json && x.errors.empty()) fuzz::Fail("ExtractJson read nothing and said nothing");
  }

  TranslateOptions o;
  o.prompting = (data[0] & 4) ? Prompting::kCot : Prompting::kDirect;
  o.max_repairs = 2;
  ScriptedLlm llm(answers);
  auto r = Translate(dom, "The projector should turn on within 60 seconds.", llm, o);
  if (auto* e = std::get_if<Error>(&r)) {
    if (e->message.empty()) fuzz::Fail("an Error without a message");
    fuzz::CheckUtf8(e->message, "an Error's message is not valid UTF-8");
    for (const auto& d : e->details) {
      if (!fuzz::WellFormedPointer(d.pointer)) fuzz::Fail("an Error detail's pointer is not a JSON pointer");
      fuzz::CheckUtf8(d.message, "an Error detail is not valid UTF-8");
    }
    return 0;
  }
  const TranslateResult& t = std::get<TranslateResult>(r);
  CheckNotes(t.warnings);
  (void)WarningsJson(t.warnings).dump();
  Diagnostics diags;
  if (!LoadStatePlan(t.state_plan, dom, diags)) {
    for (const auto& e : diags.errors()) std::fprintf(stderr, "%s\n", e.ToString().c_str());
    fuzz::Fail("Translate returned a state plan that does not load");
  }
  return 0;
}
