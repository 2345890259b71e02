#include <algorithm>
#include <curl/curl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <random>
#include <thread>

#include "translator/llm.h"
#include "translator/text.h"

namespace ctb {

namespace {

using Clock = std::chrono::steady_clock;

void GlobalInit() {
  static std::once_flag once;
  std::call_once(once, [] { curl_global_init(CURL_GLOBAL_DEFAULT); });
}

// The answer body, bounded: past `limit` bytes the transfer stops and `too_large` is set.
struct Sink {
  std::string data;
  std::size_t limit = 0;
  bool too_large = false;
};

size_t WriteBody(char* ptr, size_t size, size_t n, void* user) {
  auto* s = static_cast<Sink*>(user);
  if (s->data.size() + size * n > s->limit) {
    s->too_large = true;
    return 0;  // refuse absurd answers
  }
  s->data.append(ptr, size * n);
  return size * n;
}

size_t ReadHeader(char* ptr, size_t size, size_t n, void* user) {
  std::string line(ptr, size * n);
  auto* retry_after = static_cast<std::string*>(user);
  std::string lower = line;
  for (auto& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower.rfind("retry-after:", 0) == 0) {
    std::string v = line.substr(12);
    while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.erase(0, 1);
    while (!v.empty() && (v.back() == '\r' || v.back() == '\n' || v.back() == ' ')) v.pop_back();
    *retry_after = v;
  }
  return size * n;
}

// Retry-After as seconds or an HTTP date; -1 when absent or unreadable.
long RetryAfterMs(const std::string& v) {
  if (v.empty()) return -1;
  char* end = nullptr;
  long secs = std::strtol(v.c_str(), &end, 10);
  // A day at most: a huge value (or one strtol clamps to LONG_MAX) must not overflow secs * 1000.
  constexpr long kMaxSecs = 86400;
  if (end && *end == '\0' && secs >= 0) return std::min(secs, kMaxSecs) * 1000;
  time_t when = curl_getdate(v.c_str(), nullptr);
  if (when < 0) return -1;
  long diff = static_cast<long>(when - std::time(nullptr));
  return diff > 0 ? std::min(diff, kMaxSecs) * 1000 : 0;
}

class HttpClient : public LlmClient {
 public:
  explicit HttpClient(LlmConfig cfg) : cfg_(std::move(cfg)) { GlobalInit(); }
  std::string model() const override { return cfg_.model; }
  int attempts() const override { return attempts_; }

  std::variant<ChatResponse, Error> Complete(const ChatRequest& req) override {
    const auto deadline = Clock::now() + std::chrono::milliseconds(cfg_.timeout_ms);
    auto r = CompleteOnce(req, deadline);
    // finish_reason "length": the JSON was cut off; once more with twice the output limit.
    if (auto* ok = std::get_if<ChatResponse>(&r); ok && ok->finish_reason == "length") {
      int used = req.max_tokens > 0 ? req.max_tokens : cfg_.max_tokens;
      ChatRequest bigger = req;
      bigger.max_tokens = used > 0 ? std::min(used * 2, 1000000) : 8192;
      r = CompleteOnce(bigger, deadline);
      if (auto* again = std::get_if<ChatResponse>(&r); again && again->finish_reason == "length")
        return Error{ErrorCode::kUpstreamFailed,
                     "LLM answer was cut off (finish_reason \"length\") even with max_tokens " +
                         std::to_string(bigger.max_tokens) + ": raise CTB_LLM_MAX_TOKENS", {}};
    }
    if (auto* e = std::get_if<Error>(&r)) {
      e->message = MaskSecret(ValidUtf8(e->message), cfg_.api_key);
      for (auto& d : e->details) d.message = MaskSecret(ValidUtf8(d.message), cfg_.api_key);
    }
    return r;
  }

 private:
  // One request with its retries, every attempt and wait before `deadline`.
  std::variant<ChatResponse, Error> CompleteOnce(const ChatRequest& in, Clock::time_point deadline) {
    ChatRequest req = in;
    if (req.max_tokens <= 0) req.max_tokens = cfg_.max_tokens;
    const std::string body = ChatBody(cfg_.model, req).dump(-1, ' ', false, Json::error_handler_t::replace);
    const std::string url = Url();
    std::mt19937 rng(std::random_device{}());
    Error last{ErrorCode::kUpstreamFailed, "no attempt made", {}};
    bool failed_once = false;  // `last` holds why an attempt failed
    // The budget is spent; why the attempts before failed, when they did (a refused connection
    // retried until the time ran out on a slow machine is still a refused connection).
    auto timed_out = [&] {
      return Error{ErrorCode::kUpstreamTimeout,
                   "LLM endpoint did not answer within " + std::to_string(cfg_.timeout_ms) +
                       " ms (CTB_LLM_TIMEOUT_MS, retries included)" +
                       (failed_once ? "; the last attempt: " + last.message : std::string()), {}};
    };
    auto remaining_ms = [&] {
      return std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    };
    for (int attempt = 0; attempt <= cfg_.max_retries; ++attempt) {
      long budget = remaining_ms();
      if (budget <= 0) return timed_out();
      ++attempts_;
      Sink answer;
      answer.limit = static_cast<std::size_t>(cfg_.max_answer_bytes);
      std::string retry_after;
      long status = 0;
      CURLcode rc = Post(url, body, answer, retry_after, status, budget);
      long wait_ms = -1;
      if (answer.too_large)
        return Error{ErrorCode::kUpstreamFailed,
                     "the LLM endpoint's answer is larger than the limit of " +
                         std::to_string(cfg_.max_answer_bytes) + " bytes (CTB_LLM_MAX_ANSWER_BYTES); "
                         "not retried", {}};
      if (rc != CURLE_OK) {
        if (rc == CURLE_OPERATION_TIMEDOUT) return timed_out();  // the time budget is spent
        last = {ErrorCode::kUpstreamFailed,
                std::string("cannot reach the LLM endpoint: ") + curl_easy_strerror(rc), {}};
        failed_once = true;
      } else if (status == 200) {
        return ParseAnswer(answer.data);
      } else {
        last = {ErrorCode::kUpstreamFailed, "LLM endpoint answered HTTP " + std::to_string(status) +
                                                UpstreamMessage(answer.data), {}};
        failed_once = true;
        if (status == 401 || status == 403) {
          last.message = "LLM endpoint refused the request (HTTP " + std::to_string(status) +
                         "): check CTB_LLM_API_KEY";
          return last;
        }
        bool retryable = status == 408 || status == 409 || status == 429 || status >= 500;
        if (status == 429 && answer.data.find("insufficient_quota") != std::string::npos) retryable = false;
        if (!retryable) return last;
        wait_ms = RetryAfterMs(retry_after);
        if (wait_ms > cfg_.max_retry_after_ms) return last;  // asked to wait too long
      }
      if (attempt == cfg_.max_retries) break;
      if (wait_ms < 0) {  // exponential backoff with full jitter
        long cap = cfg_.backoff_base_ms << attempt;
        wait_ms = std::uniform_int_distribution<long>(cap / 2, cap)(rng);
      }
      if (wait_ms >= remaining_ms()) {
        last.message += " (no time left for another attempt within CTB_LLM_TIMEOUT_MS)";
        return last;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
    }
    return last;
  }

  std::string Url() const {
    std::string u = cfg_.base_url;
    while (!u.empty() && u.back() == '/') u.pop_back();
    return u + "/chat/completions";
  }

  CURLcode Post(const std::string& url, const std::string& body, Sink& answer,
                std::string& retry_after, long& status, long budget_ms) {
    CURL* curl = curl_easy_init();
    if (!curl) return CURLE_FAILED_INIT;
    curl_slist* headers = nullptr;
    headers = curl_slist_append(headers, "Content-Type: application/json");
    std::string auth;
    if (!cfg_.api_key.empty()) {
      auth = "Authorization: Bearer " + cfg_.api_key;
      headers = curl_slist_append(headers, auth.c_str());
    }
    curl_easy_setopt(curl, CURLOPT_URL, url.c_str());
    curl_easy_setopt(curl, CURLOPT_HTTPHEADER, headers);
    curl_easy_setopt(curl, CURLOPT_POSTFIELDS, body.c_str());
    curl_easy_setopt(curl, CURLOPT_POSTFIELDSIZE, static_cast<long>(body.size()));
    curl_easy_setopt(curl, CURLOPT_NOSIGNAL, 1L);
    curl_easy_setopt(curl, CURLOPT_TIMEOUT_MS, budget_ms);
    curl_easy_setopt(curl, CURLOPT_CONNECTTIMEOUT_MS, std::min(cfg_.connect_timeout_ms, budget_ms));
    curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, WriteBody);
    curl_easy_setopt(curl, CURLOPT_WRITEDATA, &answer);
    curl_easy_setopt(curl, CURLOPT_HEADERFUNCTION, ReadHeader);
    curl_easy_setopt(curl, CURLOPT_HEADERDATA, &retry_after);
    curl_easy_setopt(curl, CURLOPT_FOLLOWLOCATION, 0L);
    curl_easy_setopt(curl, CURLOPT_PROTOCOLS_STR, "http,https");
    CURLcode rc = curl_easy_perform(curl);
    curl_easy_getinfo(curl, CURLINFO_RESPONSE_CODE, &status);
    curl_slist_free_all(headers);
    curl_easy_cleanup(curl);
    return rc;
  }

  static std::string UpstreamMessage(const std::string& answer) {
    Json j = Json::parse(answer, nullptr, false);
    if (j.is_object() && j.contains("error") && j["error"].is_object() &&
        j["error"].contains("message") && j["error"]["message"].is_string()) {
      std::string m = j["error"]["message"].get<std::string>();
      return ": " + Cut(m, 200);
    }
    return "";
  }

  static std::variant<ChatResponse, Error> ParseAnswer(const std::string& answer) {
    Json j = Json::parse(answer, nullptr, false);
    auto bad = [&](const std::string& why) {
      return Error{ErrorCode::kUpstreamFailed, "LLM endpoint sent an unusable answer: " + why +
                                                   " (it began: \"" + Cut(answer, 200) + "\")", {}};
    };
    if (!j.is_object() || !j.contains("choices") || !j["choices"].is_array() || j["choices"].empty())
      return bad("no choices");
    const Json& c = j["choices"][0];
    if (!c.is_object() || !c.contains("message") || !c["message"].is_object())
      return bad("no message");
    const Json& m = c["message"];
    ChatResponse r;
    if (m.contains("content") && m["content"].is_string()) {
      r.content = m["content"].get<std::string>();
    } else if (m.contains("content") && m["content"].is_array()) {  // content parts
      for (const auto& part : m["content"])
        if (part.is_object() && part.contains("text") && part["text"].is_string())
          r.content += part["text"].get<std::string>();
        else if (part.is_string())
          r.content += part.get<std::string>();
      r.notes.push_back("the answer's content was an array of parts; their text was joined");
    }
    if (m.contains("refusal") && m["refusal"].is_string()) r.refusal = m["refusal"].get<std::string>();
    if (j.contains("usage") && j["usage"].is_object() && j["usage"].contains("total_tokens") &&
        j["usage"]["total_tokens"].is_number_integer() && j["usage"]["total_tokens"].get<long>() > 0)
      r.tokens = j["usage"]["total_tokens"].get<long>();
    if (r.content.find_first_not_of(" \t\r\n") == std::string::npos && m.contains("tool_calls") &&
        m["tool_calls"].is_array() && !m["tool_calls"].empty()) {
      const Json& call = m["tool_calls"][0];
      if (call.is_object() && call.contains("function") && call["function"].is_object()) {
        const Json& f = call["function"];
        if (f.contains("arguments") && f["arguments"].is_string()) r.content = f["arguments"].get<std::string>();
        else if (f.contains("arguments") && f["arguments"].is_object()) r.content = f["arguments"].dump();
        r.notes.push_back("the answer came as a tool call" +
                          (f.contains("name") && f["name"].is_string()
                               ? " ('" + Cut(f["name"].get<std::string>(), 60) + "')" : std::string()) +
                          "; its arguments were read");
      }
    }
    if (c.contains("finish_reason") && c["finish_reason"].is_string())
      r.finish_reason = c["finish_reason"].get<std::string>();
    return r;
  }

  LlmConfig cfg_;
  std::atomic<int> attempts_{0};
};

}  // namespace

std::unique_ptr<LlmClient> MakeHttpClient(const LlmConfig& cfg) {
  return std::make_unique<HttpClient>(cfg);
}

}  // namespace ctb
