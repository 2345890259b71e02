#include "server/stream.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <mutex>
#include <utility>

#include "planner/model/json_io.h"
#include "server/log_context.h"

namespace ctb::server {

namespace {

using Clock = std::chrono::steady_clock;

// One open event stream. Owned by the content provider for the length of the job; Send() may be
// called from any thread (it is serialised), and is a no-op once the client is gone.
class EventStream {
 public:
  EventStream(httplib::DataSink& sink, Clock::time_point t0) : sink_(sink), t0_(t0) {}

  long ElapsedMs() const {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0_).count();
  }

  // Writes one event; data goes on one line (JSON dumps without newlines).
  void Send(const std::string& event, const Json& data) {
    std::string text = "event: " + event +
                       "\ndata: " + WireText(data) +
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
};

// The core's progress as events on one stream, each with the stream's elapsed time.
class SseObserver : public app::Observer {
 public:
  explicit SseObserver(EventStream& s) : s_(s) {}
  void OnStage(const std::string& stage, const Json& info) override {
    Json data = info.is_object() ? info : Json::object();
    data["stage"] = stage;
    data["elapsed_ms"] = s_.ElapsedMs();
    s_.Send("stage", data);
  }
  void OnSolution(const SolveProgress& progress) override {
    Json data = app::SolutionEventJson(progress);
    data["elapsed_ms"] = s_.ElapsedMs();
    s_.Send("solution", data);
  }
  void OnItem(const Json& line) override { s_.Send("item", line); }

 private:
  EventStream& s_;
};

void SendBadStream(httplib::Response& res) {
  Json err = {{"code", CodeName(ErrorCode::kInvalidInput)},
              {"message", "\"stream\" must be true or false"},
              {"path", "/stream"},
              {"details", {{{"path", "/stream"}, {"message", "must be true or false"}}}}};
  res.status = HttpStatus(ErrorCode::kInvalidInput);
  res.set_content(Json({{"error", err}}).dump(), "application/json");
}

// Every solver place is taken: the stream is refused before its head, as the route would be.
void SendBusy(httplib::Response& res) {
  Json err = {{"code", CodeName(ErrorCode::kBusy)}, {"message", "all solver slots are busy; retry later"}};
  res.status = HttpStatus(ErrorCode::kBusy);
  res.set_header("Retry-After", "2");
  res.set_content(Json({{"error", err}}).dump(), "application/json");
}

// The route's answer; an exception is logged and answered as an internal error.
RouteAnswer RunGuarded(const RouteHandler& run, const httplib::Request& req, const Json& body,
                       app::Observer* observer) {
  try {
    return run(req, body, observer);
  } catch (const std::exception& e) {
    spdlog::error("{}", Json("unhandled exception in a stream: " + std::string(e.what()))
                            .dump(-1, ' ', false, Json::error_handler_t::replace));
    return Error{ErrorCode::kInternal, "internal error", {}};
  }
}

// The answer as the stream's last event: "done" with a 200 document, else "error" with the
// status the route would answer. Returns that status.
int SendLast(EventStream& stream, const RouteAnswer& answer) {
  if (const auto* e = std::get_if<Error>(&answer)) {
    const int status = HttpStatus(e->code);
    stream.Send("error", {{"error", ErrorObject(*e, "")}, {"status", status}});
    return status;
  }
  const auto& reply = std::get<JsonReply>(answer);
  if (reply.status == 200) {
    stream.Send("done", reply.body);
  } else {
    Json data = reply.body;
    data["status"] = reply.status;
    stream.Send("error", data);
  }
  return reply.status;
}

}  // namespace

void WithStreaming(const httplib::Request& req, Json body, httplib::Response& res,
                   std::atomic<int>& in_flight,
                   const std::function<std::shared_ptr<app::JobTicket>()>& reserve,
                   const RouteHandler& handler) {
  const auto it = body.find("stream");
  if (it == body.end()) return Send(res, handler(req, body, nullptr));
  if (!it->is_boolean()) return SendBadStream(res);
  const bool streaming = it->get<bool>();
  body.erase(it);
  if (!streaming) return Send(res, handler(req, body, nullptr));
  std::shared_ptr<app::JobTicket> ticket = reserve();
  if (!ticket) return SendBusy(res);
  const std::string request_id = ThreadRequestId();
  const auto t0 = Clock::now();
  res.set_header("Cache-Control", "no-cache");
  res.set_header("X-Accel-Buffering", "no");  // proxies such as nginx: do not buffer
  auto inner = std::make_shared<const httplib::Request>(req);
  auto parsed = std::make_shared<const Json>(std::move(body));
  RouteHandler run = handler;
  std::atomic<int>* counter = &in_flight;
  ++in_flight;  // counted from now: the provider runs after this handler returns
  res.set_chunked_content_provider(
      "text/event-stream",
      [inner, parsed, run, counter, request_id, t0,
       ticket](std::size_t, httplib::DataSink& sink) mutable {
        SetThreadRequestId(request_id);
        EventStream stream(sink, t0);
        SseObserver observer(stream);
        observer.ticket = std::move(ticket);
        const int status = SendLast(stream, RunGuarded(run, *inner, *parsed, &observer));
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

}  // namespace ctb::server
