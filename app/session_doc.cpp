#include "app/session_doc.h"

#include <ctime>

#include "app/document_store.h"
#include "app/store_common.h"

namespace ctb::app {

using store::NowMs;

namespace {

std::string Iso8601(long ms) {
  std::time_t secs = static_cast<std::time_t>(ms / 1000);
  std::tm tm{};
  gmtime_r(&secs, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  char out[40];
  std::snprintf(out, sizeof out, "%s.%03ldZ", buf, ms % 1000);
  return out;
}

}  // namespace

Json NewSessionDoc(const std::string& domain) {
  return {{"domain", domain}, {"conversation", Json::array()}, {"state_plan", nullptr}, {"turns", Json::array()}};
}

Session SessionFromDoc(const Json& doc) {
  Session s;
  if (!doc.is_object()) return s;
  s.domain = doc.value("domain", "");
  if (auto c = doc.find("conversation"); c != doc.end() && c->is_array())
    for (const auto& m : *c)
      if (m.is_object()) s.conversation.push_back({m.value("role", ""), m.value("content", "")});
  if (auto p = doc.find("state_plan"); p != doc.end()) s.state_plan = *p;
  return s;
}

void UpdateSessionDoc(Json& doc, const std::vector<ChatMessage>& conversation, const Json& state_plan,
                      const Json& turn) {
  Json conv = Json::array();
  for (const auto& m : conversation) conv.push_back({{"role", m.role}, {"content", m.content}});
  doc["conversation"] = conv;
  doc["state_plan"] = state_plan;
  if (turn.contains("trajectory")) {
    doc["trajectory"] = turn["trajectory"];  // the plan being executed, for /replan
  }
  if (!doc.contains("turns") || !doc["turns"].is_array()) doc["turns"] = Json::array();
  Json recorded = turn;
  recorded.erase("trajectory");
  doc["turns"].push_back(recorded);
}

Json TurnRecord(const Json& command, const std::string& reasoning, const Json& state_plan, const Json& trajectory) {
  Json summary = Json::object();
  for (const char* k : {"status", "objective", "horizon", "goal_reached_at", "verified"})
    if (trajectory.is_object() && trajectory.contains(k)) summary[k] = trajectory[k];
  Json turn = {{"command", command}, {"reasoning", reasoning}, {"state_plan", state_plan},
               {"trajectory_summary", summary}, {"at", Iso8601(NowMs())}};
  if (trajectory.is_object() && trajectory.contains("transitions")) turn["trajectory"] = trajectory;
  return turn;
}

Json SessionView(const StoredDocument& s) {
  Json turns = s.doc.is_object() && s.doc.contains("turns") && s.doc["turns"].is_array() ? s.doc["turns"] : Json::array();
  return {{"session", s.id}, {"domain", s.doc.is_object() ? s.doc.value("domain", "") : ""}, {"turns", turns},
          {"created", Iso8601(s.created_ms)}, {"updated", Iso8601(s.updated_ms)}};
}

}  // namespace ctb::app
