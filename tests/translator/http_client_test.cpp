// Transport as documented (docs/translator.md): the real libcurl client against the loopback
// mock endpoint. One deadline per request, the answer size limit, the output limit and the
// retry after finish_reason "length", the key masked, answers in other shapes.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>

#include "mock_llm.h"
#include "translator/llm.h"
#include "translator/text.h"

namespace ctb {
// A namespace of its own: the test executable's unity build puts files with same-named
// helpers side by side.
namespace http_client_test {
namespace {

using testing::MockLlmServer;
using testing::MockReply;

const char* kKey = "sk-test-secret-key-1234";

LlmConfig Config(const MockLlmServer& m) {
  LlmConfig c;
  c.base_url = m.BaseUrl();
  c.api_key = kKey;
  c.model = "mock-model";
  c.timeout_ms = 3000;
  c.backoff_base_ms = 50;
  return c;
}

ChatRequest Hi() { return ChatRequest{{{"user", "hi"}}}; }

long MsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() -
                                                               t0)
      .count();
}

MockReply Raw(const Json& message, const std::string& finish = "stop") {
  Json j = {{"choices", {{{"index", 0}, {"message", message}, {"finish_reason", finish}}}}};
  return {200, j.dump(), {}, 0};
}

TEST(HttpClientTransport, OneDeadlineCoversEveryRetry) {
  MockLlmServer m;
  for (int i = 0; i < 4; ++i) m.Then(MockReply::Status(503, "busy", 400));
  LlmConfig c = Config(m);
  c.timeout_ms = 1000;
  auto client = MakeHttpClient(c);
  auto t0 = std::chrono::steady_clock::now();
  auto r = client->Complete(Hi());
  long ms = MsSince(t0);
  ASSERT_TRUE(std::holds_alternative<Error>(r));
  // Per attempt, 4 attempts of 400 ms and the waits would take about 2 s.
  EXPECT_LT(ms, 1400);
  EXPECT_LE(client->attempts(), 3);
  const Error& e = std::get<Error>(r);
  EXPECT_TRUE(e.code == ErrorCode::kUpstreamTimeout ||
              e.message.find("no time left") != std::string::npos)
      << e.message;
}

TEST(HttpClientTransport, AnAnswerOverTheSizeLimitIsReportedAsSuchAndNotRetried) {
  MockLlmServer m;
  for (int i = 0; i < 4; ++i) m.Then(MockReply::Chat(std::string(20000, 'x')));
  LlmConfig c = Config(m);
  c.max_answer_bytes = 4096;
  auto client = MakeHttpClient(c);
  auto r = client->Complete(Hi());
  ASSERT_TRUE(std::holds_alternative<Error>(r));
  const Error& e = std::get<Error>(r);
  EXPECT_EQ(e.code, ErrorCode::kUpstreamFailed);
  EXPECT_NE(e.message.find("larger than the limit of 4096 bytes"), std::string::npos) << e.message;
  EXPECT_EQ(e.message.find("cannot reach"), std::string::npos);
  EXPECT_EQ(client->attempts(), 1);
  EXPECT_EQ(m.Requests().size(), 1u);
}

TEST(HttpClientTransport, MaxTokensIsSentWhenSetAndNotOtherwise) {
  MockLlmServer m;
  m.Then(MockReply::Chat("a"));
  m.Then(MockReply::Chat("b"));
  LlmConfig c = Config(m);
  MakeHttpClient(c)->Complete(Hi());
  c.max_tokens = 1234;
  MakeHttpClient(c)->Complete(Hi());
  auto reqs = m.Requests();
  ASSERT_EQ(reqs.size(), 2u);
  EXPECT_FALSE(reqs[0].body.contains("max_tokens"));
  EXPECT_EQ(reqs[1].body["max_tokens"], 1234);
}

TEST(HttpClientTransport, LengthIsRetriedOnceWithTwiceTheLimit) {
  MockLlmServer m;
  m.Then(MockReply::Chat("{\"initial_state\": {\"comp", "length"));
  m.Then(MockReply::Chat("{}", "stop"));
  LlmConfig c = Config(m);
  c.max_tokens = 1000;
  auto r = MakeHttpClient(c)->Complete(Hi());
  ASSERT_TRUE(std::holds_alternative<ChatResponse>(r)) << std::get<Error>(r).message;
  EXPECT_EQ(std::get<ChatResponse>(r).content, "{}");
  auto reqs = m.Requests();
  ASSERT_EQ(reqs.size(), 2u);
  EXPECT_EQ(reqs[0].body["max_tokens"], 1000);
  EXPECT_EQ(reqs[1].body["max_tokens"], 2000);
}

TEST(HttpClientTransport, LengthTwiceIsAnErrorThatNamesTheSetting) {
  MockLlmServer m;
  for (int i = 0; i < 3; ++i) m.Then(MockReply::Chat("{\"initial_state\"", "length"));
  auto r = MakeHttpClient(Config(m))->Complete(Hi());
  ASSERT_TRUE(std::holds_alternative<Error>(r));
  EXPECT_NE(std::get<Error>(r).message.find("cut off"), std::string::npos);
  EXPECT_NE(std::get<Error>(r).message.find("CTB_LLM_MAX_TOKENS"), std::string::npos);
  auto reqs = m.Requests();
  ASSERT_EQ(reqs.size(), 2u);
  EXPECT_FALSE(reqs[0].body.contains("max_tokens"));
  EXPECT_EQ(reqs[1].body["max_tokens"], 8192);
}

TEST(HttpClientTransport, TheKeyIsMaskedInUpstreamMessages) {
  MockLlmServer m;
  m.Then(MockReply::Status(400, std::string("Incorrect API key provided: ") + kKey + "."));
  auto r = MakeHttpClient(Config(m))->Complete(Hi());
  ASSERT_TRUE(std::holds_alternative<Error>(r));
  const std::string& msg = std::get<Error>(r).message;
  EXPECT_EQ(msg.find(kKey), std::string::npos) << msg;
  EXPECT_NE(msg.find("Incorrect API key provided: sk-...1234"), std::string::npos) << msg;
}

TEST(HttpClientTransport, InvalidUtf8FromUpstreamBecomesValidText) {
  MockLlmServer m;
  m.Then({400, "{\"error\": {\"message\": \"bad \xC2 byte\"}}", {}, 0});
  auto r = MakeHttpClient(Config(m))->Complete(Hi());
  ASSERT_TRUE(std::holds_alternative<Error>(r));
  const std::string& msg = std::get<Error>(r).message;
  EXPECT_EQ(ValidUtf8(msg), msg);
}

TEST(HttpClientTransport, AnUnusableAnswerIsQuoted) {
  MockLlmServer m;
  m.Then({200, "<html>upstream proxy error</html>", {}, 0});
  auto r = MakeHttpClient(Config(m))->Complete(Hi());
  ASSERT_TRUE(std::holds_alternative<Error>(r));
  EXPECT_NE(std::get<Error>(r).message.find("it began: \"<html>upstream proxy error"),
            std::string::npos);
}

TEST(HttpClientAnswer, ContentPartsToolCallsAndRefusals) {
  MockLlmServer m;
  m.Then(Raw({{"role", "assistant"},
              {"content",
               {{{"type", "text"}, {"text", "{\"a\":"}}, {{"type", "text"}, {"text", " 1}"}}}}}));
  m.Then(Raw(
      {{"role", "assistant"},
       {"content", nullptr},
       {"tool_calls",
        {{{"type", "function"}, {"function", {{"name", "plan"}, {"arguments", "{\"b\": 2}"}}}}}}}));
  m.Then(
      Raw({{"role", "assistant"}, {"content", nullptr}, {"refusal", "I cannot help with that."}}));
  auto client = MakeHttpClient(Config(m));
  auto parts = std::get<ChatResponse>(client->Complete(Hi()));
  EXPECT_EQ(parts.content, "{\"a\": 1}");
  ASSERT_EQ(parts.notes.size(), 1u);
  auto tool = std::get<ChatResponse>(client->Complete(Hi()));
  EXPECT_EQ(tool.content, "{\"b\": 2}");
  ASSERT_EQ(tool.notes.size(), 1u);
  EXPECT_NE(tool.notes[0].find("tool call ('plan')"), std::string::npos);
  auto refusal = std::get<ChatResponse>(client->Complete(Hi()));
  EXPECT_EQ(refusal.content, "");
  EXPECT_EQ(refusal.refusal, "I cannot help with that.");
}

TEST(LlmConfig, ResponseFormatSettingAndItsAlias) {
  auto with = [](const char* rf, const char* json_mode) {
    if (rf)
      setenv("CTB_LLM_RESPONSE_FORMAT", rf, 1);
    else
      unsetenv("CTB_LLM_RESPONSE_FORMAT");
    if (json_mode)
      setenv("CTB_LLM_JSON_MODE", json_mode, 1);
    else
      unsetenv("CTB_LLM_JSON_MODE");
    auto c = LlmConfig::FromEnv();
    unsetenv("CTB_LLM_RESPONSE_FORMAT");
    unsetenv("CTB_LLM_JSON_MODE");
    return c;
  };
  EXPECT_EQ(std::get<LlmConfig>(with(nullptr, nullptr)).response_format, ResponseFormat::kNone);
  EXPECT_EQ(std::get<LlmConfig>(with("json_schema", nullptr)).response_format,
            ResponseFormat::kJsonSchema);
  EXPECT_EQ(std::get<LlmConfig>(with("none", "1")).response_format, ResponseFormat::kNone);
  EXPECT_EQ(std::get<LlmConfig>(with(nullptr, "1")).response_format, ResponseFormat::kJsonObject);
  auto bad = with("yaml", nullptr);
  ASSERT_TRUE(std::holds_alternative<Error>(bad));
  EXPECT_EQ(std::get<Error>(bad).details[0].pointer, "$CTB_LLM_RESPONSE_FORMAT");
}

TEST(LlmConfig, MaxTokensFromTheEnvironment) {
  setenv("CTB_LLM_MAX_TOKENS", "4096", 1);
  auto c = LlmConfig::FromEnv();
  setenv("CTB_LLM_MAX_TOKENS", "lots", 1);
  auto bad = LlmConfig::FromEnv();
  unsetenv("CTB_LLM_MAX_TOKENS");
  EXPECT_EQ(std::get<LlmConfig>(c).max_tokens, 4096);
  EXPECT_TRUE(std::holds_alternative<Error>(bad));
}

}  // namespace
}  // namespace http_client_test
}  // namespace ctb
