// Domains through the API (contract section 12) against real servers on loopback: create, read,
// replace and delete; a stored domain across a restart (SQLite) and across two replicas (a real
// redis-server); bad documents refused with pointers and nothing stored; a domain in use by a
// session kept unless forced; /solve, /plan and /replan with a stored domain; the diagram; drafts
// from words (the LLM is the loopback mock). Every answer is checked against server/openapi.json.
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "../translator/mock_llm.h"
#include "harness.h"

namespace ctb {
namespace {

using Clock = std::chrono::steady_clock;
using testing::MockLlmServer;
using testing::MockReply;
using testing::ServerProcess;

const auto* const kOpenApi = ::testing::AddGlobalTestEnvironment(new testing::OpenApiCheck);

Json ReadJson(const std::string& path) { return Json::parse(std::ifstream(path)); }
Json Drones() { return ReadJson(testing::SourceDir() + "/config/templates/drones.json"); }

// Two drones: drone 1 to A, drone 2 to B (the door opens in 3 s, take-off 5 s, flight 20 s).
Json DronesPlan() {
  return {{"initial_state", {{"drone1", "inHangar"}, {"drone2", "inHangar"}, {"hangarDoor", "closed"}}},
          {"end_state",
           {{"maintenance_constraint", "true"},
            {"goal_constraint", "drone1l[i+1]==atA /\\ drone2l[i+1]==atB"}}},
          {"constraints", {{"episodes", Json::object()}, {"temporal", Json::object()}, {"event", Json::object()}}}};
}

// A client whose answers are recorded for the OpenAPI check.
testing::RecordingClient Rc(const ServerProcess& s) {
  testing::RecordingClient c("127.0.0.1", s.port());
  c.set_read_timeout(120, 0);
  return c;
}

Json Body(const httplib::Result& r) { return Json::parse(r->body); }
Json ErrorOf(const httplib::Result& r) { return Body(r)["error"]; }

// The pointers of an error's details.
std::vector<std::string> Pointers(const httplib::Result& r) {
  std::vector<std::string> out;
  const Json error = ErrorOf(r);  // kept: a loop over a temporary's member would dangle
  for (const auto& d : error["details"]) out.push_back(d.value("path", ""));
  return out;
}

std::string Post(testing::RecordingClient& c, const std::string& path, const Json& body, int* status) {
  auto r = c.Post(path, body.dump(), "application/json");
  *status = r ? r->status : -1;
  return r ? r->body : "";
}

Json Find(const Json& list, const std::string& name) {
  for (const auto& d : list["domains"])
    if (d["name"] == name) return d;
  return nullptr;
}

TEST(Domains, CreateReadReplaceDeleteAndKeptAcrossARestart) {
  const std::string data = testing::TempDir("domains-crud");
  {
    ServerProcess s(Json::object(), {"--data-dir", data});
    auto c = Rc(s);
    auto created = c.Post("/domains", Drones().dump(), "application/json");
    ASSERT_EQ(created->status, 201) << created->body;
    EXPECT_EQ(Body(created)["name"], "drones");
    EXPECT_EQ(created->get_header_value("Location"), "/domains/drones");
    // As written: the template and its guard, not the expanded automata.
    auto got = c.Get("/domains/drones");
    ASSERT_EQ(got->status, 200);
    EXPECT_EQ(Body(got), Drones());
    Json list = Body(c.Get("/domains"));
    EXPECT_EQ(list["domains"].size(), 4u);
    Json item = Find(list, "drones");
    ASSERT_FALSE(item.is_null());
    EXPECT_EQ(item["source"], "stored");
    EXPECT_EQ(item["version"], 1);
    EXPECT_EQ(item["automata"], Json({"drone1", "drone2", "hangarDoor"}));
    EXPECT_EQ(Find(list, "presentation")["source"], "shipped");
    auto again = c.Post("/domains", Drones().dump(), "application/json");
    EXPECT_EQ(again->status, 409);
    // Four drones: one number changed.
    Json four = Drones();
    four["parameters"]["N"] = 4;
    auto put = c.Put("/domains/drones", four.dump(), "application/json");
    ASSERT_EQ(put->status, 200) << put->body;
    EXPECT_EQ(Find(Body(c.Get("/domains")), "drones")["automata"].size(), 5u);
    EXPECT_EQ(s.Stop(10000), 0);
  }
  ServerProcess s(Json::object(), {"--data-dir", data});
  auto c = Rc(s);
  Json item = Find(Body(c.Get("/domains")), "drones");
  ASSERT_FALSE(item.is_null()) << "a stored domain survives a restart";
  EXPECT_EQ(item["version"], 2);
  EXPECT_EQ(Body(c.Get("/domains/drones"))["parameters"]["N"], 4);
  EXPECT_EQ(c.Delete("/domains/drones")->status, 204);
  EXPECT_EQ(c.Get("/domains/drones")->status, 404);
  EXPECT_EQ(c.Delete("/domains/drones")->status, 404);
  EXPECT_EQ(c.Put("/domains/drones", Drones().dump(), "application/json")->status, 404);
  std::filesystem::remove_all(data);
}

TEST(Domains, BadDocumentsAreRefusedWithPointersAndNothingIsStored) {
  const std::string data = testing::TempDir("domains-bad");
  ServerProcess s(Json::object(), {"--data-dir", data});
  auto c = Rc(s);
  // A guard in the template that names a location no drone has: the template's own pointer,
  // the instance named.
  Json bad = Drones();
  bad["automata"][0]["transitions"][1]["guard"] = "{self}l[i]==nowhere";
  auto r = c.Post("/domains", bad.dump(), "application/json");
  ASSERT_EQ(r->status, 400) << r->body;
  auto ptrs = Pointers(r);
  ASSERT_FALSE(ptrs.empty());
  EXPECT_EQ(ptrs[0].rfind("/automata/0/transitions/1", 0), 0u) << r->body;
  EXPECT_NE(r->body.find("drone1"), std::string::npos) << "names the instance: " << r->body;
  EXPECT_EQ(c.Get("/domains/drones")->status, 404) << "nothing stored";
  // No name, a name that is not a route segment, a shipped name, a body that is not an object.
  Json unnamed = Drones();
  unnamed.erase("name");
  auto r2 = c.Post("/domains", unnamed.dump(), "application/json");
  EXPECT_EQ(r2->status, 400);
  EXPECT_EQ(Pointers(r2), std::vector<std::string>{"/name"});
  Json slash = Drones();
  slash["name"] = "a/b";
  EXPECT_EQ(Pointers(c.Post("/domains", slash.dump(), "application/json")), std::vector<std::string>{"/name"});
  Json shipped = Drones();
  shipped["name"] = "presentation";
  EXPECT_EQ(c.Post("/domains", shipped.dump(), "application/json")->status, 409);
  EXPECT_EQ(c.Put("/domains/presentation", shipped.dump(), "application/json")->status, 409);
  EXPECT_EQ(c.Delete("/domains/presentation")->status, 409);
  EXPECT_EQ(c.Get("/domains/presentation")->status, 200) << "the shipped domain is untouched";
  EXPECT_EQ(c.Post("/domains", "[1]", "application/json")->status, 400);
  // A transition listed twice (issue 30): refused at the second listing, in /domains and inline
  // in /solve alike, so no solve ever meets it.
  Json twice = Drones();
  twice["automata"][0]["transitions"].push_back(twice["automata"][0]["transitions"][1]);
  const std::string dup_ptr = "/automata/0/transitions/" +
                              std::to_string(twice["automata"][0]["transitions"].size() - 1);
  auto r4 = c.Post("/domains", twice.dump(), "application/json");
  ASSERT_EQ(r4->status, 400) << r4->body;
  ASSERT_FALSE(Pointers(r4).empty());
  for (const auto& ptr : Pointers(r4)) EXPECT_EQ(ptr, dup_ptr) << r4->body;  // one per instance
  EXPECT_NE(r4->body.find("the same transition as"), std::string::npos) << r4->body;
  EXPECT_EQ(c.Get("/domains/drones")->status, 404) << "nothing stored";
  // PUT: the document's name must be the path's; a bad document leaves the stored one.
  ASSERT_EQ(c.Post("/domains", Drones().dump(), "application/json")->status, 201);
  Json renamed = Drones();
  renamed["name"] = "other";
  auto r3 = c.Put("/domains/drones", renamed.dump(), "application/json");
  EXPECT_EQ(r3->status, 400);
  EXPECT_EQ(Pointers(r3), std::vector<std::string>{"/name"});
  EXPECT_EQ(c.Put("/domains/drones", bad.dump(), "application/json")->status, 400);
  EXPECT_EQ(Body(c.Get("/domains/drones")), Drones());
  EXPECT_EQ(c.Delete("/domains/drones?force=maybe")->status, 400);
  std::filesystem::remove_all(data);
}

TEST(Domains, AStoredDomainSolvesPlansReplansAndIsKeptWhileASessionUsesIt) {
  const std::string data = testing::TempDir("domains-use");
  MockLlmServer m;
  m.Then(MockReply::Chat(DronesPlan().dump()));
  ServerProcess s(Json::object(), {"--data-dir", data},
                  {{"CTB_LLM_BASE_URL", m.BaseUrl()}, {"CTB_LLM_MODEL", "mock"}});
  auto c = Rc(s);
  ASSERT_EQ(c.Post("/domains", Drones().dump(), "application/json")->status, 201);
  Json solve = {{"domain", "drones"}, {"state_plan", DronesPlan()}, {"options", {{"objective", "makespan"}}}};
  auto solved = c.Post("/solve", solve.dump(), "application/json");
  ASSERT_EQ(solved->status, 200) << solved->body;
  Json t = Body(solved);
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["verified"], true);
  EXPECT_EQ(t["goal_reached_at"], 28) << "door 3 s, take-off 5 s, flight 20 s";
  Json replan = {{"domain", "drones"}, {"state_plan", DronesPlan()}, {"trajectory", t}, {"now", 0},
                 {"options", {{"objective", "makespan"}}}};
  auto re = c.Post("/replan", replan.dump(), "application/json");
  ASSERT_EQ(re->status, 200) << re->body;
  EXPECT_EQ(Body(re)["goal_reached_at"], 28);
  // /plan: the prompt is built from the stored domain.
  Json plan = {{"domain", "drones"}, {"command", "drone 1 to A and drone 2 to B"}, {"prompting", "direct"}};
  auto p = c.Post("/plan", plan.dump(), "application/json");
  ASSERT_EQ(p->status, 200) << p->body;
  const std::string session = Body(p)["session"];
  ASSERT_EQ(m.Requests().size(), 1u);
  const std::string prompt = m.Requests()[0].body["messages"].dump();
  EXPECT_NE(prompt.find("hangarDoor"), std::string::npos) << "the prompt describes the stored domain";
  auto busy = c.Delete("/domains/drones");
  EXPECT_EQ(busy->status, 409);
  EXPECT_NE(ErrorOf(busy)["message"].get<std::string>().find("force"), std::string::npos);
  EXPECT_EQ(c.Delete("/domains/drones?force=true")->status, 204);
  EXPECT_EQ(c.Post("/solve", solve.dump(), "application/json")->status, 404);
  std::filesystem::remove_all(data);
}

TEST(Domains, TheDiagramNamesEveryAutomatonAndLocation) {
  const std::string data = testing::TempDir("domains-diagram");
  ServerProcess s(Json::object(), {"--data-dir", data});
  auto c = Rc(s);
  ASSERT_EQ(c.Post("/domains", Drones().dump(), "application/json")->status, 201);
  auto d = c.Get("/domains/drones/diagram");
  ASSERT_EQ(d->status, 200);
  EXPECT_EQ(d->get_header_value("Content-Type"), "image/svg+xml");
  EXPECT_EQ(d->body.rfind("<svg", 0), 0u);
  for (const char* name : {"drone1", "drone2", "hangarDoor"})
    EXPECT_NE(d->body.find(std::string(">automaton ") + name + "<"), std::string::npos) << name;
  for (const char* name : {"inHangar", "flyingToA", "atB", "opening"})
    EXPECT_NE(d->body.find(std::string(">") + name + "<"), std::string::npos) << name;
  EXPECT_EQ(c.Get("/domains/presentation/diagram")->status, 200);
  EXPECT_EQ(c.Get("/domains/nosuch/diagram")->status, 404);
  std::filesystem::remove_all(data);
}

std::string Recording(const std::string& name) {
  std::ifstream in(testing::SourceDir() + "/tests/recordings/draft/" + name);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(Domains, DraftsFromWordsAreCheckedRepairedAndNeverStored) {
  const std::string data = testing::TempDir("domains-draft");
  MockLlmServer m;
  m.Then(MockReply::Chat(Recording("good.txt")));
  for (int i = 0; i < 3; ++i) m.Then(MockReply::Chat(Recording("broken.txt")));
  ServerProcess s(Json::object(), {"--data-dir", data},
                  {{"CTB_LLM_BASE_URL", m.BaseUrl()}, {"CTB_LLM_MODEL", "mock"}});
  auto c = Rc(s);
  const Json ask = {{"description", "two drones that take off in 5 s and fly to A or B in 20 s; "
                                    "the hangar door must be open to take off"}};
  int status = 0;
  Json good = Json::parse(Post(c, "/domains/draft", ask, &status));
  ASSERT_EQ(status, 200) << good.dump();
  EXPECT_FALSE(good["restatement"].get<std::string>().empty());
  EXPECT_TRUE(good["questions"].is_array());
  const std::string name = good["action_model"]["name"];
  EXPECT_EQ(c.Get("/domains/" + name)->status, 404) << "a draft is not stored";
  // Accepting it is a POST of the model.
  EXPECT_EQ(c.Post("/domains", good["action_model"].dump(), "application/json")->status, 201);
  // A draft that stays broken after the repairs: 422 with every error, under /action_model.
  auto broken = c.Post("/domains/draft", ask.dump(), "application/json");
  ASSERT_EQ(broken->status, 422) << broken->body;
  ASSERT_FALSE(Pointers(broken).empty());
  for (const auto& p : Pointers(broken)) EXPECT_EQ(p.rfind("/action_model", 0), 0u) << p;
  EXPECT_EQ(m.Requests().size(), 4u) << "one draft and two repairs";
  const std::string repair = m.Requests()[2].body["messages"].dump();
  EXPECT_NE(repair.find(": "), std::string::npos);
  EXPECT_EQ(c.Post("/domains/draft", Json({{"description", ""}}).dump(), "application/json")->status, 400);
  EXPECT_EQ(c.Post("/domains/draft", Json({{"text", "x"}}).dump(), "application/json")->status, 400);
  std::filesystem::remove_all(data);
}

TEST(Domains, ReplicasSharingRedisSeeTheSameDomains) {
  ASSERT_TRUE(testing::Executable("/usr/bin/redis-server")) << "bash scripts/install-deps.sh --test";
  const std::string dir = testing::TempDir("domains-replicas");
  const int redis_port = testing::FreeLoopbackPort();
  pid_t redis = testing::Spawn({"/usr/bin/redis-server", "--port", std::to_string(redis_port), "--bind",
                                "127.0.0.1", "--save", "", "--appendonly", "no", "--dir", dir},
                               dir + "/redis.log");
  testing::StopAtExit stop_redis(redis);
  ASSERT_TRUE(testing::WaitForPort(redis_port, 5000)) << "redis-server did not start";
  const std::string store = "redis://127.0.0.1:" + std::to_string(redis_port) + "/2";
  {
    ServerProcess a(Json::object(), {"--session-store", store});
    ServerProcess b(Json::object(), {"--session-store", store});
    auto ca = Rc(a);
    auto cb = Rc(b);
    ASSERT_EQ(ca.Post("/domains", Drones().dump(), "application/json")->status, 201);
    EXPECT_EQ(cb.Post("/domains", Drones().dump(), "application/json")->status, 409);
    EXPECT_EQ(Body(cb.Get("/domains/drones")), Drones());
    Json solve = {{"domain", "drones"}, {"state_plan", DronesPlan()}, {"options", {{"objective", "makespan"}}}};
    auto solved = cb.Post("/solve", solve.dump(), "application/json");
    ASSERT_EQ(solved->status, 200) << solved->body;
    EXPECT_EQ(Body(solved)["goal_reached_at"], 28);
    Json four = Drones();
    four["parameters"]["N"] = 4;
    ASSERT_EQ(cb.Put("/domains/drones", four.dump(), "application/json")->status, 200);
    EXPECT_EQ(Find(Body(ca.Get("/domains")), "drones")["version"], 2);
    EXPECT_EQ(ca.Delete("/domains/drones")->status, 204);
    EXPECT_EQ(cb.Get("/domains/drones")->status, 404);
  }
  testing::StopChild(redis);
  std::filesystem::remove_all(dir);
}


std::string ReadText(const std::string& path) {
  std::ifstream f(path);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

// PDDL through the API (issue 32 item 5): the search and rescue domain and problem imported, solved
// to the shipped optimum (11 s, tests/interchange/pddl_import_test.cpp) inline and once stored;
// the CLI's import of the same files is the same model; problems at /domain or /problem with the
// offset of their line.
TEST(Domains, PddlImportsOverHttpAndTheModelSolvesToTheShippedOptimum) {
  const std::string dir = testing::SourceDir() + "/tests/interchange/pddl/";
  const std::string domain = ReadText(dir + "search_rescue_domain.pddl");
  const std::string problem = ReadText(dir + "search_rescue_problem.pddl");
  ServerProcess s(Json::object(), {"--data-dir", testing::TempDir("domains-pddl")});
  auto c = Rc(s);
  int status = 0;
  Json a = Json::parse(Post(c, "/domains/import-pddl", {{"domain", domain}, {"problem", problem}}, &status));
  ASSERT_EQ(status, 200) << a.dump();
  EXPECT_EQ(a["stored"], false);
  EXPECT_GT(a["ground_actions"].get<int>(), 0);
  EXPECT_FALSE(a["actions"].empty());
  // The CLI gives the same model (both go through the core).
  const std::string out = testing::TempDir("domains-pddl-cli") + "/model.json";
  const std::string cmd = std::string(CTB_BINARY) + " domain import-pddl " + dir + "search_rescue_domain.pddl " + dir +
                          "search_rescue_problem.pddl -o " + out + " > /dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  EXPECT_EQ(ReadJson(out), a["action_model"]);
  // Solved inline, and by name once stored.
  Json solve = {{"action_model", a["action_model"]}, {"state_plan", a["state_plan"]}};
  Json t = Json::parse(Post(c, "/solve", solve, &status));
  ASSERT_EQ(status, 200) << t.dump();
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["objective"]["value"], 11);
  Json stored = Json::parse(Post(c, "/domains/import-pddl",
                                 {{"domain", domain}, {"problem", problem}, {"name", "rescue_pddl"}, {"store", true}}, &status));
  ASSERT_EQ(status, 201) << stored.dump();
  EXPECT_EQ(stored["stored"], true);
  EXPECT_EQ(Body(c.Get("/domains/rescue_pddl")), stored["action_model"]);
  Json by_name = Json::parse(Post(c, "/solve", {{"domain", "rescue_pddl"}, {"state_plan", stored["state_plan"]}}, &status));
  ASSERT_EQ(status, 200) << by_name.dump();
  EXPECT_EQ(by_name["objective"]["value"], 11);
  Post(c, "/domains/import-pddl", {{"domain", domain}, {"problem", problem}, {"name", "rescue_pddl"}, {"store", true}}, &status);
  EXPECT_EQ(status, 409) << "the name is taken";
  // A problem in the domain text: at /domain, the offset of its line and column.
  std::string broken = domain;
  const std::size_t at = broken.find("(:durative-action");
  ASSERT_NE(at, std::string::npos);
  broken.insert(at, "(:frobnicate)\n");
  auto r = c.Post("/domains/import-pddl", Json({{"domain", broken}}).dump(), "application/json");
  ASSERT_EQ(r->status, 400) << r->body;
  Json d = ErrorOf(r)["details"][0];
  EXPECT_EQ(d["path"], "/domain");
  ASSERT_TRUE(d.contains("offset")) << r->body;
  EXPECT_EQ(broken.compare(d["offset"].get<std::size_t>(), 13, "(:frobnicate)"), 0) << r->body;
  // A problem in the problem text: at /problem.
  std::string bad_problem = problem;
  bad_problem.replace(bad_problem.find("(at robot1 outside)"), 19, "(at robot9 outside)");
  r = c.Post("/domains/import-pddl", Json({{"domain", domain}, {"problem", bad_problem}}).dump(), "application/json");
  ASSERT_EQ(r->status, 400) << r->body;
  EXPECT_EQ(Pointers(r)[0], "/problem") << r->body;
  // Bad requests.
  r = c.Post("/domains/import-pddl", Json({{"domain", 5}}).dump(), "application/json");
  ASSERT_EQ(r->status, 400);
  EXPECT_EQ(Pointers(r)[0], "/domain");
  r = c.Post("/domains/import-pddl", Json({{"problem", problem}}).dump(), "application/json");
  ASSERT_EQ(r->status, 400);
  EXPECT_EQ(Pointers(r)[0], "/domain");
  r = c.Post("/domains/import-pddl", Json({{"domain", domain}, {"store", "yes"}}).dump(), "application/json");
  ASSERT_EQ(r->status, 400);
  EXPECT_EQ(Pointers(r)[0], "/store");
  r = c.Post("/domains/import-pddl", Json({{"domain", domain}, {"extra", 1}}).dump(), "application/json");
  EXPECT_EQ(r->status, 400);
}


// The request budget counts the model as loaded, templates expanded (found by the domain fuzz
// target, tests/fuzz/domain/regressions/template_expands_past_budget): the shipped rescue team
// with 77 robots is 3 automata as written and 80 once expanded, over the 64 allowed.
TEST(Domains, TheBudgetCountsTheModelAfterItsTemplatesAreExpanded) {
  ServerProcess s(Json::object(), {"--data-dir", testing::TempDir("domains-expanded")});
  auto c = Rc(s);
  Json team = ReadJson(testing::SourceDir() + "/config/templates/search_rescue_team.json");
  team["parameters"]["N"] = 77;
  team["name"] = "big_team";
  auto r = c.Post("/domains", team.dump(), "application/json");
  ASSERT_EQ(r->status, 413) << r->body;
  EXPECT_NE(ErrorOf(r)["message"].get<std::string>().find("after expanding templates"), std::string::npos) << r->body;
  EXPECT_EQ(ErrorOf(r)["limit"]["name"], "max_automata") << r->body;
  EXPECT_EQ(c.Get("/domains/big_team")->status, 404) << "nothing stored";
  r = c.Post("/solve", Json({{"action_model", team}, {"state_plan", DronesPlan()}}).dump(), "application/json");
  ASSERT_EQ(r->status, 413) << r->body;
  EXPECT_EQ(Pointers(r)[0], "/action_model/automata");
  // Within the budget once expanded: stored.
  team["parameters"]["N"] = 4;
  EXPECT_EQ(c.Post("/domains", team.dump(), "application/json")->status, 201);
}

}  // namespace
}  // namespace ctb
