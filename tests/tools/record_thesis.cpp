// Writes tests/recordings/thesis: runs the real translation pipeline against the thesis' LLM
// answers (a scripted client) through the recording client. Usage: record_thesis SCRIPT OUTDIR
#include <fstream>
#include <iostream>
#include <sstream>

#include "planner/model/catalog.h"
#include "translator/pipeline.h"

namespace {

class Scripted : public ctb::LlmClient {
 public:
  explicit Scripted(std::vector<std::string> answers) : answers_(std::move(answers)) {}
  std::string model() const override { return "gpt-4o"; }
  std::variant<ctb::ChatResponse, ctb::Error> Complete(const ctb::ChatRequest&) override {
    if (next_ >= answers_.size()) return ctb::Error{ctb::ErrorCode::kUnavailable, "script exhausted", {}};
    ctb::ChatResponse r;
    r.content = answers_[next_++];
    r.finish_reason = "stop";
    return r;
  }

 private:
  std::vector<std::string> answers_;
  std::size_t next_ = 0;
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: record_thesis SCRIPT OUTDIR\n";
    return 2;
  }
  const std::string src = CTB_SOURCE_DIR;
  auto script = ctb::Json::parse(ReadFile(argv[1]));
  int failures = 0;
  for (const auto& c : script) {
    std::vector<std::string> answers;
    for (const auto& a : c["answers"]) {
      std::string text = a.contains("text") ? a["text"].get<std::string>()
                                            : ReadFile(src + "/config/examples/" + a["file"].get<std::string>());
      if (a.contains("replace")) {
        std::string from = a["replace"][0], to = a["replace"][1];
        text.replace(text.find(from), from.size(), to);
      }
      answers.push_back(text);
    }
    ctb::Diagnostics d;
    auto domain = ctb::LoadDomainByNameOrPath(c["domain"], src + "/config", d);
    auto client = ctb::MakeRecordingClient(std::make_unique<Scripted>(answers), argv[2]);
    ctb::TranslateOptions o;
    o.prompting = *ctb::ParsePrompting(c["prompting"]);
    o.prompts_dir = src + "/prompts";
    auto r = ctb::Translate(*domain, c["command"], *client, o);
    if (auto* e = std::get_if<ctb::Error>(&r)) {
      std::cerr << c["name"].get<std::string>() << ": " << e->ToString() << "\n";
      ++failures;
    } else {
      std::cout << c["name"].get<std::string>() << ": recorded " << std::get<ctb::TranslateResult>(r).llm_calls
                << " exchange(s)\n";
    }
  }
  return failures ? 1 : 0;
}
