#include "server/stream.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <mutex>
#include <utility>

#include "server/log_context.h"

namespace ctb::server {

namespace {

using Clock = std::chrono::steady_clock;

// One open event stream. Owned by the content provider for the length of the job; Send() may be
// called from any thread (it is serialised), and is a no-op once the client is gone.
class EventStream {
 public:
  EventStream(httplib::DataSink& sink, Clock::time_point t0, int llm_calls_expected)
      : sink_(sink), t0_(t0), llm_calls_expected_(llm_calls_expected) {}

  long ElapsedMs() const {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0_).count();
  }
  int llm_calls_expected() const { return llm_calls_expected_; }

  // Writes one event; data goes on one line (JSON dumps without newlines).
  void Send(const std::string& event, const Json& data) {
    std::string text = "event: " + event +
                       "\ndata: " + data.dump(-1, ' ', false, Json::error_handler_t::replace) +
                       "\n\n";
    std::lock_guard<std::mutex> lock(mu_);
    if (open_ && !sink_.write(text.data(), text.size())) open_ = false;
  }
  bool open() {
    std::lock_guard<std::mutex> lock(mu_);
    return open_;
  }

 private:
  std::mutex mu_;
  httplib::DataSink& sink_;
  bool open_ = true;
  const Clock::time_point t0_;
  const int llm_calls_expected_;
};

thread_local EventStream* t_stream = nullptr;

// Installs a stream as this thread's for the scope.
class ThreadStream {
 public:
  explicit ThreadStream(EventStream* s) { t_stream = s; }
  ~ThreadStream() { t_stream = nullptr; }
  ThreadStream(const ThreadStream&) = delete;
  ThreadStream& operator=(const ThreadStream&) = delete;
};

class ReportingLlm : public LlmClient {
 public:
  ReportingLlm(std::unique_ptr<LlmClient> inner, EventStream* stream)
      : inner_(std::move(inner)), stream_(stream) {}
  std::variant<ChatResponse, Error> Complete(const ChatRequest& req) override {
    int call = ++calls_;
    Json data = {{"stage", call > stream_->llm_calls_expected() ? "repairing" : "translating"},
                 {"llm_call", call},
                 {"elapsed_ms", stream_->ElapsedMs()}};
    stream_->Send("stage", data);
    return inner_->Complete(req);
  }
  std::string model() const override { return inner_->model(); }
  int attempts() const override { return inner_->attempts(); }

 private:
  std::unique_ptr<LlmClient> inner_;
  EventStream* stream_;
  std::atomic<int> calls_{0};
};

// 2430.0 -> 2430, 12.5 stays.
Json Seconds(const Json& v) {
  if (v.is_number_float() && std::floor(v.get<double>()) == v.get<double>() &&
      std::fabs(v.get<double>()) < 1e15)
    return static_cast<long long>(v.get<double>());
  return v;
}

void SendBadStream(httplib::Response& res) {
  Json err = {{"code", CodeName(ErrorCode::kInvalidInput)},
              {"message", "\"stream\" must be true or false"},
              {"path", "/stream"},
              {"details", {{{"path", "/stream"}, {"message", "must be true or false"}}}}};
  res.status = HttpStatus(ErrorCode::kInvalidInput);
  res.set_content(Json({{"error", err}}).dump(), "application/json");
}

}  // namespace

void WithStreaming(const httplib::Request& req, httplib::Response& res, std::atomic<int>& in_flight,
                   const RouteHandler& handler) {
  Diagnostics d;
  auto body = ParseJsonStrict(req.body, d);
  if (!body || !body->is_object() || !body->contains("stream")) return handler(req, res);
  const Json stream = (*body)["stream"];
  if (!stream.is_boolean()) return SendBadStream(res);
  body->erase("stream");
  auto inner = std::make_shared<httplib::Request>(req);
  inner->body = body->dump();
  if (!stream.get<bool>()) return handler(*inner, res);

  // The LLM calls the prompting mode makes before any repair: chain of thought makes two (extract,
  // map), direct one; a follow-up in a session one.
  int expected = 1;
  if (!body->contains("session") && (!body->contains("prompting") || (*body)["prompting"] == "cot"))
    expected = 2;
  const std::string request_id = ThreadRequestId();
  const auto t0 = Clock::now();
  res.set_header("Cache-Control", "no-cache");
  res.set_header("X-Accel-Buffering", "no");  // proxies such as nginx: do not buffer
  RouteHandler run = handler;
  std::atomic<int>* counter = &in_flight;
  ++in_flight;  // counted from now: the provider runs after this handler returns
  res.set_chunked_content_provider(
      "text/event-stream",
      [inner, run, counter, request_id, t0, expected](std::size_t, httplib::DataSink& sink) {
        SetThreadRequestId(request_id);
        EventStream stream(sink, t0, expected);
        httplib::Response answer;
        {
          ThreadStream installed(&stream);
          try {
            run(*inner, answer);
          } catch (const std::exception& e) {
            spdlog::error("{}", Json("unhandled exception in a stream: " + std::string(e.what()))
                                    .dump(-1, ' ', false, Json::error_handler_t::replace));
            answer.status = 500;
            answer.body =
                Json({{"error",
                       {{"code", CodeName(ErrorCode::kInternal)}, {"message", "internal error"}}}})
                    .dump();
          }
        }
        int status = answer.status == -1 ? 200 : answer.status;
        Diagnostics ad;
        auto data = ParseJsonStrict(answer.body, ad);
        if (!data) data = Json{{"error", {{"code", "internal"}, {"message", "no answer"}}}};
        if (status == 200) {
          stream.Send("done", *data);
        } else {
          (*data)["status"] = status;
          stream.Send("error", *data);
        }
        spdlog::info("{}", Json({{"event", "stream_end"},
                                 {"path", inner->path},
                                 {"status", status},
                                 {"client_connected", stream.open()},
                                 {"ms", stream.ElapsedMs()}})
                               .dump(-1, ' ', false, Json::error_handler_t::replace));
        sink.done();
        SetThreadRequestId("");
        return true;
      },
      // Runs when the response is gone, whether or not the provider ran (a client that left
      // before it started): the job is no longer in flight.
      [counter](bool) { --*counter; });
}

void StreamStage(const std::string& stage) {
  if (t_stream) t_stream->Send("stage", {{"stage", stage}, {"elapsed_ms", t_stream->ElapsedMs()}});
}

std::function<void(const Json& progress)> StreamSolutionReporter() {
  EventStream* s = t_stream;
  if (!s) return nullptr;
  return [s](const Json& p) {
    Json data = p;
    const std::string kind = p.value("kind", "cost");
    Json makespan = Seconds(p.value("makespan", Json()));
    data["makespan"] = makespan;
    if (kind == "makespan")
      data["objective"] = makespan;
    else if (kind == "cost_then_makespan")
      data["objective"] = {{"cost", p.value("cost", Json())}, {"makespan", makespan}};
    else
      data["objective"] = p.value("cost", Json());
    data["solve_ms"] = p.value("elapsed_ms", Json());
    data["elapsed_ms"] = s->ElapsedMs();
    s->Send("solution", data);
  };
}

std::unique_ptr<LlmClient> StreamReportingLlm(std::unique_ptr<LlmClient> inner) {
  if (!t_stream) return inner;
  return std::make_unique<ReportingLlm>(std::move(inner), t_stream);
}

}  // namespace ctb::server
