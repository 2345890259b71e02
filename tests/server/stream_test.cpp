// Black-box tests of the Server-Sent Events of POST /plan and /solve with "stream": true (contract
// section 9): the real `ctburton serve`, the real minizinc, the shipped LLM recordings; the
// client reads the raw socket the way `curl -N` does (chunked transfer decoded as it arrives,
// each event timed on arrival).
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <strings.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include "../planner/test_util.h"
#include "../process_count.h"
#include "harness.h"
#include "openapi_record.h"

namespace ctb {
namespace {

using Clock = std::chrono::steady_clock;
using ctb::testing::SolverProcesses;

// Every answer (its events, as far as the test read them) is checked against server/openapi.json
// at the end (tests/server/openapi_record.h).
const auto* const kOpenApi = ::testing::AddGlobalTestEnvironment(new ctb::testing::OpenApiCheck);

const bool kIgnoreSigpipe = [] {
  signal(SIGPIPE, SIG_IGN);
  return true;
}();

const char* kTp1 =
    "The computer and projector start in the off state, and the connection is disconnected. The "
    "projector should turn on and stay on for 1800 seconds, following which everything should turn "
    "off within 600 seconds. In addition, the projector should turn on within 60 seconds.";

// A connection for reading a stream, with a generous receive time-out.
int Connect(int port) {
  int s = testing::ConnectFrom(port);
  if (s < 0) return -1;
  timeval tv{120, 0};
  setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  return s;
}

// `ctburton serve --demo` as a child process (harness.h), no LLM configured (the recordings
// answer), its sessions in a directory of its own.
class Server : public testing::ServerProcess {
 public:
  Server() : ServerProcess(nlohmann::json::object(), {"--demo"}) {}
};

struct Event {
  std::string name;
  Json data;
  long at_ms;  // since the request was sent
};

// One POST on a raw socket; reads the status line and headers, then the chunked body as it
// arrives, splitting it into events. Close() hangs up (a client that leaves).
class SseClient {
 public:
  SseClient(int port, const Json& body, const std::string& path = "/plan") : path_(path) {
    fd_ = Connect(port);
    std::string b = body.dump();
    std::string req = "POST " + path +
                      " HTTP/1.1\r\nHost: 127.0.0.1\r\nAccept: text/event-stream\r\n"
                      "Accept-Encoding: gzip, deflate, br\r\nContent-Type: application/json\r\n"
                      "Content-Length: " +
                      std::to_string(b.size()) + "\r\n\r\n" + b;
    t0_ = Clock::now();
    if (fd_ >= 0) send(fd_, req.data(), req.size(), 0);
    while (fd_ >= 0 && raw_.find("\r\n\r\n") == std::string::npos && Fill()) {
    }
    auto end = raw_.find("\r\n\r\n");
    if (end == std::string::npos) return;
    head_ = raw_.substr(0, end);
    raw_.erase(0, end + 4);
    std::istringstream line(head_);
    std::string version;
    line >> version >> status_;
  }
  ~SseClient() { Close(); }
  void Close() {
    Keep();
    if (fd_ >= 0) close(fd_);
    fd_ = -1;
  }
  int status() const { return status_; }
  // The header's value (case-insensitive name), "" when absent.
  std::string Header(const std::string& name) const {
    std::istringstream in(head_);
    std::string l;
    while (std::getline(in, l)) {
      auto c = l.find(':');
      if (c == std::string::npos) continue;
      std::string k = l.substr(0, c);
      if (strcasecmp(k.c_str(), name.c_str()) != 0) continue;
      std::string v = l.substr(c + 1);
      while (!v.empty() && (v.front() == ' ')) v.erase(0, 1);
      while (!v.empty() && (v.back() == '\r' || v.back() == ' ')) v.pop_back();
      return v;
    }
    return "";
  }
  // The next event; nullopt at the end of the body (or on a closed connection).
  std::optional<Event> Next() {
    for (;;) {
      auto end = body_.find("\n\n");
      if (end != std::string::npos) {
        std::string block = body_.substr(0, end);
        body_.erase(0, end + 2);
        Event e{"message", Json(), MsSince()};
        std::istringstream in(block);
        std::string l, data;
        while (std::getline(in, l)) {
          if (l.rfind("event: ", 0) == 0) e.name = l.substr(7);
          if (l.rfind("data: ", 0) == 0) data += l.substr(6);
        }
        e.data = Json::parse(data, nullptr, false);
        return e;
      }
      if (!Dechunk()) return std::nullopt;
    }
  }
  std::vector<Event> All() {
    std::vector<Event> v;
    while (auto e = Next()) v.push_back(*e);
    return v;
  }

 private:
  long MsSince() const {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0_).count();
  }
  bool Fill() {
    char buf[8192];
    ssize_t n = fd_ < 0 ? -1 : recv(fd_, buf, sizeof buf, 0);
    if (n <= 0) return false;
    raw_.append(buf, static_cast<std::size_t>(n));
    return true;
  }
  // Moves one chunk from raw_ to body_; false at the last chunk or when the connection ends.
  bool Dechunk() {
    for (;;) {
      auto eol = raw_.find("\r\n");
      if (eol != std::string::npos) {
        std::size_t size = std::stoul(raw_.substr(0, eol), nullptr, 16);
        if (size == 0) return false;
        if (raw_.size() >= eol + 2 + size + 2) {
          body_ += raw_.substr(eol + 2, size);
          seen_ += raw_.substr(eol + 2, size);
          raw_.erase(0, eol + 2 + size + 2);
          return true;
        }
      }
      if (!Fill()) return false;
    }
  }
  // Records the answer for the OpenAPI check, once: an event stream as far as it was read (the
  // checker skips a last, unfinished event), any other body whole. This client asks for
  // compression (to show streams are not compressed): a compressed body (a plain JSON answer,
  // br or gzip) cannot be checked here and is left out; server_tests check those uncompressed.
  void Keep() {
    if (kept_ || status_ == 0) return;
    kept_ = true;
    const std::string coding = Header("Content-Encoding");
    if (!coding.empty() && strcasecmp(coding.c_str(), "identity") != 0) return;
    std::string body = seen_;
    if (strcasecmp(Header("Transfer-Encoding").c_str(), "chunked") != 0) {
      const std::size_t n = std::strtoul(Header("Content-Length").c_str(), nullptr, 10);
      while (raw_.size() < n && Fill()) {
      }
      body = raw_.substr(0, n);
    }
    ctb::testing::Record("POST", path_, status_, Header("Content-Type"), body);
  }
  int fd_ = -1;
  int status_ = 0;
  bool kept_ = false;
  std::string path_, head_, raw_, body_, seen_;
  Clock::time_point t0_;
};

Json Example(const std::string& file) {
  std::ifstream in(ctb::testing::ConfigDir() + "/examples/" + file);
  std::stringstream ss;
  ss << in.rdbuf();
  return Json::parse(ss.str());
}

std::vector<std::string> Names(const std::vector<Event>& events) {
  std::vector<std::string> v;
  for (const auto& e : events)
    v.push_back(e.name == "stage" ? "stage:" + e.data.value("stage", "?") : e.name);
  return v;
}

TEST(ServiceStream, PlanStreamsStagesTheImprovingPlanAndTheWholeAnswer) {
  Server s;
  SseClient c(s.port(), {{"domain", "presentation"}, {"command", kTp1}, {"stream", true}});
  ASSERT_EQ(c.status(), 200);
  EXPECT_EQ(c.Header("Content-Type"), "text/event-stream");
  EXPECT_EQ(c.Header("Content-Encoding"), "") << "events must not wait in a compressor";
  EXPECT_EQ(c.Header("Cache-Control"), "no-cache");
  auto events = c.All();
  auto names = Names(events);
  ASSERT_GE(names.size(), 5u) << ::testing::PrintToString(names);
  // Chain of thought: two LLM calls (extract, map), then the solve.
  EXPECT_EQ(names[0], "stage:translating");
  EXPECT_EQ(events[0].data["llm_call"], 1);
  EXPECT_EQ(names[1], "stage:translating");
  EXPECT_EQ(events[1].data["llm_call"], 2);
  EXPECT_EQ(names[2], "stage:solving");
  EXPECT_EQ(names.back(), "done");
  const Json& answer = events.back().data;
  ASSERT_TRUE(answer.contains("trajectory")) << answer.dump();
  EXPECT_EQ(answer["trajectory"]["status"], "optimal");
  EXPECT_EQ(answer["trajectory"]["objective"]["value"], 7);
  EXPECT_TRUE(answer["trajectory"]["verified"].get<bool>());
  EXPECT_EQ(answer["session"].get<std::string>().size(), 32u);
  EXPECT_TRUE(answer["reasoning"].get<std::string>().rfind("Initial State", 0) == 0);
  // Each improving plan, the last one being the answer's.
  std::vector<Event> solutions;
  for (const auto& e : events)
    if (e.name == "solution") solutions.push_back(e);
  ASSERT_GE(solutions.size(), 1u);
  EXPECT_EQ(solutions.back().data["objective"], 7);
  EXPECT_EQ(solutions.back().data["kind"], "cost");
  EXPECT_EQ(solutions.back().data["makespan"], 2430);
  EXPECT_TRUE(solutions.back().data["elapsed_ms"].is_number_integer());
  for (std::size_t i = 1; i < solutions.size(); ++i)
    EXPECT_LT(solutions[i].data["objective"].get<long>(),
              solutions[i - 1].data["objective"].get<long>());
}

TEST(ServiceStream, DirectPromptingReportsItsRepair) {
  Server s;
  SseClient c(
      s.port(),
      {{"domain", "presentation"}, {"command", kTp1}, {"prompting", "direct"}, {"stream", true}});
  auto names = Names(c.All());
  // The recorded direct answer has the projl[0] slip: one repair request.
  ASSERT_GE(names.size(), 4u);
  EXPECT_EQ(names[0], "stage:translating");
  EXPECT_EQ(names[1], "stage:repairing");
  EXPECT_EQ(names[2], "stage:solving");
  EXPECT_EQ(names.back(), "done");
}

TEST(ServiceStream, SolveStreamsTheSameAnswerAsWithoutStreaming) {
  Server s;
  Json body = {{"domain", "presentation"}, {"state_plan", Example("presentation/test1_cot.json")}};
  Json streamed = body;
  streamed["stream"] = true;
  SseClient c(s.port(), streamed, "/solve");
  auto events = c.All();
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(Names(events).front(), "stage:solving");
  ASSERT_EQ(events.back().name, "done");
  SseClient plain(s.port(), body, "/solve");
  EXPECT_EQ(plain.Header("Content-Type"), "application/json");
  Json t = events.back().data;
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["goal_reached_at"], 2430);
  EXPECT_EQ(t["objective"]["value"], 7);
}

TEST(ServiceStream, StreamFalseAnswersPlainJson) {
  Server s;
  Json body = {{"domain", "presentation"},
               {"state_plan", Example("presentation/test1_cot.json")},
               {"stream", false}};
  SseClient c(s.port(), body, "/solve");
  EXPECT_EQ(c.status(), 200);
  EXPECT_EQ(c.Header("Content-Type"), "application/json");
}

TEST(ServiceStream, StreamMustBeABoolean) {
  Server s;
  SseClient c(s.port(), {{"domain", "presentation"}, {"command", kTp1}, {"stream", "yes"}});
  EXPECT_EQ(c.status(), 400);
  EXPECT_EQ(c.Header("Content-Type"), "application/json");
}

TEST(ServiceStream, AnInvalidRequestEndsWithAnErrorEvent) {
  Server s;
  {
    SseClient c(s.port(), {{"domain", "nope"}, {"state_plan", Json::object()}, {"stream", true}},
                "/solve");
    EXPECT_EQ(c.status(), 200);
    auto events = c.All();
    ASSERT_EQ(events.size(), 1u) << ::testing::PrintToString(Names(events));
    EXPECT_EQ(events[0].name, "error");
    EXPECT_EQ(events[0].data["status"], 404);
    EXPECT_EQ(events[0].data["error"]["code"], "not_found");
  }
  {
    Json sp = Example("presentation/test1_cot.json");
    sp["initial_state"]["proj"] = "projOnn";
    SseClient c(s.port(), {{"domain", "presentation"}, {"state_plan", sp}, {"stream", true}},
                "/solve");
    auto events = c.All();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].data["status"], 400);
    EXPECT_EQ(events[0].data["error"]["path"], "/state_plan/initial_state/proj");
  }
  {
    // No LLM and no recording for this command: 503 with how to configure one.
    SseClient c(s.port(),
                {{"domain", "presentation"}, {"command", "never recorded"}, {"stream", true}});
    auto events = c.All();
    ASSERT_FALSE(events.empty());
    EXPECT_EQ(events.back().name, "error");
    EXPECT_EQ(events.back().data["status"], 503);
    EXPECT_NE(events.back().data["error"]["message"].get<std::string>().find("CTB_LLM_BASE_URL"),
              std::string::npos);
  }
}

// The assembly test prompt, cheapest: the first-plan engine's plan comes in milliseconds, Gecode's
// proof of 12 transitions seconds later. (By makespan its plan now meets the workload bound at
// once.)
Json SlowSolve() {
  return {{"domain", "assembly"},
          {"state_plan", Example("assembly/test.json")},
          {"options", {{"time_limit_ms", 60000}, {"objective", "cost"}}},
          {"stream", true}};
}

// Assembly, C onto A from a tower (tests/data/slow_c_on_a.json), fastest, looking as far as 64
// events (the server's limit): no bound meets its optimum, so the search runs to the time limit.
Json VerySlowSolve() {
  return {{"domain", "assembly"},
          {"state_plan", Json::parse(std::ifstream(testing::SourceDir() + "/tests/data/slow_c_on_a.json"))},
          {"options", {{"time_limit_ms", 60000}, {"objective", "makespan"}, {"max_horizon", 64}}},
          {"stream", true}};
}

TEST(ServiceStream, AnImprovingPlanArrivesBeforeTheAnswer) {
  Server s;
  SseClient c(s.port(), SlowSolve(), "/solve");
  auto events = c.All();
  ASSERT_GE(events.size(), 3u);
  ASSERT_EQ(events.back().name, "done");
  long first_solution = -1;
  for (const auto& e : events)
    if (e.name == "solution" && first_solution < 0) first_solution = e.at_ms;
  ASSERT_GE(first_solution, 0) << ::testing::PrintToString(Names(events));
  // Every improving plan says how far from optimal it may be.
  for (const auto& e : events)
    if (e.name == "solution") {
      ASSERT_TRUE(e.data.contains("bound")) << e.data.dump();
      EXPECT_LE(e.data["bound"].get<double>(), e.data["objective"].get<double>()) << e.data.dump();
    }
  // Read off the wire well before the answer, not flushed together with it.
  EXPECT_LT(first_solution + 500, events.back().at_ms);
  EXPECT_EQ(events.back().data["status"], "optimal");
  EXPECT_EQ(events.back().data["objective"]["value"], 12);
}

// A stream reserves its solver place before its 200 head: with one place (1 worker, no queue)
// taken by a running stream, another stream is refused before any head, like a plain request:
// 503 busy with Retry-After, never a 200 whose last event is an error (seen under load by
// bench/soak.py). Once the first stream is gone, the place serves again.
TEST(ServiceStream, AStreamOnABusyServerIs503WithRetryAfterBeforeItsHead) {
  testing::ServerProcess s({{"solver_workers", 1}, {"solver_queue", 0}}, {"--demo"});
  const Json quick = {{"domain", "presentation"}, {"state_plan", Example("presentation/test1_cot.json")}, {"stream", true}};
  {
    SseClient first(s.port(), VerySlowSolve(), "/solve");
    ASSERT_EQ(first.status(), 200);
    SseClient second(s.port(), quick, "/solve");
    EXPECT_EQ(second.status(), 503);
    EXPECT_FALSE(second.Header("Retry-After").empty());
    EXPECT_EQ(second.Header("Content-Type"), "application/json");
    SseClient plan(s.port(), {{"domain", "presentation"}, {"command", kTp1}, {"stream", true}});
    EXPECT_EQ(plan.status(), 503) << "a /plan stream reserves too";
    auto c = s.Client();
    auto plain = c.Post("/solve", Json({{"domain", "presentation"}, {"state_plan", Example("presentation/test1_cot.json")}}).dump(),
                        "application/json");
    ASSERT_TRUE(plain);
    EXPECT_EQ(plain->status, 503);
    EXPECT_FALSE(plain->get_header_value("Retry-After").empty());
    first.Close();
  }
  // The hung-up stream gives its place back (its watcher stops the solver).
  std::vector<Event> events;
  for (int i = 0; i < 800; ++i) {  // up to 20 s on a loaded machine; at once on an idle one
    SseClient again(s.port(), quick, "/solve");
    if (again.status() == 200) {
      events = again.All();
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  ASSERT_FALSE(events.empty()) << "the place was not given back";
  EXPECT_EQ(events.back().name, "done");
}

TEST(ServiceStream, AClientThatHangsUpCancelsTheSolver) {
  Server s;
  {
    SseClient c(s.port(), VerySlowSolve(), "/solve");
    std::optional<Event> e;
    while ((e = c.Next()) && e->name != "solution") {
    }
    ASSERT_TRUE(e) << "no solution event";
    // The next horizon's model starts a moment after the first plan.
    int running = 0;
    for (int i = 0; i < 60 && running == 0; ++i) {
      running = SolverProcesses();
      if (!running) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    EXPECT_GT(running, 0) << "the optimality proof should still be running";
    c.Close();
  }
  int left = -1;
  for (int i = 0; i < 100 && left != 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    left = SolverProcesses();
  }
  EXPECT_EQ(left, 0) << "solver processes left after the client hung up";
  // The slot is free again: another stream runs to its answer.
  SseClient again(s.port(),
                  {{"domain", "presentation"},
                   {"state_plan", Example("presentation/test1_cot.json")},
                   {"stream", true}},
                  "/solve");
  auto events = again.All();
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().name, "done");
}

}  // namespace
}  // namespace ctb
