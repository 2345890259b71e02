#include <algorithm>
#include <curl/curl.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <random>
#include <thread>

#include "translator/llm.h"

namespace ctb {

namespace {

using Clock = std::chrono::steady_clock;

void GlobalInit() {
  static std::once_flag once;
  std::call_once(once, [] { curl_global_init(CURL_GLOBAL_DEFAULT); });
}

size_t WriteBody(char* ptr, size_t size, size_t n, void* user) {
  auto* s = static_cast<std::string*>(user);
  if (s->size() + size * n > 16 * 1024 * 1024) return 0;  // refuse absurd answers
  s->append(ptr, size * n);
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
    const std::string body = ChatBody(cfg_.model, req).dump();
    const std::string url = Url();
    std::mt19937 rng(std::random_device{}());
    Error last{ErrorCode::kUpstreamFailed, "no attempt made", {}};
    for (int attempt = 0; attempt <= cfg_.max_retries; ++attempt) {
      ++attempts_;
      std::string answer, retry_after;
      long status = 0;
      CURLcode rc = Post(url, body, answer, retry_after, status);
      long wait_ms = -1;
      if (rc != CURLE_OK) {
        if (rc == CURLE_OPERATION_TIMEDOUT)
          last = {ErrorCode::kUpstreamTimeout,
                  "LLM endpoint did not answer within " + std::to_string(cfg_.timeout_ms) + " ms", {}};
        else
          last = {ErrorCode::kUpstreamFailed,
                  std::string("cannot reach the LLM endpoint: ") + curl_easy_strerror(rc), {}};
        if (rc == CURLE_OPERATION_TIMEDOUT) return last;  // the time budget is spent
      } else if (status == 200) {
        return ParseAnswer(answer);
      } else {
        last = {ErrorCode::kUpstreamFailed, "LLM endpoint answered HTTP " + std::to_string(status) +
                                                UpstreamMessage(answer), {}};
        if (status == 401 || status == 403) {
          last.message = "LLM endpoint refused the request (HTTP " + std::to_string(status) +
                         "): check CTB_LLM_API_KEY";
          return last;
        }
        bool retryable = status == 408 || status == 409 || status == 429 || status >= 500;
        if (status == 429 && answer.find("insufficient_quota") != std::string::npos) retryable = false;
        if (!retryable) return last;
        wait_ms = RetryAfterMs(retry_after);
        if (wait_ms > cfg_.max_retry_after_ms) return last;  // asked to wait too long
      }
      if (attempt == cfg_.max_retries) break;
      if (wait_ms < 0) {  // exponential backoff with full jitter
        long cap = cfg_.backoff_base_ms << attempt;
        wait_ms = std::uniform_int_distribution<long>(cap / 2, cap)(rng);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
    }
    return last;
  }

 private:
  std::string Url() const {
    std::string u = cfg_.base_url;
    while (!u.empty() && u.back() == '/') u.pop_back();
    return u + "/chat/completions";
  }

  CURLcode Post(const std::string& url, const std::string& body, std::string& answer,
                std::string& retry_after, long& status) {
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
    curl_easy_setopt(curl, CURLOPT_TIMEOUT_MS, cfg_.timeout_ms);
    curl_easy_setopt(curl, CURLOPT_CONNECTTIMEOUT_MS, cfg_.connect_timeout_ms);
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
      if (m.size() > 200) m = m.substr(0, 200) + "...";
      return ": " + m;
    }
    return "";
  }

  static std::variant<ChatResponse, Error> ParseAnswer(const std::string& answer) {
    Json j = Json::parse(answer, nullptr, false);
    auto bad = [](const std::string& why) {
      return Error{ErrorCode::kUpstreamFailed, "LLM endpoint sent an unusable answer: " + why, {}};
    };
    if (!j.is_object() || !j.contains("choices") || !j["choices"].is_array() || j["choices"].empty())
      return bad("no choices");
    const Json& c = j["choices"][0];
    if (!c.is_object() || !c.contains("message") || !c["message"].is_object())
      return bad("no message");
    const Json& m = c["message"];
    ChatResponse r;
    if (m.contains("content") && m["content"].is_string()) r.content = m["content"].get<std::string>();
    if (c.contains("finish_reason") && c["finish_reason"].is_string())
      r.finish_reason = c["finish_reason"].get<std::string>();
    if (r.finish_reason == "length")
      return Error{ErrorCode::kUpstreamFailed,
                   "LLM answer was cut off (finish_reason \"length\"): raise the model's output "
                   "limit", {}};
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
