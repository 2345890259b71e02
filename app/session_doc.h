// The stored form of a dialogue session (a JSON document in the session store) and the views of
// it the routes answer with. Pure functions; never throw on a well-formed document, and tolerate
// missing fields (a document written by an older version).
//
// doc = {"domain", "conversation": [{"role", "content"}], "state_plan", "trajectory"?,
//        "turns": [{"command", "reasoning", "state_plan", "trajectory_summary", "at", "replan"?}]}
// "trajectory" is the session's current plan (the last turn's, when it has one): what /replan
// replans by default.
#pragma once

#include <string>
#include <vector>

#include "planner/model/json_io.h"
#include "translator/llm.h"

namespace ctb::app {

// What a follow-up needs from the session.
struct Session {
  std::string domain;
  std::vector<ChatMessage> conversation;
  Json state_plan;
};

Json NewSessionDoc(const std::string& domain);
Session SessionFromDoc(const Json& doc);
// Replaces the conversation and current state plan, and appends the turn; a turn's
// "trajectory" (TurnRecord keeps the whole plan there) becomes the session's current plan and is
// not stored in the turn itself.
void UpdateSessionDoc(Json& doc, const std::vector<ChatMessage>& conversation, const Json& state_plan,
                      const Json& turn);
// One turn: the command, reasoning, state plan, a summary of the trajectory (status, objective,
// horizon, goal_reached_at, verified) and the time (ISO 8601 UTC).
Json TurnRecord(const Json& command, const std::string& reasoning, const Json& state_plan, const Json& trajectory);

struct StoredDocument;
// GET /sessions/{id}: {"session", "domain", "turns", "created", "updated"}.
Json SessionView(const StoredDocument& s);

}  // namespace ctb::app
