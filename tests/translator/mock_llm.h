// A chat-completions endpoint on loopback for tests: a real HTTP server (cpp-httplib) that
// answers from a script, one entry per request, and keeps what it received.
#pragma once

#include <httplib.h>

#include <chrono>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "planner/model/json_io.h"

namespace ctb::testing {

struct MockReply {
  int status = 200;
  std::string body;  // raw body; see Chat() for a completion
  std::vector<std::pair<std::string, std::string>> headers;
  int delay_ms = 0;

  // A successful completion with this content.
  static MockReply Chat(const std::string& content, const std::string& finish = "stop") {
    Json j = {{"id", "mock"}, {"object", "chat.completion"},
              {"choices", {{{"index", 0}, {"message", {{"role", "assistant"}, {"content", content}}},
                            {"finish_reason", finish}}}}};
    return {200, j.dump(), {}, 0};
  }
  static MockReply Status(int status, const std::string& message, int delay_ms = 0) {
    Json j = {{"error", {{"message", message}, {"type", "mock"}}}};
    return {status, j.dump(), {}, delay_ms};
  }
};

struct MockRequest {
  Json body;
  std::string authorization;
};

class MockLlmServer {
 public:
  MockLlmServer() {
    server_.Post("/v1/chat/completions", [this](const httplib::Request& req, httplib::Response& res) {
      MockReply reply;
      {
        std::lock_guard<std::mutex> lock(mu_);
        requests_.push_back({Json::parse(req.body, nullptr, false), req.get_header_value("Authorization")});
        if (script_.empty()) {
          reply = MockReply::Status(500, "mock script exhausted");
        } else {
          reply = script_.front();
          script_.pop_front();
        }
      }
      if (reply.delay_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(reply.delay_ms));
      res.status = reply.status;
      for (const auto& [k, v] : reply.headers) res.set_header(k, v);
      res.set_content(reply.body, "application/json");
    });
    port_ = server_.bind_to_any_port("127.0.0.1");
    thread_ = std::thread([this] { server_.listen_after_bind(); });
    while (!server_.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ~MockLlmServer() {
    server_.stop();
    thread_.join();
  }
  std::string BaseUrl() const { return "http://127.0.0.1:" + std::to_string(port_) + "/v1"; }
  void Then(MockReply r) {
    std::lock_guard<std::mutex> lock(mu_);
    script_.push_back(std::move(r));
  }
  std::vector<MockRequest> Requests() {
    std::lock_guard<std::mutex> lock(mu_);
    return requests_;
  }

 private:
  httplib::Server server_;
  int port_ = 0;
  std::thread thread_;
  std::mutex mu_;
  std::deque<MockReply> script_;
  std::vector<MockRequest> requests_;
};

}  // namespace ctb::testing
