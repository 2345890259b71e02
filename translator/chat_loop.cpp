#include "translator/chat_loop.h"

#include "translator/text.h"

namespace ctb {

namespace {
constexpr std::size_t kMaxQuotedAnswer = 12000;
}

std::variant<ChatResponse, Error> ChatLoop::Ask() {
  ChatRequest req;
  req.messages = msgs_;
  req.json_mode = json_mode_;
  ++calls_;
  auto r = llm_.Complete(req);
  if (auto* e = std::get_if<Error>(&r)) return *e;
  msgs_.push_back({"assistant", Excerpt(std::get<ChatResponse>(r).content, kMaxQuotedAnswer)});
  return r;
}

std::variant<ChatResponse, Error> ChatLoop::Repair(const std::string& request) {
  ++repairs_;
  msgs_.push_back({"user", request});
  return Ask();
}

}  // namespace ctb
