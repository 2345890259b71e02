// Sessions (issue 13) against real servers on loopback: the SQLite store across a restart, the
// optimistic version (two follow-ups at once: one 409), the cap checked before the LLM, GET and
// DELETE; and two replicas sharing a real redis-server behind a real nginx (round robin), one of
// them killed during a solve. The LLM is the loopback mock. Every answer is checked against
// server/openapi.json at the end.
#include <sys/stat.h>

#include <filesystem>
#include <future>
#include <string>

#include <gtest/gtest.h>

#include "../process_count.h"
#include "../translator/mock_llm.h"
#include "harness.h"

namespace ctb {
namespace {

using Clock = std::chrono::steady_clock;
using testing::MockLlmServer;
using testing::MockReply;
using testing::ServerProcess;

const auto* const kOpenApi = ::testing::AddGlobalTestEnvironment(new testing::OpenApiCheck);

Json Example(const std::string& file) {
  return Json::parse(std::ifstream(testing::ConfigDir() + "/examples/" + file));
}

// One request through httplib, recorded for the OpenAPI check.
httplib::Result Call(httplib::Client& c, const std::string& method, const std::string& path, const Json& body = nullptr) {
  httplib::Result r = method == "GET"      ? c.Get(path.c_str())
                      : method == "DELETE" ? c.Delete(path.c_str())
                                           : c.Post(path.c_str(), body.dump(), "application/json");
  testing::Record(method, path, r);
  return r;
}

Json PlanBody(const std::string& command, const std::string& session = "", Json options = nullptr) {
  Json b = {{"command", command}, {"prompting", "direct"}};
  if (session.empty()) b["domain"] = "presentation";
  else b["session"] = session;
  if (!options.is_null()) b["options"] = options;
  return b;
}

std::vector<std::pair<std::string, std::string>> LlmEnv(const MockLlmServer& m, std::vector<std::pair<std::string, std::string>> more = {}) {
  more.push_back({"CTB_LLM_BASE_URL", m.BaseUrl()});
  more.push_back({"CTB_LLM_MODEL", "mock"});
  return more;
}

TEST(Sessions, SqliteKeepsEveryTurnAcrossARestart) {
  MockLlmServer m;
  Json first = Example("presentation/test1_cot.json");
  Json second = first;
  second["constraints"]["episodes"]["ProjectorOnDuration"]["lower_bound"] = 300;
  second["constraints"]["episodes"]["ProjectorOnDuration"]["upper_bound"] = 300;
  m.Then(MockReply::Chat(first.dump()));
  m.Then(MockReply::Chat(second.dump()));
  const std::string data = testing::TempDir("sessions-sqlite");
  std::string id;
  {
    ServerProcess s(Json::object(), {"--data-dir", data}, LlmEnv(m));
    auto c = s.Client();
    auto p1 = Call(c, "POST", "/plan", PlanBody("turn one"));
    ASSERT_TRUE(p1);
    ASSERT_EQ(p1->status, 200) << p1->body;
    id = Json::parse(p1->body)["session"];
    EXPECT_EQ(id.size(), 32u);
    EXPECT_EQ(id.find_first_not_of("0123456789abcdef"), std::string::npos);
    EXPECT_EQ(s.Stop(10000), 0);
  }
  EXPECT_TRUE(std::filesystem::exists(data + "/sessions.db"));
  ServerProcess s(Json::object(), {"--data-dir", data}, LlmEnv(m));
  auto c = s.Client();
  auto p2 = Call(c, "POST", "/plan", PlanBody("turn two: 300 seconds", id));
  ASSERT_TRUE(p2);
  ASSERT_EQ(p2->status, 200) << p2->body;
  EXPECT_EQ(Json::parse(p2->body)["session"], id);
  // The follow-up saw the first turn's conversation, restored from the database.
  auto reqs = m.Requests();
  ASSERT_EQ(reqs.size(), 2u);
  EXPECT_NE(reqs[1].body["messages"].dump().find("turn one"), std::string::npos);
  auto g = Call(c, "GET", "/sessions/" + id);
  ASSERT_EQ(g->status, 200);
  Json view = Json::parse(g->body);
  EXPECT_EQ(view["domain"], "presentation");
  ASSERT_EQ(view["turns"].size(), 2u);
  EXPECT_EQ(view["turns"][0]["command"], "turn one");
  EXPECT_EQ(view["turns"][1]["command"], "turn two: 300 seconds");
  EXPECT_EQ(view["turns"][1]["state_plan"], second);
  EXPECT_EQ(view["turns"][0]["trajectory_summary"]["status"], "optimal");
  EXPECT_FALSE(view["turns"][1]["at"].get<std::string>().empty());
  // Another id reads nothing; DELETE removes it.
  EXPECT_EQ(Call(c, "GET", "/sessions/" + std::string(32, 'a'))->status, 404);
  EXPECT_EQ(Call(c, "DELETE", "/sessions/" + id)->status, 204);
  EXPECT_EQ(Call(c, "GET", "/sessions/" + id)->status, 404);
  EXPECT_EQ(Call(c, "DELETE", "/sessions/" + id)->status, 404);
  std::filesystem::remove_all(data);
}

TEST(Sessions, TwoFollowUpsAtOnceLoseNoTurnOneGets409) {
  MockLlmServer m;
  Json plan = Example("presentation/test1_cot.json");
  m.Then(MockReply::Chat(plan.dump()));
  MockReply slow = MockReply::Chat(plan.dump());
  slow.delay_ms = 2500;
  m.Then(slow);                         // follow-up A: answered late
  m.Then(MockReply::Chat(plan.dump())); // follow-up B: answered at once, stored first
  const std::string data = testing::TempDir("sessions-conflict");
  ServerProcess s(Json::object(), {"--data-dir", data}, LlmEnv(m));
  auto c = s.Client();
  auto p1 = Call(c, "POST", "/plan", PlanBody("start"));
  ASSERT_EQ(p1->status, 200) << p1->body;
  const std::string id = Json::parse(p1->body)["session"];
  auto a = std::async(std::launch::async, [&] {
    auto ca = s.Client();
    return Call(ca, "POST", "/plan", PlanBody("follow-up A", id));
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  auto cb = s.Client();
  auto b = Call(cb, "POST", "/plan", PlanBody("follow-up B", id));
  auto ra = a.get();
  ASSERT_TRUE(ra && b);
  EXPECT_EQ(b->status, 200) << b->body;
  EXPECT_EQ(ra->status, 409) << ra->body;
  EXPECT_EQ(Json::parse(ra->body)["error"]["code"], "conflict");
  Json view = Json::parse(Call(c, "GET", "/sessions/" + id)->body);
  ASSERT_EQ(view["turns"].size(), 2u);
  EXPECT_EQ(view["turns"][1]["command"], "follow-up B");
  std::filesystem::remove_all(data);
}

TEST(Sessions, TheCapAndTheOptionsAreCheckedBeforeAnyLlmCall) {
  MockLlmServer m;
  Json plan = Example("presentation/test1_cot.json");
  m.Then(MockReply::Chat(plan.dump()));
  m.Then(MockReply::Chat(plan.dump()));
  const std::string data = testing::TempDir("sessions-cap");
  ServerProcess s({{"max_sessions", 1}}, {"--data-dir", data}, LlmEnv(m));
  auto c = s.Client();
  ASSERT_EQ(Call(c, "POST", "/plan", PlanBody("one"))->status, 200);
  auto full = Call(c, "POST", "/plan", PlanBody("two"));
  EXPECT_EQ(full->status, 503);
  EXPECT_EQ(Json::parse(full->body)["error"]["code"], "busy");
  auto bad = Call(c, "POST", "/plan", PlanBody("three", "", {{"objective", "fastest"}}));
  EXPECT_TRUE(bad->status == 400 || bad->status == 503) << bad->status;
  EXPECT_EQ(m.Requests().size(), 1u) << "no LLM call for a request refused up front";
  std::filesystem::remove_all(data);
}

// --- replicas: redis-server + two `ctburton serve` + nginx, all on free loopback ports ---

using testing::Executable;
using testing::Spawn;
using testing::StopChild;
using testing::WaitForPort;

// Solver processes of a killed replica are reparented to this test (a subreaper): kill and reap.
void KillOrphanedSolvers() {
  for (int round = 0; round < 50; ++round) {
    bool any = false;
    for (const auto& proc : testing::Processes()) {
      if (proc.ppid != getpid() || (proc.comm != "minizinc" && proc.comm.rfind("fzn-", 0) != 0))
        continue;
      pid_t p = static_cast<pid_t>(proc.pid);
      kill(p, SIGKILL);
      waitpid(p, nullptr, 0);
      any = true;
    }
    if (!any) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

TEST(Replicas, TurnsAlternateAcrossReplicasAndAKilledReplicaLosesNoSession) {
  ASSERT_TRUE(Executable("/usr/bin/redis-server") && Executable("/usr/sbin/nginx"))
      << "redis-server or nginx missing: bash scripts/install-deps.sh --test";
  const int before = testing::SolverProcesses();
  const std::string dir = testing::TempDir("sessions-replicas");
  const int redis_port = testing::FreeLoopbackPort();
  pid_t redis = Spawn({"/usr/bin/redis-server", "--port", std::to_string(redis_port), "--bind", "127.0.0.1",
                       "--save", "", "--appendonly", "no", "--dir", dir},
                      dir + "/redis.log");
  testing::StopAtExit stop_redis(redis);
  ASSERT_TRUE(WaitForPort(redis_port, 5000)) << "redis-server did not start";

  MockLlmServer m;
  Json plan = Example("presentation/test1_cot.json");
  for (int i = 0; i < 4; ++i) m.Then(MockReply::Chat(plan.dump()));
  // The long solve that is running when its replica is killed.
  // (Assembly: the first-plan engine's plan is not provably optimal there, so minizinc runs.)
  Json slow = Json::parse(std::ifstream(testing::SourceDir() + "/tests/data/slow_c_on_a.json"));
  m.Then(MockReply::Chat(slow.dump()));
  for (int i = 0; i < 2; ++i) m.Then(MockReply::Chat(plan.dump()));

  const std::string store = "redis://127.0.0.1:" + std::to_string(redis_port) + "/0";
  auto replica = [&] {
    return std::make_unique<ServerProcess>(Json::object(), std::vector<std::string>{"--session-store", store},
                                           LlmEnv(m));
  };
  auto r1 = replica();
  auto r2 = replica();
  const int proxy_port = testing::FreeLoopbackPort();
  for (const char* sub : {"body", "proxy", "fastcgi", "uwsgi", "scgi", "logs"}) {
    std::filesystem::create_directories(dir + "/" + sub);
    chmod((dir + "/" + sub).c_str(), 0777);
  }
  std::ofstream(dir + "/nginx.conf")
      << "daemon off;\nworker_processes 1;\npid " << dir << "/nginx.pid;\nerror_log " << dir << "/logs/error.log;\n"
      << "events { worker_connections 256; }\nhttp {\n  access_log off;\n"
      << "  client_body_temp_path " << dir << "/body;\n  proxy_temp_path " << dir << "/proxy;\n"
      << "  fastcgi_temp_path " << dir << "/fastcgi;\n  uwsgi_temp_path " << dir << "/uwsgi;\n"
      << "  scgi_temp_path " << dir << "/scgi;\n"
      << "  upstream ctb {\n    server 127.0.0.1:" << r1->port() << " max_fails=1 fail_timeout=10s;\n"
      << "    server 127.0.0.1:" << r2->port() << " max_fails=1 fail_timeout=10s;\n  }\n"
      << "  server {\n    listen 127.0.0.1:" << proxy_port << ";\n    location / {\n"
      << "      proxy_pass http://ctb;\n      proxy_http_version 1.1;\n      proxy_set_header Connection \"\";\n"
      << "      proxy_read_timeout 120s;\n    }\n  }\n}\n";
  pid_t nginx = Spawn({"/usr/sbin/nginx", "-p", dir, "-c", dir + "/nginx.conf"}, dir + "/nginx.out");
  testing::StopAtExit stop_nginx(nginx);
  ASSERT_TRUE(WaitForPort(proxy_port, 5000)) << "nginx did not start";

  httplib::Client c("127.0.0.1", proxy_port);
  c.set_read_timeout(120, 0);
  // A dialogue of four turns; round robin sends them to alternate replicas.
  auto p1 = Call(c, "POST", "/plan", PlanBody("turn 1"));
  ASSERT_TRUE(p1);
  ASSERT_EQ(p1->status, 200) << p1->body;
  const std::string id = Json::parse(p1->body)["session"];
  for (int t = 2; t <= 4; ++t) {
    auto p = Call(c, "POST", "/plan", PlanBody("turn " + std::to_string(t), id));
    ASSERT_TRUE(p);
    ASSERT_EQ(p->status, 200) << p->body;
  }
  // Both replicas served turns (each replica's log of requests is its own: count via /metrics).
  int served_by_both = 0;
  for (auto* r : {r1.get(), r2.get()}) {
    auto mtx = r->Client().Get("/metrics");
    if (mtx && mtx->body.find("route=\"/plan\",status=\"200\"") != std::string::npos) ++served_by_both;
  }
  EXPECT_EQ(served_by_both, 2) << "round robin spread the turns";
  // Each turn saw the whole history: the fourth LLM request quotes turn 3's command.
  auto reqs = m.Requests();
  ASSERT_EQ(reqs.size(), 4u);
  EXPECT_NE(reqs[3].body["messages"].dump().find("turn 3"), std::string::npos);

  // A long solve in a new dialogue; the replica running it is killed.
  auto pending = std::async(std::launch::async, [&] {
    httplib::Client cl("127.0.0.1", proxy_port);
    cl.set_read_timeout(120, 0);
    Json b = {{"domain", "assembly"}, {"command", "slow one"}, {"prompting", "direct"},
              {"options", {{"objective", "makespan"}, {"time_limit_ms", 60000}}}};
    // Not recorded for the OpenAPI check: the 502 is nginx's own (HTML) page, not the service's.
    return cl.Post("/plan", b.dump(), "application/json");
  });
  ServerProcess* victim = nullptr;
  for (int i = 0; i < 1000 && !victim; ++i) {
    for (auto* r : {r1.get(), r2.get()})
      if (!r->Children("minizinc").empty()) victim = r;
    if (!victim) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_NE(victim, nullptr) << "no replica started a solve";
  ServerProcess* survivor = victim == r1.get() ? r2.get() : r1.get();
  victim->Kill();
  auto t0 = Clock::now();
  auto killed = pending.get();
  ASSERT_TRUE(killed);
  EXPECT_TRUE(killed->status == 502 || killed->status == 503) << killed->status;
  EXPECT_LT(std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count(), 5000);
  KillOrphanedSolvers();
  // The other replica serves; the first dialogue is intact and continues.
  auto p5 = Call(c, "POST", "/plan", PlanBody("turn 5", id));
  ASSERT_TRUE(p5);
  EXPECT_EQ(p5->status, 200) << p5->body;
  auto g = Call(c, "GET", "/sessions/" + id);
  ASSERT_EQ(g->status, 200);
  Json view = Json::parse(g->body);
  ASSERT_EQ(view["turns"].size(), 5u);
  for (int t = 0; t < 5; ++t) EXPECT_EQ(view["turns"][t]["command"], "turn " + std::to_string(t + 1));
  EXPECT_EQ(testing::Health(survivor->port(), "127.0.0.1").status, 200);

  StopChild(nginx);
  r1.reset();
  r2.reset();
  StopChild(redis);
  KillOrphanedSolvers();
  EXPECT_EQ(testing::SolverProcesses(), before);
  std::filesystem::remove_all(dir);
}

TEST(Sessions, RedisStoreHasTheSameCapAndIdleExpiry) {
  ASSERT_TRUE(Executable("/usr/bin/redis-server")) << "redis-server missing: bash scripts/install-deps.sh --test";
  const std::string dir = testing::TempDir("sessions-redis-cap");
  const int redis_port = testing::FreeLoopbackPort();
  pid_t redis = Spawn({"/usr/bin/redis-server", "--port", std::to_string(redis_port), "--bind", "127.0.0.1",
                       "--save", "", "--appendonly", "no", "--dir", dir},
                      dir + "/redis.log");
  testing::StopAtExit stop_redis(redis);
  ASSERT_TRUE(WaitForPort(redis_port, 5000)) << "redis-server did not start";
  MockLlmServer m;
  Json plan = Example("presentation/test1_cot.json");
  for (int i = 0; i < 2; ++i) m.Then(MockReply::Chat(plan.dump()));
  {
    ServerProcess s({{"max_sessions", 1}, {"session_idle_s", 2}},
                    {"--session-store", "redis://127.0.0.1:" + std::to_string(redis_port) + "/3"}, LlmEnv(m));
    auto c = s.Client();
    auto p1 = Call(c, "POST", "/plan", PlanBody("one"));
    ASSERT_EQ(p1->status, 200) << p1->body;
    const std::string id = Json::parse(p1->body)["session"];
    auto full = Call(c, "POST", "/plan", PlanBody("two"));
    EXPECT_EQ(full->status, 503);
    EXPECT_EQ(m.Requests().size(), 1u) << "refused before the LLM";
    EXPECT_EQ(Call(c, "GET", "/sessions/" + id)->status, 200);
    std::this_thread::sleep_for(std::chrono::milliseconds(2600));
    EXPECT_EQ(Call(c, "GET", "/sessions/" + id)->status, 404) << "expired after 2 s idle";
    EXPECT_EQ(Call(c, "POST", "/plan", PlanBody("three"))->status, 200) << "the expired one no longer counts";
  }
  StopChild(redis);
  std::filesystem::remove_all(dir);
}

// Review defects of issue 13, section 4 (each a process exit code or an answer).
int RunToExit(const std::vector<std::string>& args, std::vector<std::pair<std::string, std::string>> env = {}) {
  pid_t pid = fork();
  if (pid == 0) {
    for (auto& [k, v] : env) setenv(k.c_str(), v.c_str(), 1);
    int devnull = open("/dev/null", O_WRONLY);
    dup2(devnull, 1);
    dup2(devnull, 2);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  for (int i = 0; i < 500; ++i) {
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  return -2;  // still running after 10 s
}

TEST(Defects, ReviewFindingsOfIssue13) {
  const std::string dir = testing::TempDir("sessions-defects");
  // A second domain file with an existing name stops the start, instead of being dropped.
  std::filesystem::create_directories(dir + "/config/domains");
  std::filesystem::copy_file(testing::ConfigDir() + "/domains/presentation.json", dir + "/config/domains/a.json");
  std::filesystem::copy_file(testing::ConfigDir() + "/domains/presentation.json", dir + "/config/domains/b.json");
  EXPECT_EQ(RunToExit({CTB_BINARY, "serve", "--port", "0", "--config-dir", dir + "/config", "--data-dir", dir + "/d"}), 2);
  // Out-of-range numbers in the configuration file are refused, not cast.
  std::ofstream(dir + "/big.json") << R"({"solver_workers": 1099511627776})";
  EXPECT_EQ(RunToExit({CTB_BINARY, "serve", "--port", "0", "--config", dir + "/big.json", "--data-dir", dir + "/d"},
                      {{"CTB_CONFIG_DIR", testing::ConfigDir()}}), 2);
  std::ofstream(dir + "/neg.json") << R"({"read_timeout_s": 0})";
  EXPECT_EQ(RunToExit({CTB_BINARY, "serve", "--port", "0", "--config", dir + "/neg.json", "--data-dir", dir + "/d"},
                      {{"CTB_CONFIG_DIR", testing::ConfigDir()}}), 2);
  // `ctburton plan` refuses an invalid --objective up front (exit 1, the shared exit-code map).
  EXPECT_EQ(RunToExit({CTB_BINARY, "plan", "--domain", "presentation", "--objective", "fastest", "x"},
                      {{"CTB_CONFIG_DIR", testing::ConfigDir()}}), 1);
  // /metrics counts the page and static files; without --demo there is no recordings fallback.
  ServerProcess s(Json::object(), {"--data-dir", dir + "/d"});
  auto c = s.Client();
  auto page = c.Get("/");
  ASSERT_TRUE(page);
  auto m = Call(c, "GET", "/metrics");
  EXPECT_NE(m->body.find("route=\"(static)\""), std::string::npos);
  auto t = Call(c, "POST", "/translate", Json({{"domain", "presentation"}, {"command", "x"}}));
  EXPECT_EQ(t->status, 503);
  EXPECT_NE(Json::parse(t->body)["error"]["message"].get<std::string>().find("--demo"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ctb
