// The LLM side: an OpenAI-compatible chat-completions client behind a small interface, and its
// record/replay decorators. Tests substitute the interface; the real client speaks HTTP(S) with
// libcurl.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "planner/model/error.h"
#include "planner/model/json_io.h"

namespace ctb {

struct ChatMessage {
  std::string role;  // system, user, assistant
  std::string content;
};

// How the endpoint is asked to shape its answer (CTB_LLM_RESPONSE_FORMAT).
enum class ResponseFormat { kNone, kJsonObject, kJsonSchema };
std::optional<ResponseFormat> ParseResponseFormat(const std::string& s);
const char* ResponseFormatName(ResponseFormat f);

struct ChatRequest {
  std::vector<ChatMessage> messages;
  bool json_mode = false;  // response_format json_object (when response_format is null)
  Json response_format;    // sent as is when not null (e.g. a json_schema member)
  int max_tokens = 0;      // 0: the client's CTB_LLM_MAX_TOKENS, or the server's default
};

struct ChatResponse {
  std::string content;        // the text, or the arguments of the first tool call
  std::string finish_reason;
  std::string refusal;        // the model's refusal (OpenAI's message.refusal), if any
  std::vector<std::string> notes;  // how the content was read (content parts, tool call)
  long tokens = 0;            // usage.total_tokens when the endpoint (or the recording) says it
};

// The request body sent to /chat/completions (also the record/replay key, canonical JSON).
Json ChatBody(const std::string& model, const ChatRequest& req);

class LlmClient {
 public:
  virtual ~LlmClient() = default;
  // One completion. Errors: kUpstreamFailed (refused, bad answer, length cut-off),
  // kUpstreamTimeout, kUnavailable (not configured, replay miss). Thread-safe.
  virtual std::variant<ChatResponse, Error> Complete(const ChatRequest& req) = 0;
  virtual std::string model() const = 0;
  // Calls made (attempts on the wire, retries included), for metrics and tests.
  virtual int attempts() const { return 0; }
};

// Configuration, filled from the environment (CTB_LLM_*); see docs/translator.md.
struct LlmConfig {
  std::string base_url;   // CTB_LLM_BASE_URL, e.g. https://api.openai.com/v1
  std::string api_key;    // CTB_LLM_API_KEY (sent as a bearer token, never logged)
  std::string model = "gpt-4o";  // CTB_LLM_MODEL
  long timeout_ms = 60000;        // CTB_LLM_TIMEOUT_MS: one deadline per request, retries included
  long connect_timeout_ms = 5000;
  int max_retries = 3;
  long max_retry_after_ms = 30000;
  long backoff_base_ms = 250;
  ResponseFormat response_format = ResponseFormat::kNone;  // CTB_LLM_RESPONSE_FORMAT
                                                          // (CTB_LLM_JSON_MODE=1: json_object)
  int max_tokens = 0;             // CTB_LLM_MAX_TOKENS (0: not sent)
  long max_answer_bytes = 16L * 1024 * 1024;  // CTB_LLM_MAX_ANSWER_BYTES
  int max_repairs = 2;            // CTB_LLM_MAX_REPAIRS
  std::string record_dir;         // CTB_LLM_RECORD
  std::string replay_dir;         // CTB_LLM_REPLAY

  static std::variant<LlmConfig, Error> FromEnv();
  // The key shown as "sk-...abcd" (or "(none)") for logs.
  std::string MaskedKey() const;
};

// The HTTP client (libcurl). Retries 408/409/429 (not insufficient_quota) and 5xx and
// connection errors with exponential backoff and jitter, honouring Retry-After up to a cap;
// never retries 401/403. One deadline (timeout_ms) covers every attempt and wait of a call. An
// answer over max_answer_bytes is an error of its own, not retried. finish_reason "length" is
// retried once with twice the output limit, then an error. Content given as an array of parts
// is joined; with no content, the first tool call's arguments are read. Every error message is
// valid UTF-8 and has the API key masked.
std::unique_ptr<LlmClient> MakeHttpClient(const LlmConfig& cfg);

// Wraps a client and stores each exchange under dir as <key>.json: the model, the request body
// and the answer; never headers or the key.
std::unique_ptr<LlmClient> MakeRecordingClient(std::unique_ptr<LlmClient> inner, const std::string& dir);

// Answers from recordings in dir; a request with no recording is a kUnavailable error.
std::variant<std::unique_ptr<LlmClient>, Error> MakeReplayClient(const std::string& dir,
                                                                 const std::string& model);

// The client the configuration asks for: replay, else HTTP (wrapped for recording when asked).
// kUnavailable when neither an endpoint nor a replay directory is configured.
std::variant<std::unique_ptr<LlmClient>, Error> MakeClient(const LlmConfig& cfg);

// The record/replay key of a request: FNV-1a 64 of "model\n" + canonical body, in hex.
std::string RequestKey(const std::string& model, const Json& body);

}  // namespace ctb
