// Black-box tests of `ctburton serve`: the real binary on a free loopback port, the real HTTP
// client, the real minizinc; the LLM is the loopback mock.
#include <httplib.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <thread>

#include <gtest/gtest.h>

#include "../process_count.h"

#include "../planner/test_util.h"
#include "../translator/mock_llm.h"
#include "harness.h"
#include "openapi_record.h"

namespace ctb {
namespace {

using testing::MockLlmServer;
using testing::MockReply;

// Every answer the tests receive through Server::Client() is checked against server/openapi.json
// at the end (tests/server/openapi_record.h).
const auto* const kOpenApi = ::testing::AddGlobalTestEnvironment(new ctb::testing::OpenApiCheck);

// Writing to a socket the server closed must fail, not kill the test binary.
const bool kIgnoreSigpipe = [] {
  signal(SIGPIPE, SIG_IGN);
  return true;
}();

using ctb::testing::SolverProcesses;

// The server as a child process (harness.h), its answers recorded for the OpenAPI check.
class Server : public ctb::testing::ServerProcess {
 public:
  explicit Server(std::vector<std::pair<std::string, std::string>> env = {}, Json config = Json::object(),
                  std::string log_path = "")
      : ServerProcess(std::move(config), {}, std::move(env), std::move(log_path)) {}
  ctb::testing::RecordingClient Client() const {
    ctb::testing::RecordingClient c("127.0.0.1", port());
    c.set_read_timeout(120, 0);
    return c;
  }
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Json Example(const std::string& file) { return Json::parse(ReadFile(ctb::testing::ConfigDir() + "/examples/" + file)); }

Json SolveBody(const std::string& file, Json options = Json::object()) {
  Json b = {{"domain", file.substr(0, file.find('/'))}, {"state_plan", Example(file)}};
  if (!options.empty()) b["options"] = options;
  return b;
}

// Assembly, C onto A from a tower (tests/data/slow_c_on_a.json): the first plan comes at once,
// but no bound meets the optimum, so minizinc searches to the time limit. (Its loose temporal
// constraint, C on A within ten minutes of A's lifting, keeps the zone search with a deadline
// out: that search proves the goal alone optimal in a millisecond.)
Json SlowBody(Json options) {
  return {{"domain", "assembly"},
          {"state_plan", Json::parse(ReadFile(ctb::testing::SourceDir() + "/tests/data/slow_c_on_a.json"))},
          {"options", options}};
}

Json ErrorOf(const httplib::Result& r) { return Json::parse(r->body)["error"]; }

TEST(Service, HealthReadyDomainsAndThePage) {
  Server s;
  auto c = s.Client();
  auto h = c.Get("/healthz");
  ASSERT_TRUE(h);
  EXPECT_EQ(h->status, 200);
  EXPECT_EQ(c.Get("/readyz")->status, 200);
  auto d = c.Get("/domains");
  ASSERT_EQ(d->status, 200);
  EXPECT_EQ(Json::parse(d->body)["domains"].size(), 3u);
  auto one = c.Get("/domains/presentation");
  ASSERT_EQ(one->status, 200);
  EXPECT_EQ(Json::parse(one->body)["automata"].size(), 3u);
  auto missing = c.Get("/domains/nosuch");
  EXPECT_EQ(missing->status, 404);
  EXPECT_EQ(ErrorOf(missing)["code"], "not_found");
  auto route = c.Get("/nosuch/route");
  EXPECT_EQ(route->status, 404);
  EXPECT_EQ(ErrorOf(route)["code"], "not_found");
  auto page = c.Get("/");
  ASSERT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("<title>ctburton</title>"), std::string::npos);
  EXPECT_EQ(c.Get("/app.js")->status, 200);
  // The rest of what the page loads, /info and /openapi.json: their types and bodies are checked
  // against server/openapi.json at the end like every other answer.
  for (const char* f : {"/style.css", "/favicon.ico", "/favicon.svg", "/examples.json", "/nosuch.js"})
    EXPECT_EQ(c.Get(f)->status, std::string(f) == "/nosuch.js" ? 404 : 200) << f;
  auto info = c.Get("/info");
  ASSERT_EQ(info->status, 200);
  EXPECT_EQ(Json::parse(info->body)["llm"]["mode"], "none");
  EXPECT_EQ(c.Get("/openapi.json")->status, 200);
  auto gone = c.Delete("/sessions/0123456789abcdef0123456789abcdef");
  EXPECT_EQ(gone->status, 404);
}

TEST(Service, SolveAnswersAVerifiedTrajectory) {
  Server s;
  auto r = s.Client().Post("/solve", SolveBody("presentation/test1_cot.json", {{"objective", "makespan"}}).dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  Json t = Json::parse(r->body);
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["verified"], true);
  EXPECT_EQ(t["goal_reached_at"], 2430);
}

// Issue 21: POST /replan over the application core. Robot 1 stands at door 1 at t = 1 and cannot
// open it: robot 2 comes to open it, person 1 is reached at 12 (tests/planner/replan_test.cpp);
// a history that does not read is a 400 at its pointer.
TEST(Service, ReplanFromWhatHappened) {
  Server s;
  Json b = SolveBody("search_rescue/test2.json", {{"objective", "makespan"}});
  b["now"] = 1;
  b["executed"] = Json::parse(R"([
      {"time": 0, "automaton": "robot1", "from": "outside", "to": "goingToDoor1"},
      {"time": 1, "automaton": "robot1", "from": "goingToDoor1", "to": "atDoor1"}])");
  b["blocked"] = Json::parse(R"([{"automaton": "robot1", "from": "atDoor1", "to": "door1Opening"}])");
  auto r = s.Client().Post("/replan", b.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  Json t = Json::parse(r->body);
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["goal_reached_at"], 12);
  EXPECT_EQ(t["verified"], true);
  EXPECT_EQ(t["now"], 1);
  EXPECT_EQ(t["transitions"][0]["executed"], true);
  b["executed"][1]["to"] = "insideRoom1";
  r = s.Client().Post("/replan", b.dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400) << r->body;
  EXPECT_EQ(ErrorOf(r).value("path", ""), "/executed/1/to") << r->body;
}

// Contract section 11: what happened, in words, read by the LLM into `blocked` (a first reading
// that names no automaton of the domain is repaired), then replanned like the explicit request.
TEST(Service, ReplanFromAReportInWords) {
  MockLlmServer m;
  m.Then(MockReply::Chat(
      R"({"blocked": [{"automaton": "robot7", "from": "atDoor1", "to": "door1Opening"}], "restatement": "x"})"));
  m.Then(MockReply::Chat("```json\n{\"blocked\": [{\"automaton\": \"robot1\", \"from\": \"atDoor1\", "
                         "\"to\": \"door1Opening\"}], \"restatement\": \"robot 1 cannot open door 1\"}\n```"));
  Server s({{"CTB_LLM_BASE_URL", m.BaseUrl()}, {"CTB_LLM_MODEL", "mock"}});
  auto c = s.Client();
  auto plan = c.Post("/solve", SolveBody("search_rescue/test2.json", {{"objective", "makespan"}}).dump(),
                     "application/json");
  ASSERT_EQ(plan->status, 200) << plan->body;
  Json b = SolveBody("search_rescue/test2.json", {{"objective", "makespan"}});
  b["trajectory"] = Json::parse(plan->body);
  b["now"] = 1;
  b["executed"] = Json::parse(R"([
      {"time": 0, "automaton": "robot1", "from": "outside", "to": "goingToDoor1"},
      {"time": 1, "automaton": "robot1", "from": "goingToDoor1", "to": "atDoor1"}])");
  b["command"] = "robot 1 cannot open door 1";
  auto r = c.Post("/replan", b.dump(), "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  Json t = Json::parse(r->body);
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["goal_reached_at"], 12) << "as with the blocked transition given explicitly";
  EXPECT_EQ(t["report"]["blocked"], Json::parse(R"([{"automaton": "robot1", "from": "atDoor1", "to": "door1Opening"}])"));
  EXPECT_EQ(t["report"]["restatement"], "robot 1 cannot open door 1");
  for (const auto& tr : t["transitions"])
    EXPECT_FALSE(tr["automaton"] == "robot1" && tr["from"] == "atDoor1" && tr["to"] == "door1Opening") << tr;
  auto reqs = m.Requests();
  ASSERT_EQ(reqs.size(), 2u);
  const std::string first = reqs[0].body["messages"].dump();
  EXPECT_NE(first.find("robot 1 cannot open door 1"), std::string::npos);
  EXPECT_NE(first.find("t=1 s"), std::string::npos) << "the prompt shows the present time";
  EXPECT_NE(first.find("door1Opening"), std::string::npos) << "and the domain";
  const std::string repair = reqs[1].body["messages"].back()["content"];
  EXPECT_NE(repair.find("/blocked/0"), std::string::npos) << repair;
  // The client's own part is checked before any LLM call.
  b["executed"][1]["to"] = "insideRoom1";
  auto bad = c.Post("/replan", b.dump(), "application/json");
  EXPECT_EQ(bad->status, 400);
  EXPECT_EQ(ErrorOf(bad).value("path", ""), "/executed/1/to");
  b.erase("trajectory");
  auto no_plan = c.Post("/replan", b.dump(), "application/json");
  EXPECT_EQ(no_plan->status, 400);
  EXPECT_EQ(ErrorOf(no_plan).value("path", ""), "/trajectory");
  EXPECT_EQ(m.Requests().size(), 2u);
}

TEST(Service, InfeasibleIsA200) {
  Server s;
  Json b = {{"domain", "presentation"}, {"state_plan", Json::parse(ReadFile(ctb::testing::SourceDir() + "/tests/data/deadline_infeasible.json"))}};
  auto r = s.Client().Post("/solve", b.dump(), "application/json");
  ASSERT_EQ(r->status, 200);
  EXPECT_EQ(Json::parse(r->body)["status"], "infeasible");
}

// Issue 10: the answer restates the plan and says why it is infeasible and what would do.
TEST(Service, InfeasibleAnswerIsExplained) {
  Server s;
  Json b = {{"domain", "presentation"}, {"state_plan", Json::parse(ReadFile(ctb::testing::SourceDir() + "/tests/data/deadline_infeasible.json"))}};
  auto r = s.Client().Post("/solve", b.dump(), "application/json");
  ASSERT_EQ(r->status, 200);
  Json t = Json::parse(r->body);
  ASSERT_TRUE(t.contains("state_plan_summary"));
  EXPECT_EQ(t["state_plan_summary"].size(), 3u);  // initial state, goal, OnWithin10
  ASSERT_TRUE(t.contains("explanation"));
  EXPECT_EQ(t["explanation"]["conflicts"][0]["constraints"], Json::array({"/constraints/temporal/OnWithin10"}));
  EXPECT_EQ(t["explanation"]["relaxations"][0]["changes"][0]["value"], 30);
}

TEST(Service, InlineActionModel) {
  Server s;
  Json b = {{"action_model", Json::parse(ReadFile(ctb::testing::ConfigDir() + "/domains/presentation.json"))},
            {"state_plan", Example("presentation/test1_cot.json")}};
  auto r = s.Client().Post("/solve", b.dump(), "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
}

TEST(Service, BadInputGetsTheContractsErrorShape) {
  Server s;
  auto c = s.Client();
  struct Case { std::string body; int status; std::string path; };
  Json bad_plan = SolveBody("presentation/test1_cot.json");
  bad_plan["state_plan"]["initial_state"]["proj"] = "projOf";
  Json bad_option = SolveBody("presentation/test1_cot.json", {{"max_horizon", 100000}});
  Json unknown_domain = SolveBody("presentation/test1_cot.json");
  unknown_domain["domain"] = "nosuch";
  Json extra = SolveBody("presentation/test1_cot.json");
  extra["plan"] = 1;
  Json bad_model = {{"action_model", {{"name", "x"}, {"automata", Json::array()}}}, {"state_plan", Json::object()}};
  std::vector<Case> cases = {
      {"{bad json", 400, "/"},
      {"", 400, "/"},
      {"[1,2]", 400, "/"},
      {std::string(100, '[') + std::string(100, ']'), 400, "/"},
      {bad_plan.dump(), 400, "/state_plan/initial_state/proj"},
      {bad_option.dump(), 400, "/options/max_horizon"},
      {unknown_domain.dump(), 404, "/domain"},
      {extra.dump(), 400, "/plan"},
      {bad_model.dump(), 400, "/action_model/automata"},
  };
  for (const auto& k : cases) {
    auto r = c.Post("/solve", k.body, "application/json");
    ASSERT_TRUE(r) << k.body;
    EXPECT_EQ(r->status, k.status) << k.body.substr(0, 80) << " -> " << r->body;
    Json e = ErrorOf(r);
    EXPECT_TRUE(e.contains("code") && e.contains("message")) << r->body;
    EXPECT_EQ(e.value("path", ""), k.path) << r->body;
  }
  EXPECT_TRUE(s.Alive());
}

TEST(Service, OversizedBodiesPlainAndChunked) {
  Server s({}, {{"max_body_bytes", 4096}});
  auto c = s.Client();
  std::string big = "{\"x\": \"" + std::string(100000, 'a') + "\"}";
  auto r = c.Post("/solve", big, "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 413);
  EXPECT_EQ(ErrorOf(r)["code"], "too_large");
  // A chunked body cannot dodge the limit: chunked requests are refused outright. The server
  // stops reading at once, so the upload is bounded by the client's own timeouts.
  std::size_t sent = 0;
  httplib::Client cc = s.Client();
  cc.set_write_timeout(3, 0);
  cc.set_read_timeout(5, 0);
  auto chunked = cc.Post("/solve",
                        [&](size_t, httplib::DataSink& sink) {
                          if (sent < 50000) {
                            std::string part(10000, ' ');
                            sink.write(part.data(), part.size());
                            sent += part.size();
                          } else {
                            sink.done();
                          }
                          return true;
                        },
                        "application/json");
  // Either the refusal arrives, or the server cut the upload short; never a 200.
  ctb::testing::Record("POST", "/solve", chunked);
  if (chunked) {
    EXPECT_TRUE(chunked->status == 411 || chunked->status == 413) << chunked->status;
  }
  EXPECT_EQ(c.Get("/healthz")->status, 200);
}

TEST(Service, RequestIdIsEchoedOrMade) {
  Server s;
  auto c = s.Client();
  auto r = c.Get("/healthz", {{"X-Request-Id", "abc-123"}});
  EXPECT_EQ(r->get_header_value("X-Request-Id"), "abc-123");
  auto made = c.Get("/healthz", {{"X-Request-Id", "bad id with spaces"}});
  EXPECT_EQ(made->get_header_value("X-Request-Id").size(), 16u);
}

TEST(Service, OneJsonLogLinePerRequestWithItsId) {
  std::string log = "/tmp/ctb-server-log-" + std::to_string(getpid()) + ".txt";
  {
    Server s({}, Json::object(), log);
    s.Client().Post("/solve", {{"X-Request-Id", "log-check-1"}}, "{bad", "application/json");
  }
  std::ifstream in(log);
  std::string line;
  int lines = 0, mine = 0;
  while (std::getline(in, line)) {
    Json j = Json::parse(line, nullptr, false);
    EXPECT_FALSE(j.is_discarded()) << "not JSON: " << line;
    ++lines;
    if (!j.is_discarded() && j.value("request_id", "") == "log-check-1" && j["log"]["event"] == "request") {
      ++mine;
      EXPECT_EQ(j["log"]["status"], 400);
      EXPECT_EQ(j["log"]["route"], "/solve");
    }
  }
  EXPECT_GT(lines, 2);
  EXPECT_EQ(mine, 1);
  std::filesystem::remove(log);
}

TEST(Service, MetricsCountRequests) {
  Server s;
  auto c = s.Client();
  c.Get("/healthz");
  c.Post("/solve", "{bad", "application/json");
  auto m = c.Get("/metrics");
  ASSERT_EQ(m->status, 200);
  EXPECT_NE(m->body.find("ctb_http_requests_total{route=\"/healthz\",status=\"200\"} "), std::string::npos) << m->body;
  EXPECT_NE(m->body.find("ctb_http_requests_total{route=\"/solve\",status=\"400\"} 1"), std::string::npos);
  EXPECT_NE(m->body.find("ctb_http_request_duration_seconds_bucket{route=\"/solve\",le=\"+Inf\"} 1"), std::string::npos);
  EXPECT_NE(m->body.find("ctb_solver_jobs_running 0"), std::string::npos);
  EXPECT_NE(m->body.find("ctb_llm_calls_total"), std::string::npos);
}

const char* kTp1 =
    "The computer and projector start in the off state, and the connection is disconnected. The projector "
    "should turn on and stay on for 1800 seconds, following which everything should turn off within 600 "
    "seconds. In addition, the projector should turn on within 60 seconds.";

TEST(Service, PlanAndTranslateFromTheRecordingsWithoutAnLlm) {
  Server s({}, {{"demo", true}});  // the recordings answer only behind the demo switch
  auto c = s.Client();
  Json b = {{"domain", "presentation"}, {"command", kTp1}};
  auto t = c.Post("/translate", b.dump(), "application/json");
  ASSERT_EQ(t->status, 200) << t->body;
  EXPECT_TRUE(Json::parse(t->body)["state_plan"]["constraints"]["temporal"].contains("ProjectorOnWithin60"));
  auto p = c.Post("/plan", b.dump(), "application/json");
  ASSERT_EQ(p->status, 200) << p->body;
  Json pj = Json::parse(p->body);
  EXPECT_EQ(pj["trajectory"]["verified"], true);
  EXPECT_EQ(pj["session"].get<std::string>().size(), 32u);
  b["command"] = "Something nobody recorded.";
  auto miss = c.Post("/plan", b.dump(), "application/json");
  EXPECT_EQ(miss->status, 503);
  EXPECT_NE(ErrorOf(miss)["message"].get<std::string>().find("CTB_LLM_BASE_URL"), std::string::npos);
}

TEST(Service, SessionFollowUpEditsThePreviousStatePlan) {
  MockLlmServer m;
  Json first = Example("presentation/test1_cot.json");
  Json second = first;
  second["constraints"]["episodes"]["ProjectorOnDuration"]["lower_bound"] = 300;
  second["constraints"]["episodes"]["ProjectorOnDuration"]["upper_bound"] = 300;
  m.Then(MockReply::Chat("Initial State\nall off"));
  m.Then(MockReply::Chat(first.dump()));
  m.Then(MockReply::Chat(second.dump()));
  Server s({{"CTB_LLM_BASE_URL", m.BaseUrl()}, {"CTB_LLM_MODEL", "mock"}});
  auto c = s.Client();
  auto p1 = c.Post("/plan", Json({{"domain", "presentation"}, {"command", kTp1}}).dump(), "application/json");
  ASSERT_EQ(p1->status, 200) << p1->body;
  std::string session = Json::parse(p1->body)["session"];
  Json follow = {{"session", session}, {"command", "make the projector stay on for 300 seconds instead"}};
  auto p2 = c.Post("/plan", follow.dump(), "application/json");
  ASSERT_EQ(p2->status, 200) << p2->body;
  Json t = Json::parse(p2->body)["trajectory"];
  const Json& ep = t["episodes"]["ProjectorOnDuration"];
  EXPECT_EQ(ep["end"].get<double>() - ep["start"].get<double>(), 300);
  auto reqs = m.Requests();
  ASSERT_EQ(reqs.size(), 3u);
  const Json& msgs = reqs[2].body["messages"];
  std::string last = msgs.back()["content"];
  EXPECT_NE(last.find("\"ProjectorOnDuration\""), std::string::npos) << "the follow-up quotes the current plan";
  EXPECT_NE(last.find("300 seconds instead"), std::string::npos);
  EXPECT_GE(msgs.size(), 5u) << "the conversation is kept";
  auto unknown = c.Post("/plan", Json({{"session", "nope"}, {"command", "x"}}).dump(), "application/json");
  EXPECT_EQ(unknown->status, 404);
}

TEST(Service, TheApiKeyNeverLeavesInA502AndWarningsAreReturned) {
  MockLlmServer m;
  const std::string key = "sk-test-secret-key-1234";
  m.Then(MockReply::Status(400, "Incorrect API key provided: " + key));
  Json plan = Example("presentation/test1_cot.json");
  m.Then(MockReply::Chat("<think>draft</think>\n" + plan.dump()));
  Server s({{"CTB_LLM_BASE_URL", m.BaseUrl()}, {"CTB_LLM_API_KEY", key}});
  auto c = s.Client();
  Json b = {{"domain", "presentation"}, {"command", kTp1}, {"prompting", "direct"}};
  auto bad = c.Post("/translate", b.dump(), "application/json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 502);
  EXPECT_EQ(bad->body.find(key), std::string::npos) << bad->body;
  EXPECT_NE(bad->body.find("sk-...1234"), std::string::npos) << bad->body;
  auto ok = c.Post("/translate", b.dump(), "application/json");
  ASSERT_TRUE(ok);
  ASSERT_EQ(ok->status, 200) << ok->body;
  Json w = Json::parse(ok->body)["warnings"];
  ASSERT_EQ(w.size(), 1u) << ok->body;
  EXPECT_NE(w[0]["message"].get<std::string>().find("<think>"), std::string::npos);
}

TEST(Service, LlmFailuresMapToTheirStatuses) {
  MockLlmServer m;
  m.Then(MockReply::Status(401, "bad key"));
  m.Then(MockReply::Status(200, "late", 3000));
  for (int i = 0; i < 4; ++i) m.Then(MockReply::Chat("no json here"));
  Server s({{"CTB_LLM_BASE_URL", m.BaseUrl()}, {"CTB_LLM_TIMEOUT_MS", "500"}});
  auto c = s.Client();
  Json b = {{"domain", "presentation"}, {"command", kTp1}, {"prompting", "direct"}};
  EXPECT_EQ(c.Post("/translate", b.dump(), "application/json")->status, 502);
  EXPECT_EQ(c.Post("/translate", b.dump(), "application/json")->status, 504);
  auto unrepairable = c.Post("/translate", b.dump(), "application/json");
  EXPECT_EQ(unrepairable->status, 422);
  EXPECT_EQ(ErrorOf(unrepairable)["code"], "unprocessable");
}

TEST(Service, BurstOfSolvesIsAnsweredWith200Or503AndTheServerLives) {
  Server s({}, {{"solver_workers", 1}, {"solver_queue", 1}});
  const int n = 6;
  std::vector<std::future<int>> answers;
  // Assembly, C onto A from a tower: no bound meets its optimum, so minizinc runs to the limit.
  Json body = SlowBody({{"objective", "makespan"}, {"time_limit_ms", 3000}});
  std::vector<std::string> retry_after(n);
  for (int i = 0; i < n; ++i)
    answers.push_back(std::async(std::launch::async, [&, i] {
      auto r = s.Client().Post("/solve", body.dump(), "application/json");
      if (!r) return -1;
      retry_after[i] = r->get_header_value("Retry-After");
      return r->status;
    }));
  int ok = 0, busy = 0;
  for (int i = 0; i < n; ++i) {
    int st = answers[i].get();
    EXPECT_TRUE(st == 200 || st == 503) << st;
    if (st == 200) ++ok;
    if (st == 503) {
      ++busy;
      EXPECT_FALSE(retry_after[i].empty());
    }
  }
  EXPECT_EQ(ok + busy, n);
  EXPECT_GE(busy, 1);
  EXPECT_GE(ok, 1);
  EXPECT_EQ(s.Client().Get("/healthz")->status, 200);
}

TEST(Service, AClientThatGoesAwayHasItsSolverKilled) {
  int before = SolverProcesses();
  Server s;
  {
    httplib::Client c = s.Client();
    c.set_read_timeout(1, 0);  // gives up after 1 s and closes its connection
    auto r = c.Post("/solve", SlowBody({{"objective", "makespan"}, {"max_horizon", 64}, {"time_limit_ms", 60000}}).dump(), "application/json");
    EXPECT_FALSE(r) << "the solve takes longer than the client waits";
  }
  bool gone = false;
  for (int i = 0; i < 100 && !gone; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    gone = SolverProcesses() == before;
  }
  EXPECT_TRUE(gone) << "the solver still runs 5 s after its client left";
  EXPECT_EQ(s.Client().Get("/healthz")->status, 200);
  // The processes die a moment before the handler gives its slot back: wait (bounded) for it.
  bool slot_free = false;
  for (int i = 0; i < 40 && !slot_free; ++i) {
    slot_free = s.Client().Get("/metrics")->body.find("ctb_solver_jobs_running 0") != std::string::npos;
    if (!slot_free) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(slot_free) << "the job's pool slot was not released within 2 s";
}

TEST(Service, ShutdownDuringASolveKillsTheSolverAndExitsZero) {
  int before = SolverProcesses();
  Server s({}, {{"shutdown_grace_ms", 500}});
  auto pending = std::async(std::launch::async, [&] {
    auto r = s.Client().Post("/solve", SlowBody({{"objective", "makespan"}, {"max_horizon", 64}, {"time_limit_ms", 60000}}).dump(), "application/json");
    return r ? r->status : -1;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  EXPECT_GT(SolverProcesses(), before) << "a solve is running";
  auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(s.Stop(15000), 0);
  auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(ms, 10000);
  int st = pending.get();
  EXPECT_TRUE(st == 503 || st == 200 || st == -1) << st;
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(SolverProcesses(), before);
}

}  // namespace
}  // namespace ctb
