// The /networks/check body: strict parsing with every error at its JSON pointer.
#include <gtest/gtest.h>

#include "planner/network/network_json.h"

namespace ctb::network {
namespace {

std::vector<std::string> Errors(const std::string& text) {
  Diagnostics d;
  std::optional<Json> j = ParseJsonStrict(text, d);
  if (j) {
    EXPECT_FALSE(ParseCheckBody(*j, d).has_value());
  }
  std::vector<std::string> out;
  for (const Diagnostic& e : d.errors()) out.push_back(e.ToString());
  return out;
}

bool Contains(const std::vector<std::string>& errors, const std::string& needle) {
  for (const std::string& e : errors) {
    if (e.find(needle) != std::string::npos) return true;
  }
  return false;
}

TEST(NetworkParse, ReadsTheContractExample) {
  Diagnostics d;
  const Json body = Json::parse(R"({"points": ["a", "b", "c"], "links": [
      {"from": "a", "to": "b", "lb": 1, "ub": 5, "contingent": true},
      {"from": "b", "to": "c", "lb": -2.5, "ub": null},
      {"from": "a", "to": "c", "lb": 0}]})");
  std::optional<Network> net = ParseCheckBody(body, d);
  ASSERT_TRUE(net) << d.errors()[0].ToString();
  ASSERT_EQ(net->links.size(), 3u);
  EXPECT_EQ(net->points[1].kind, PointKind::kContingent);
  EXPECT_EQ(net->links[0].ub, 5000);
  EXPECT_EQ(net->links[1].lb, -2500);
  EXPECT_FALSE(net->links[1].ub.has_value());
  EXPECT_FALSE(net->links[2].ub.has_value());
}

TEST(NetworkParse, UnknownPointSuggestsTheNearest) {
  const auto e = Errors(R"({"points": ["start", "end"], "links": [
      {"from": "start", "to": "edn", "lb": 0, "ub": 1}]})");
  EXPECT_TRUE(Contains(e, "/links/0/to: unknown point 'edn' (did you mean 'end'?)"));
}

TEST(NetworkParse, DuplicateNamesAndBadNames) {
  const auto e = Errors(R"({"points": ["a", "b", "a", 3, ""], "links": []})");
  EXPECT_TRUE(Contains(e, "/points/2: duplicate point name 'a' (first at /points/0)"));
  EXPECT_TRUE(Contains(e, "/points/3: expected a non-empty point name"));
  EXPECT_TRUE(Contains(e, "/points/4: expected a non-empty point name"));
}

TEST(NetworkParse, BoundsAreLocated) {
  const auto e = Errors(R"({"points": ["a", "b"], "links": [
      {"from": "a", "to": "b", "lb": 0, "ub": 1},
      {"from": "a", "to": "b", "lb": 0, "ub": 1},
      {"from": "a", "to": "b", "lb": 0, "ub": 1},
      {"from": "a", "to": "b", "lb": 0, "ub": "5"},
      {"from": "a", "to": "b", "lb": 1e300},
      {"from": "a", "to": "b", "lb": 0.0001},
      {"from": "a", "to": "b", "lb": 3, "ub": 2}]})");
  EXPECT_TRUE(Contains(e, "/links/3/ub: expected a number of seconds, got string"));
  EXPECT_TRUE(Contains(e, "/links/4/lb: expected a finite number"));
  EXPECT_TRUE(Contains(e, "/links/5/lb: expected a finite number"));
  EXPECT_TRUE(Contains(e, "/links/6/ub: ub is below lb"));
}

TEST(NetworkParse, ContingentRules) {
  const auto twice = Errors(R"({"points": ["a", "b", "c"], "links": [
      {"from": "a", "to": "b", "lb": 1, "ub": 2, "contingent": true},
      {"from": "c", "to": "b", "lb": 1, "ub": 2, "contingent": true}]})");
  EXPECT_TRUE(
      Contains(twice, "/links/1/to: the point is already the end of contingent link /links/0"));
  const auto e = Errors(R"({"points": ["a", "b", "c"], "links": [
      {"from": "a", "to": "b", "lb": 1, "ub": 2, "contingent": true},
      {"from": "a", "to": "c", "lb": -1, "ub": 2, "contingent": true},
      {"from": "b", "to": "a", "lb": 0, "contingent": true}]})");
  EXPECT_TRUE(Contains(e, "/links/1/lb: a contingent link needs lb >= 0"));
  EXPECT_TRUE(Contains(e, "/links/2/ub: a contingent link needs a finite ub"));
}

TEST(NetworkParse, ContingentCycle) {
  const auto e = Errors(R"({"points": ["a", "b"], "links": [
      {"from": "a", "to": "b", "lb": 1, "ub": 2, "contingent": true},
      {"from": "b", "to": "a", "lb": 1, "ub": 2, "contingent": true}]})");
  EXPECT_TRUE(Contains(e, "contingent links form a cycle"));
}

TEST(NetworkParse, StrictKeysAndShape) {
  EXPECT_TRUE(Contains(Errors(R"({"points": [], "links": [], "extra": 1})"), "/extra"));
  EXPECT_TRUE(Contains(
      Errors(R"({"points": ["a","b"], "links": [{"from": "a", "to": "b", "lb": 0, "weight": 1}]})"),
      "/links/0/weight"));
  EXPECT_TRUE(Contains(Errors(R"({"points": ["a","b"], "links": [{"from": "a", "to": "b"}]})"),
                       "/links/0/lb: missing required field"));
  EXPECT_TRUE(Contains(Errors(R"({"links": []})"), "/points: missing required field"));
  EXPECT_TRUE(Contains(Errors(R"({"points": ["a"], "links": {}})"), "/links: expected an array"));
  EXPECT_TRUE(
      Contains(Errors(R"({"points": ["a", "b"], "links": [{"from": "a", "to": "a", "lb": 0}]})"),
               "/links/0: a link from a point to itself"));
  EXPECT_TRUE(Contains(Errors(R"([1])"), "expected"));
}

TEST(NetworkParse, AnswerJson) {
  CheckResult r;
  r.consistent = true;
  r.conflict = {1, 2};
  const Json j = CheckResultToJson(r);
  EXPECT_EQ(j["conflict"], Json::array({1, 2}));
  EXPECT_FALSE(j["dynamic"].get<bool>());
  r.dynamic = r.strong = true;
  r.conflict.clear();
  EXPECT_FALSE(CheckResultToJson(r).contains("conflict"));
}

}  // namespace
}  // namespace ctb::network
