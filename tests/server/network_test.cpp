// POST /networks/check against the real server binary (contract section 13): answers, located
// errors, and the 4 MiB body limit of this route (other routes keep max_body_bytes). Answers are
// recorded for the OpenAPI check of server_test.cpp.
#include <gtest/gtest.h>

#include <string>

#include "harness.h"

namespace ctb {
namespace {

class NetServer : public ctb::testing::ServerProcess {
 public:
  explicit NetServer(Json config = Json::object()) : ServerProcess(std::move(config), {}, {}, "") {}
  ctb::testing::RecordingClient Client() const {
    ctb::testing::RecordingClient c("127.0.0.1", port());
    c.set_read_timeout(60, 0);
    return c;
  }
};

// POST /solve with an uncertain action model (contract section 13): the search among plans
// through the service. Both robots at door 1: the 3 s plan (arrivals tied) is cut, the 4 s plan
// is dynamically controllable; within 1 s of each other: none is (within 8 events), infeasible
// with an explanation from the controllability conflicts (tests/planner/controllable_search_test
// derives both). The answers are recorded for the OpenAPI check.
TEST(NetworkService, SolvesSearchAmongPlansThroughTheService) {
  NetServer s;
  auto c = s.Client();
  Diagnostics diags;
  auto model = ReadJsonFile(std::string(CTB_TEST_SOURCE_DIR) + "/config/uncertain/search_rescue.json", diags);
  auto together = ReadJsonFile(
      std::string(CTB_TEST_SOURCE_DIR) + "/config/uncertain/rescue_arrive_together.json", diags);
  ASSERT_TRUE(model && together);
  Json both = *together;
  both["constraints"]["temporal"] = Json::object();
  Json body = {{"action_model", *model}, {"state_plan", both}, {"options", {{"max_horizon", 8}}}};
  auto r = c.Post("/solve", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  Json a = Json::parse(r->body);
  EXPECT_EQ(a["status"], "optimal") << r->body;
  EXPECT_EQ(a["objective"]["value"], 4);
  EXPECT_GE(a["controllability"]["search"]["plans_cut"], 1);

  body["state_plan"] = *together;
  r = c.Post("/solve", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  a = Json::parse(r->body);
  EXPECT_EQ(a["status"], "infeasible") << r->body;
  EXPECT_EQ(a["explanation"]["status"], "controllability") << a["explanation"].dump();
  EXPECT_FALSE(a["explanation"]["relaxations"].empty());
}

// A ==[1,3]==> C, C -[0,1]-> B: dynamic (B when C is seen), not strong (tests/planner/
// network_check_test.cpp derives it); with C -[-2,-1]-> B instead, not dynamic: conflict [0, 1].
TEST(NetworkService, AnswersTheCheck) {
  NetServer s;
  auto c = s.Client();
  Json body = {{"points", {"A", "B", "C"}},
               {"links",
                {{{"from", "A"}, {"to", "C"}, {"lb", 1}, {"ub", 3}, {"contingent", true}},
                 {{"from", "C"}, {"to", "B"}, {"lb", 0}, {"ub", 1}},
                 {{"from", "A"}, {"to", "B"}, {"lb", 0}, {"ub", nullptr}}}}};
  auto r = c.Post("/networks/check", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  Json a = Json::parse(r->body);
  EXPECT_EQ(a["consistent"], true);
  EXPECT_EQ(a["strong"], false);
  EXPECT_EQ(a["dynamic"], true);
  EXPECT_FALSE(a.contains("conflict"));
  EXPECT_TRUE(a["ms"].is_number());

  body["links"][1]["lb"] = -2;
  body["links"][1]["ub"] = -1;
  r = c.Post("/networks/check", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  a = Json::parse(r->body);
  EXPECT_EQ(a["dynamic"], false);
  EXPECT_EQ(a["conflict"], Json::array({0, 1}));
}

TEST(NetworkService, LocatedErrors) {
  NetServer s;
  auto c = s.Client();
  Json body = {{"points", {"start", "end"}},
               {"links",
                {{{"from", "start"}, {"to", "edn"}, {"lb", 0}},
                 {{"from", "start"}, {"to", "end"}, {"lb", 2}, {"ub", 1}}}}};
  auto r = c.Post("/networks/check", body.dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  Json e = Json::parse(r->body)["error"];
  EXPECT_EQ(e["code"], "invalid_input");
  EXPECT_EQ(e["path"], "/links/0/to") << r->body;
  EXPECT_NE(r->body.find("did you mean 'end'"), std::string::npos) << r->body;
  EXPECT_NE(r->body.find("/links/1/ub"), std::string::npos) << r->body;
}

// A chain of 10,000 points with names padded to make a body above 1 MiB (the default
// max_body_bytes) and below 4 MiB: accepted here; the same bytes on /validate: 413; beyond 4 MiB on
// this route: 413.
TEST(NetworkService, BodiesUpToFourMiB) {
  NetServer s;
  auto c = s.Client();
  Json points = Json::array(), links = Json::array();
  const int n = 10000;
  for (int i = 0; i < n; ++i) points.push_back("point-" + std::to_string(i) + std::string(40, 'x'));
  for (int i = 0; i + 1 < n; ++i) {
    links.push_back({{"from", points[i]},
                     {"to", points[i + 1]},
                     {"lb", 1},
                     {"ub", 5},
                     {"contingent", i % 4 == 0}});
  }
  const std::string text = Json({{"points", points}, {"links", links}}).dump();
  ASSERT_GT(text.size(), std::size_t{1} << 20);
  ASSERT_LT(text.size(), std::size_t{4} << 20);
  auto r = c.Post("/networks/check", text, "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body.substr(0, 300);
  Json a = Json::parse(r->body);
  EXPECT_EQ(a["dynamic"], true);
  EXPECT_EQ(a["strong"], true);
  EXPECT_LT(a["ms"].get<double>(), 10000);

  // Refused from the declared length, before any byte of the body is read.
  auto head = [](const std::string& path, std::size_t length) {
    return "POST " + path +
           " HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
           "Content-Length: " +
           std::to_string(length) + "\r\nConnection: close\r\n\r\n";
  };
  EXPECT_EQ(ctb::testing::RawRequest(s.port(), head("/validate", text.size())).status, 413);
  EXPECT_EQ(ctb::testing::RawRequest(s.port(), head("/networks/check", (4 << 20) + 1)).status, 413);
}

}  // namespace
}  // namespace ctb
