// Where dialogue sessions live (issue 13): an interface and two implementations, SQLite (the
// embedded default, one file in the data directory, WAL) and Redis (shared by several replicas).
//
// A session is one JSON document with a version. Updates are optimistic: Update() writes only if
// the stored version is the one read, so two follow-ups racing on one session cannot lose a turn
// (the loser gets kConflict and the service answers 409). The cap (max_sessions) and idle expiry
// (session_idle_s since the last write) behave the same on both stores. Ids are made by the
// caller (server/ids.h, 128 random bits).
//
// Thread-safe: each store serialises its calls on one connection. Never throws; a store that
// cannot be reached gives kUnavailable.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "planner/model/error.h"
#include "planner/model/json_io.h"

namespace ctb::app {

struct StoredSession {
  std::string id;
  long version = 0;        // set by the store: 1 on creation, +1 per update
  long created_ms = 0;     // Unix time
  long updated_ms = 0;
  // {"domain", "conversation": [{"role", "content"}], "state_plan", "turns": [...]}.
  Json doc = Json::object();
};

enum class StoreResult { kOk, kConflict, kFull, kNotFound, kUnavailable };

class SessionStore {
 public:
  virtual ~SessionStore() = default;
  // The session, nullopt when unknown or expired, or an Error (kUnavailable) when the store fails.
  virtual std::variant<std::optional<StoredSession>, Error> Get(const std::string& id) = 0;
  // kFull when max_sessions live sessions exist.
  virtual StoreResult Create(StoredSession& s) = 0;
  // Writes s.doc if the stored version is still s.version; s.version is advanced on kOk.
  virtual StoreResult Update(StoredSession& s) = 0;
  virtual StoreResult Delete(const std::string& id) = 0;
  // Live sessions (expired ones are dropped first); -1 when the store fails.
  virtual long Count() = 0;
  // Live sessions whose document's "domain" is `domain`; -1 when the store fails. Used to refuse
  // deleting a domain in use (contract section 12); a session created meanwhile is not seen.
  virtual long CountUsing(const std::string& domain) = 0;
  // The ids of live documents, oldest first (executions resumed at start-up).
  virtual std::variant<std::vector<std::string>, Error> List() = 0;
  virtual std::string Describe() const = 0;  // for the start-up log, no secrets
  // The backend's words for the last failure ("database or disk is full"); "" when unknown.
  virtual std::string LastError() const { return {}; }
  // A small write that changes no document (a heartbeat row or key): false when it fails. Tells
  // /healthz whether a store that failed to write writes again.
  virtual bool Probe() = 0;
};

struct SessionStoreConfig {
  std::string url;        // "" or "sqlite" (the default): SQLite in data_dir; "redis://host:port/db"
  std::string data_dir = "./data";
  long max_sessions = 1000;
  long idle_s = 1800;
  // What the store keeps: "session" (table sessions, keys ctb:session:<id>) or "execution".
  std::string kind = "session";
};

// Opens (and creates) the store, or an Error naming what failed.
std::variant<std::unique_ptr<SessionStore>, Error> OpenSessionStore(const SessionStoreConfig& c);

// Reads "redis://host:port/db" (host defaults to 127.0.0.1, port 6379, db 0); an Error
// (kInvalidInput) for anything else.
std::optional<Error> ParseRedisUrl(const std::string& url, std::string& host, int& port, int& db);

std::unique_ptr<SessionStore> OpenSqliteStore(const std::string& path, long max_sessions, long idle_s,
                                              std::string& error, const std::string& table = "sessions");
std::unique_ptr<SessionStore> OpenRedisStore(const std::string& host, int port, int db, long max_sessions,
                                             long idle_s, std::string& error,
                                             const std::string& kind = "session");

}  // namespace ctb::app
