#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "translator/llm.h"
#include "translator/text.h"

namespace ctb {

std::optional<ResponseFormat> ParseResponseFormat(const std::string& s) {
  if (s == "none") return ResponseFormat::kNone;
  if (s == "json_object") return ResponseFormat::kJsonObject;
  if (s == "json_schema") return ResponseFormat::kJsonSchema;
  return std::nullopt;
}

const char* ResponseFormatName(ResponseFormat f) {
  switch (f) {
    case ResponseFormat::kNone: return "none";
    case ResponseFormat::kJsonObject: return "json_object";
    case ResponseFormat::kJsonSchema: return "json_schema";
  }
  return "none";
}

Json ChatBody(const std::string& model, const ChatRequest& req) {
  Json messages = Json::array();
  for (const auto& m : req.messages)
    messages.push_back({{"role", m.role}, {"content", ValidUtf8(m.content)}});
  Json body = {{"model", model}, {"messages", messages}, {"temperature", 0}};
  if (!req.response_format.is_null()) body["response_format"] = req.response_format;
  else if (req.json_mode) body["response_format"] = {{"type", "json_object"}};
  if (req.max_tokens > 0) body["max_tokens"] = req.max_tokens;
  return body;
}

std::string RequestKey(const std::string& model, const Json& body) {
  std::string text = model + "\n" + body.dump(-1, ' ', false, Json::error_handler_t::replace);
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

namespace {

std::string Env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

class RecordingClient : public LlmClient {
 public:
  RecordingClient(std::unique_ptr<LlmClient> inner, std::string dir)
      : inner_(std::move(inner)), dir_(std::move(dir)) {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
  }
  std::string model() const override { return inner_->model(); }
  int attempts() const override { return inner_->attempts(); }
  std::variant<ChatResponse, Error> Complete(const ChatRequest& req) override {
    auto r = inner_->Complete(req);
    if (auto* ok = std::get_if<ChatResponse>(&r)) {
      Json body = ChatBody(model(), req);
      Json rec = {{"model", model()},
                  {"request", body},
                  {"response", {{"content", ok->content}, {"finish_reason", ok->finish_reason}}}};
      if (ok->tokens > 0) rec["response"]["tokens"] = ok->tokens;
      std::lock_guard<std::mutex> lock(mu_);
      std::ofstream(dir_ + "/" + RequestKey(model(), body) + ".json")
          << rec.dump(1, ' ', false, Json::error_handler_t::replace) << "\n";
    }
    return r;
  }

 private:
  std::unique_ptr<LlmClient> inner_;
  std::string dir_;
  std::mutex mu_;
};

class ReplayClient : public LlmClient {
 public:
  ReplayClient(std::map<std::string, ChatResponse> answers, std::string model, std::string dir)
      : answers_(std::move(answers)), model_(std::move(model)), dir_(std::move(dir)) {}
  std::string model() const override { return model_; }
  std::variant<ChatResponse, Error> Complete(const ChatRequest& req) override {
    std::string key = RequestKey(model_, ChatBody(model_, req));
    auto it = answers_.find(key);
    if (it == answers_.end())
      return Error{ErrorCode::kUnavailable,
                   "no recorded LLM answer for this request (model '" + model_ + "', key " + key +
                       ") in " + dir_ + "; configure an endpoint (CTB_LLM_BASE_URL) or record "
                       "one with CTB_LLM_RECORD", {}};
    return it->second;
  }

 private:
  std::map<std::string, ChatResponse> answers_;
  std::string model_;
  std::string dir_;
};

}  // namespace

std::variant<LlmConfig, Error> LlmConfig::FromEnv() {
  LlmConfig c;
  Diagnostics d;
  c.base_url = Env("CTB_LLM_BASE_URL");
  c.api_key = Env("CTB_LLM_API_KEY");
  if (auto m = Env("CTB_LLM_MODEL"); !m.empty()) c.model = m;
  c.record_dir = Env("CTB_LLM_RECORD");
  c.replay_dir = Env("CTB_LLM_REPLAY");
  if (auto f = Env("CTB_LLM_RESPONSE_FORMAT"); !f.empty()) {
    if (auto rf = ParseResponseFormat(f)) c.response_format = *rf;
    else d.Error("$CTB_LLM_RESPONSE_FORMAT", "must be json_schema, json_object or none");
  } else if (Env("CTB_LLM_JSON_MODE") == "1") {
    c.response_format = ResponseFormat::kJsonObject;  // the older setting, kept as an alias
  }
  auto number = [&](const char* name, long lo, long hi, auto& out) {
    std::string v = Env(name);
    if (v.empty()) return;
    char* end = nullptr;
    long n = std::strtol(v.c_str(), &end, 10);
    if (!end || *end != '\0' || n < lo || n > hi)
      d.Error(std::string("$") + name, "must be an integer between " + std::to_string(lo) + " and " +
                                           std::to_string(hi));
    else
      out = static_cast<std::remove_reference_t<decltype(out)>>(n);
  };
  number("CTB_LLM_TIMEOUT_MS", 100, 600000, c.timeout_ms);
  number("CTB_LLM_MAX_REPAIRS", 0, 10, c.max_repairs);
  number("CTB_LLM_MAX_TOKENS", 1, 1000000, c.max_tokens);
  number("CTB_LLM_MAX_ANSWER_BYTES", 1024, 256L * 1024 * 1024, c.max_answer_bytes);
  if (!c.base_url.empty() && c.base_url.rfind("http://", 0) != 0 && c.base_url.rfind("https://", 0) != 0)
    d.Error("$CTB_LLM_BASE_URL", "must start with http:// or https://");
  if (!d.ok()) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid LLM configuration", d);
  return c;
}

std::string LlmConfig::MaskedKey() const { return MaskedSecret(api_key); }

std::unique_ptr<LlmClient> MakeRecordingClient(std::unique_ptr<LlmClient> inner, const std::string& dir) {
  return std::make_unique<RecordingClient>(std::move(inner), dir);
}

std::variant<std::unique_ptr<LlmClient>, Error> MakeReplayClient(const std::string& dir,
                                                                 const std::string& model) {
  std::map<std::string, ChatResponse> answers;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    return Error{ErrorCode::kUnavailable, "replay directory '" + dir + "' does not exist", {}};
  for (const auto& f : std::filesystem::directory_iterator(dir, ec)) {
    if (f.path().extension() != ".json") continue;
    Diagnostics d;
    auto j = ReadJsonFile(f.path().string(), d);
    if (!j || !j->is_object() || !j->contains("request") || !j->contains("response") ||
        !(*j)["response"].contains("content") || !(*j)["response"]["content"].is_string())
      return Error{ErrorCode::kInvalidInput, "recording '" + f.path().string() + "' is malformed", {}};
    std::string m = j->value("model", model);
    if (m != model) continue;
    ChatResponse r;
    r.content = (*j)["response"]["content"].get<std::string>();
    r.finish_reason = (*j)["response"].value("finish_reason", "stop");
    if (const auto it = (*j)["response"].find("tokens");
        it != (*j)["response"].end() && it->is_number_integer() && it->get<long>() > 0)
      r.tokens = it->get<long>();
    answers[RequestKey(m, (*j)["request"])] = std::move(r);
  }
  return std::unique_ptr<LlmClient>(std::make_unique<ReplayClient>(std::move(answers), model, dir));
}

std::variant<std::unique_ptr<LlmClient>, Error> MakeClient(const LlmConfig& cfg) {
  if (!cfg.replay_dir.empty()) return MakeReplayClient(cfg.replay_dir, cfg.model);
  if (cfg.base_url.empty())
    return Error{ErrorCode::kUnavailable,
                 "no LLM endpoint configured: set CTB_LLM_BASE_URL (e.g. https://api.openai.com/v1 "
                 "or http://localhost:11434/v1), CTB_LLM_API_KEY and CTB_LLM_MODEL, or "
                 "CTB_LLM_REPLAY to answer from recordings", {}};
  auto client = MakeHttpClient(cfg);
  if (!cfg.record_dir.empty()) return MakeRecordingClient(std::move(client), cfg.record_dir);
  return client;
}

}  // namespace ctb
