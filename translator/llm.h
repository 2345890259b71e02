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

struct ChatRequest {
  std::vector<ChatMessage> messages;
  bool json_mode = false;  // ask for JSON output (response_format); off by default
};

struct ChatResponse {
  std::string content;
  std::string finish_reason;
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
  long timeout_ms = 60000;        // CTB_LLM_TIMEOUT_MS: total per request
  long connect_timeout_ms = 5000;
  int max_retries = 3;
  long max_retry_after_ms = 30000;
  long backoff_base_ms = 250;
  bool json_mode = false;         // CTB_LLM_JSON_MODE=1
  int max_repairs = 2;            // CTB_LLM_MAX_REPAIRS
  std::string record_dir;         // CTB_LLM_RECORD
  std::string replay_dir;         // CTB_LLM_REPLAY

  static std::variant<LlmConfig, Error> FromEnv();
  // The key shown as "sk-...abcd" (or "(none)") for logs.
  std::string MaskedKey() const;
};

// The HTTP client (libcurl). Retries 408/409/429 (not insufficient_quota) and 5xx and
// connection errors with exponential backoff and jitter, honouring Retry-After up to a cap;
// never retries 401/403; finish_reason "length" is an error.
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
