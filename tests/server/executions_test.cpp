// Executions (contract section 14) against the real server on loopback, with the real minizinc:
// the sim adapter carries search_rescue to the goal; a failed move replans; bad reports are
// refused at their pointer while the execution goes on; a repeated report changes nothing; the
// SSE stream ends with `finished`; kill -9 mid-execution and a restart on the same data: every
// acknowledged report is still there, no command is dispatched twice, and the run finishes.
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "harness.h"

namespace ctb {
// A namespace of its own: the test executable's unity build puts files with same-named
// helpers side by side.
namespace executions_test {
namespace {

using Clock = std::chrono::steady_clock;
using testing::ServerProcess;

Json Example(const std::string& file) {
  return Json::parse(std::ifstream(testing::ConfigDir() + "/examples/" + file));
}

Json Post(httplib::Client& c, const std::string& path, const Json& body, int* status = nullptr) {
  auto r = c.Post(path.c_str(), body.dump(), "application/json");
  testing::Record("POST", path, r);  // checked against server/openapi.json (sessions_test.cpp)
  if (!r) {
    ADD_FAILURE() << "no answer from POST " << path;
    return Json();
  }
  if (status) *status = r->status;
  return Json::parse(r->body, nullptr, false);
}

Json Get(httplib::Client& c, const std::string& path, bool record = true) {
  auto r = c.Get(path.c_str());
  if (record) testing::Record("GET", path, r);
  if (!r) {
    ADD_FAILURE() << "no answer from GET " << path;
    return Json();
  }
  return Json::parse(r->body, nullptr, false);
}

// GET /executions/{id} until `done` holds or the deadline passes (generous: the machine may be
// loaded); the last view.
template <typename Pred>
Json WaitFor(httplib::Client& c, const std::string& id, Pred done, int seconds = 90) {
  const auto until = Clock::now() + std::chrono::seconds(seconds);
  Json v;
  while (Clock::now() < until) {
    v = Get(c, "/executions/" + id, /*record=*/false);
    if (done(v)) return Get(c, "/executions/" + id);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ADD_FAILURE() << "timed out; last view: " << v.dump().substr(0, 2000);
  return v;
}

bool Ended(const Json& v) { return v.value("state", "") != "running"; }

int Count(const Json& view, const std::string& event) {
  int n = 0;
  for (const auto& e : view["events"]) n += e["event"] == event;
  return n;
}

Json RescueRequest(double speed, const Json& extra = Json::object()) {
  Json body = {{"domain", "search_rescue"}, {"state_plan", Example("search_rescue/test1.json")},
               {"speed", speed}};
  for (const auto& [k, v] : extra.items()) body[k] = v;
  return body;
}

// An execution carried on after its server died: every report the first server acknowledged
// (its GET showed it in `before`) is in the history `after`, and no command was dispatched twice.
void ExpectCarriedOnFrom(const Json& before, const Json& after) {
  std::set<std::string> history;
  for (const auto& h : after["history"]) history.insert(h["automaton"].get<std::string>() + h["to"].get<std::string>());
  for (const auto& h : before["history"])
    EXPECT_TRUE(history.count(h["automaton"].get<std::string>() + h["to"].get<std::string>())) << h.dump();
  std::set<std::string> sent;
  for (const auto& e : after["events"])
    if (e["event"] == "dispatched") {
      EXPECT_TRUE(sent.insert(e["data"].dump()).second) << "twice: " << e.dump();
    }
}

TEST(Executions, TheSimCarriesAPlanToTheGoalAndTheStreamEndsWithFinished) {
  ServerProcess server;
  auto c = server.Client();
  int status = 0;
  // Speed 5: a plan second is 200 ms of wall time. The sim's reports are exact (no grace), so a
  // stall of the execution's thread longer than a grid step (at speed 100, 10 ms: a loaded CI
  // machine) dispatched a command late and replanned once.
  Json started = Post(c, "/executions", RescueRequest(5, {{"adapter", "sim"}}), &status);
  ASSERT_EQ(status, 201) << started.dump();
  const std::string id = started["execution"];
  Json v = WaitFor(c, id, Ended);
  EXPECT_EQ(v["state"], "succeeded") << v.dump();
  EXPECT_EQ(v["replans"], 0) << v.dump().substr(0, 3000);
  // Every transition of the plan was reported, in the history, each command dispatched once.
  EXPECT_EQ(v["history"].size(), v["plan"]["transitions"].size());
  std::set<std::string> sent;
  for (const auto& e : v["events"])
    if (e["event"] == "dispatched") {
      EXPECT_TRUE(sent.insert(e["data"].dump()).second) << e.dump();
    }
  int commands = 0;
  for (const auto& t : v["plan"]["transitions"]) commands += t["command"].is_string();
  EXPECT_EQ(static_cast<int>(sent.size()), commands);
  // The stream replays what happened and ends with `finished`.
  auto sse = c.Get(("/executions/" + id + "/events").c_str());
  ASSERT_TRUE(sse);
  EXPECT_NE(sse->get_header_value("Content-Type").find("text/event-stream"), std::string::npos);
  EXPECT_NE(sse->body.find("event: dispatched"), std::string::npos);
  const auto last = sse->body.rfind("event: ");
  EXPECT_EQ(sse->body.substr(last, 15), "event: finished") << sse->body.substr(last);
}

TEST(Executions, AFailedMoveReplansAroundItAndBadReportsAreRefusedAtTheirPointer) {
  ServerProcess server;
  auto c = server.Client();
  int status = 0;
  // External devices: this test is the team. At speed 1 nothing becomes overdue meanwhile.
  Json started = Post(c, "/executions", RescueRequest(1, {{"adapter", "external"}}), &status);
  ASSERT_EQ(status, 201) << started.dump();
  const std::string id = started["execution"];
  const std::string reports = "/executions/" + id + "/reports";
  Json v = WaitFor(c, id, [](const Json& x) { return Count(x, "dispatched") >= 2; });
  std::map<std::string, Json> first;  // automaton -> its first command
  for (const auto& e : v["events"])
    if (e["event"] == "dispatched" && !first.count(e["data"]["automaton"])) first[e["data"]["automaton"]] = e["data"];
  ASSERT_TRUE(first.count("robot1") && first.count("robot2")) << v.dump();

  struct Bad {
    Json report;
    std::string path;
  };
  const std::vector<Bad> bad = {
      {{{"automaton", "robot9"}, {"location", "atDoor1"}, {"time", 0}}, "/automaton"},
      {{{"automaton", "robot1"}, {"location", "onTheMoon"}, {"time", 0}}, "/location"},
      {{{"automaton", "robot1"}, {"location", "insideRoom1"}, {"time", 0}}, "/location"},  // no such move
      {{{"automaton", "robot1"}, {"location", first["robot1"]["to"]}, {"time", 100000}}, "/time"},
      {{{"automaton", "robot1"}, {"failed", "fly"}, {"time", 0}}, "/failed"},
      {{{"automaton", "robot1"}, {"time", 0}}, "/location"},
      {{{"automaton", "robot1"}, {"location", "x"}, {"time", 0}, {"speed", 3}}, "/speed"},
  };
  for (const auto& b : bad) {
    Json err = Post(c, reports, b.report, &status);
    EXPECT_EQ(status, 400) << b.report.dump();
    EXPECT_EQ(err["error"]["path"], b.path) << err.dump();
  }
  auto garbage = c.Post(reports.c_str(), "{not json", "application/json");
  ASSERT_TRUE(garbage);
  EXPECT_EQ(garbage->status, 400);

  // robot2 moves as told, twice reported: stored once.
  const Json done2 = {{"automaton", "robot2"}, {"location", first["robot2"]["to"]}, {"time", 0}};
  Json ok = Post(c, reports, done2, &status);
  EXPECT_EQ(status, 200) << ok.dump();
  EXPECT_EQ(ok["duplicate"], false);
  ok = Post(c, reports, done2, &status);
  EXPECT_EQ(status, 200);
  EXPECT_EQ(ok["duplicate"], true);

  // robot1 cannot make its move: the plan goes around it.
  const Json failed = {{"automaton", "robot1"}, {"failed", first["robot1"]["command"]}, {"time", 0}};
  Post(c, reports, failed, &status);
  EXPECT_EQ(status, 200);
  v = WaitFor(c, id, [](const Json& x) { return x.value("replans", 0) >= 1 || Ended(x); });
  EXPECT_EQ(v["state"], "running") << v.value("why", "");
  EXPECT_EQ(v["replans"], 1);
  ASSERT_EQ(v["blocked"].size(), 1u);
  EXPECT_EQ(v["blocked"][0]["automaton"], "robot1");
  EXPECT_EQ(v["history"].size(), 1u);  // robot2's move, once
  for (const auto& t : v["plan"]["transitions"])
    if (t["automaton"] == "robot1" && t.value("command", Json()) == first["robot1"]["command"] &&
        !t.value("executed", false))
      ADD_FAILURE() << "the new plan uses the blocked move again: " << t.dump();
  Json replanned;
  for (const auto& e : v["events"])
    if (e["event"] == "replanned") replanned = e["data"];
  EXPECT_NE(replanned.value("why", "").find("cannot"), std::string::npos) << replanned.dump();

  auto stop = c.Delete(("/executions/" + id).c_str());
  ASSERT_TRUE(stop);
  EXPECT_EQ(stop->status, 200);
  v = WaitFor(c, id, Ended);
  EXPECT_EQ(v["state"], "stopped");
  Post(c, reports, done2, &status);
  EXPECT_EQ(status, 409) << "a report after the end is refused";
}

TEST(Executions, AKilledServerResumesFromTheStoreAndDispatchesNothingTwice) {
  const std::string data = "/tmp/ctb-exec-restart-" + std::to_string(getpid());
  std::filesystem::remove_all(data);
  std::string id;
  Json before;
  {
    ServerProcess server({}, {}, {{"CTB_DATA_DIR", data}});
    auto c = server.Client();
    int status = 0;
    Json started = Post(c, "/executions", RescueRequest(3, {{"adapter", "sim"}}), &status);
    ASSERT_EQ(status, 201) << started.dump();
    id = started["execution"];
    before = WaitFor(c, id, [](const Json& x) { return Count(x, "reported") >= 3 || Ended(x); });
    ASSERT_EQ(before["state"], "running") << "too fast to kill mid-way";
    server.Kill();
  }
  ServerProcess server({}, {}, {{"CTB_DATA_DIR", data}});
  auto c = server.Client();
  Json after = WaitFor(c, id, Ended);
  EXPECT_EQ(after["state"], "succeeded") << after.value("why", "");
  ExpectCarriedOnFrom(before, after);
  EXPECT_EQ(after["history"].size(), after["plan"]["transitions"].size());
  std::filesystem::remove_all(data);
}

// Learned durations: robot 2's drive to door 2 takes 10 s in the domain; reported after 0.5 s
// (a replan follows), GET /domains/search_rescue/durations counts it, and the suggested domain
// admits it ([0, 10] on the domain's 1 s grid) and is itself a valid domain (stored as a new one).
TEST(Executions, DurationsSeenAreCountedAndASuggestedDomainAdmitsThem) {
  ServerProcess server;
  auto c = server.Client();
  int status = 0;
  Json fast = Post(c, "/executions", RescueRequest(1, {{"adapter", "external"}}), &status);
  ASSERT_EQ(status, 201);
  const std::string id2 = fast["execution"];
  const std::string reports2 = "/executions/" + id2 + "/reports";
  WaitFor(c, id2, [](const Json& x) { return Count(x, "dispatched") >= 2; });
  Post(c, reports2, {{"automaton", "robot2"}, {"location", "goingToDoor2"}, {"time", 0}}, &status);
  ASSERT_EQ(status, 200);
  WaitFor(c, id2, [](const Json& x) { return x.value("now", 0.0) >= 0.5; });
  Json late = Post(c, reports2, {{"automaton", "robot2"}, {"location", "atDoor2"}, {"time", 0.5}}, &status);
  ASSERT_EQ(status, 200) << late.dump();
  auto stop2 = c.Delete(("/executions/" + id2).c_str());
  ASSERT_TRUE(stop2);

  Json d = Get(c, "/domains/search_rescue/durations");
  Json row;
  for (const auto& r : d["transitions"])
    if (r["automaton"] == "robot2" && r["from"] == "goingToDoor2") row = r;
  ASSERT_FALSE(row.is_null()) << d.dump();
  EXPECT_EQ(row["count"], 1);
  EXPECT_EQ(row["min"], 0.5);
  EXPECT_EQ(row["max"], 0.5);
  ASSERT_TRUE(d["suggested"].is_object()) << d.dump().substr(0, 500);
  bool widened = false;
  for (const auto& a : d["suggested"]["automata"])
    if (a["name"] == "robot2")
      for (const auto& t : a["transitions"])
        if (t["from"] == "goingToDoor2" && t["to"] == "atDoor2") {
          EXPECT_EQ(t["duration"], (Json{0, 10})) << t.dump();
          widened = true;
        }
  EXPECT_TRUE(widened);
  Json doc = d["suggested"];
  doc["name"] = "search_rescue_learned";
  Json created = Post(c, "/domains", doc, &status);
  EXPECT_EQ(status, 201) << created.dump().substr(0, 500);
  auto unknown = c.Get("/domains/nosuchdomain/durations");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 404);
}

// Two replicas on one redis-server (contract 14): an execution started on A goes on in B when A
// is killed (A's claim runs out after a second); every acknowledged report stays, no command is
// sent twice, and the run succeeds. While A lives, B shows the execution but does not carry it.
TEST(Executions, ASecondReplicaOnRedisTakesOverFromAKilledOne) {
  ASSERT_TRUE(testing::Executable("/usr/bin/redis-server")) << "bash scripts/install-deps.sh --test";
  const std::string dir = testing::TempDir("executions-redis");
  const int redis_port = testing::FreeLoopbackPort();
  pid_t redis = testing::Spawn({"/usr/bin/redis-server", "--port", std::to_string(redis_port), "--bind", "127.0.0.1",
                                "--save", "", "--appendonly", "no", "--dir", dir},
                               dir + "/redis.log");
  testing::StopAtExit stop_redis(redis);
  ASSERT_TRUE(testing::WaitForPort(redis_port, 5000)) << "redis-server did not start";
  const std::vector<std::string> store = {"--session-store", "redis://127.0.0.1:" + std::to_string(redis_port) + "/5"};
  const Json config = {{"execution_lease_ms", 1000}};
  std::string id;
  Json before;
  ServerProcess b(config, store);
  auto cb = b.Client();
  {
    ServerProcess a(config, store);
    auto ca = a.Client();
    int status = 0;
    Json started = Post(ca, "/executions", RescueRequest(4, {{"adapter", "sim"}}), &status);
    ASSERT_EQ(status, 201) << started.dump();
    id = started["execution"];
    before = WaitFor(ca, id, [](const Json& x) { return Count(x, "reported") >= 2 || Ended(x); });
    ASSERT_EQ(before["state"], "running") << "too fast to kill mid-way";
    Json seen = Get(cb, "/executions/" + id);
    EXPECT_EQ(seen["state"], "running") << "B sees it in the shared store";
    int status_b = 0;
    Post(cb, "/executions/" + id + "/reports", {{"automaton", "robot1"}, {"location", "x"}, {"time", 0}}, &status_b);
    EXPECT_EQ(status_b, 503) << "B does not carry it while A does";
    a.Kill();
  }
  Json after = WaitFor(cb, id, Ended);
  EXPECT_EQ(after["state"], "succeeded") << after.value("why", "");
  ExpectCarriedOnFrom(before, after);
  // Every transition of the plan carried out (a replan after the takeover may add observed
  // jumps, which are no transitions).
  std::size_t planned = 0;
  for (const auto& t : after["plan"]["transitions"]) planned += !t.value("observed", false);
  EXPECT_EQ(after["history"].size(), planned);
  testing::StopChild(redis);
  std::filesystem::remove_all(dir);
}

// A changed goal while it runs (contract 14): robot 1 alone to person 1 instead of both persons;
// the state plan is checked at its own pointers, the future is replanned from what happened
// (robot 2's move stays in the history), and a bad one is refused while the execution goes on.
TEST(Executions, AChangedGoalReplansFromWhatHappened) {
  ServerProcess server;
  auto c = server.Client();
  int status = 0;
  Json started = Post(c, "/executions", RescueRequest(1, {{"adapter", "external"}}), &status);
  ASSERT_EQ(status, 201) << started.dump();
  const std::string id = started["execution"];
  WaitFor(c, id, [](const Json& x) { return Count(x, "dispatched") >= 2; });
  Post(c, "/executions/" + id + "/reports", {{"automaton", "robot2"}, {"location", "goingToDoor2"}, {"time", 0}}, &status);
  ASSERT_EQ(status, 200);
  Json bad = Example("search_rescue/test2.json");
  bad["end_state"]["goal_constraint"] = "robot1l[i+1]==onTheMoon";
  auto r = c.Put(("/executions/" + id + "/state_plan").c_str(), bad.dump(), "application/json");
  ASSERT_TRUE(r);
  testing::Record("PUT", "/executions/" + id + "/state_plan", r);
  EXPECT_EQ(r->status, 400) << r->body;
  EXPECT_EQ(Json::parse(r->body)["error"]["path"], "/end_state/goal_constraint") << r->body;
  const Json goal = Example("search_rescue/test2.json");
  r = c.Put(("/executions/" + id + "/state_plan").c_str(), goal.dump(), "application/json");
  ASSERT_TRUE(r);
  testing::Record("PUT", "/executions/" + id + "/state_plan", r);
  EXPECT_EQ(r->status, 200) << r->body;
  Json v = WaitFor(c, id, [](const Json& x) { return x.value("replans", 0) >= 1 || Ended(x); });
  EXPECT_EQ(v["state"], "running") << v.value("why", "");
  Json replanned;
  for (const auto& e : v["events"])
    if (e["event"] == "replanned") replanned = e["data"];
  EXPECT_EQ(replanned.value("why", ""), "the state plan changed");
  bool robot2_kept = false, robot1_rescues = false;
  for (const auto& t : v["plan"]["transitions"]) {
    if (t["automaton"] == "robot2" && t["to"] == "goingToDoor2" && t.value("executed", false)) robot2_kept = true;
    if (t["automaton"] == "robot1" && t["to"] == "rescuedPerson1") robot1_rescues = true;
  }
  EXPECT_TRUE(robot2_kept) << "what happened stays";
  EXPECT_TRUE(robot1_rescues) << "the new goal is planned for";
  auto stop = c.Delete(("/executions/" + id).c_str());
  ASSERT_TRUE(stop);
  r = c.Put(("/executions/" + id + "/state_plan").c_str(), goal.dump(), "application/json");
  ASSERT_TRUE(r);
  WaitFor(c, id, Ended);
  r = c.Put(("/executions/" + id + "/state_plan").c_str(), goal.dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 409) << r->body;
}

TEST(Executions, BadRequestsAreRefusedAtTheirPointer) {
  ServerProcess server;
  auto c = server.Client();
  int status = 0;
  struct Bad {
    Json body;
    int status;
    std::string path;
  };
  const std::vector<Bad> bad = {
      {RescueRequest(1, {{"adapter", "pigeon"}}), 400, "/adapter"},
      {RescueRequest(0), 400, "/speed"},
      {RescueRequest(1, {{"adapter", "external"}, {"sim", {{"fail", 0.5}}}}), 400, "/sim"},
      {RescueRequest(1, {{"sim", {{"fail", 2}}}}), 400, "/sim/fail"},
      {RescueRequest(1, {{"adapter", "mqtt"}}), 503, "/adapter"},
      {{{"state_plan", Example("search_rescue/test1.json")}}, 400, "/domain"},
      {RescueRequest(1, {{"colour", "red"}}), 400, "/colour"},
  };
  for (const auto& b : bad) {
    Json err = Post(c, "/executions", b.body, &status);
    EXPECT_EQ(status, b.status) << b.body.dump().substr(0, 200) << " -> " << err.dump();
    EXPECT_EQ(err["error"].value("path", ""), b.path) << err.dump();
  }
  Json none = Post(c, "/executions", {{"domain", "search_rescue"}, {"state_plan",
                                       Example("search_rescue/impossible_door_shut_deadline.json")}}, &status);
  EXPECT_EQ(status, 422) << none.dump();
  auto missing = c.Get("/executions/0123456789abcdef");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
}

}  // namespace
}  // namespace executions_test
}  // namespace ctb
