// One conversation with the LLM that asks, checks and asks for repairs (drafts, reports): each
// answer is kept in the conversation (a bounded excerpt) so that a repair request follows it.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "planner/model/error.h"
#include "translator/llm.h"

namespace ctb {

class ChatLoop {
 public:
  ChatLoop(LlmClient& llm, bool json_mode, std::vector<ChatMessage> first)
      : llm_(llm), json_mode_(json_mode), msgs_(std::move(first)) {}

  // Sends the conversation; the answer, or the client's error.
  std::variant<ChatResponse, Error> Ask();
  // Adds a repair request (a user message) and asks again.
  std::variant<ChatResponse, Error> Repair(const std::string& request);

  int calls() const { return calls_; }
  int repairs() const { return repairs_; }

 private:
  LlmClient& llm_;
  bool json_mode_;
  std::vector<ChatMessage> msgs_;
  int calls_ = 0, repairs_ = 0;
};

}  // namespace ctb
