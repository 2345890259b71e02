// Where the service keeps its versioned JSON documents (issues 13, 22, 31): dialogue sessions,
// domains created through the API and executions. One interface, two backends: SQLite (the
// embedded default, <data_dir>/sessions.db in WAL mode; "memory" for the CLI's local mode) and
// Redis (shared by several replicas). Each kind of document has its own table or key space of the
// same backend:
//
//   SQLite  table <kind>s(<key>, version, created_ms, updated_ms, doc); <key> is "name" for
//           domains and "id" for the others (the layout of the stores this one replaces).
//   Redis   hash ctb:<kind>:<id> -> version, created_ms, updated_ms, doc, and the index
//           ctb:<kind>s: a sorted set of ids by last write when the kind expires (the hash then
//           has an EXPIRE of the idle time), a set of ids when it never expires. Every write is a
//           Lua script, so it is atomic across replicas.
//
// Writes are optimistic: Update() writes only if the stored version is the one read, so two
// follow-ups racing on one session cannot lose a turn (the loser gets kConflict). The cap (max)
// and the idle expiry (idle_s since the last write) behave the same on both backends. Ids are made
// by the caller.
//
// Thread-safe: each store serialises its calls on one connection. Never throws; a store that
// cannot be reached gives kUnavailable (an Error, -1 or StoreResult::kUnavailable).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "planner/model/error.h"
#include "planner/model/json_io.h"

namespace ctb::app {

struct StoredDocument {
  std::string id;       // a session or execution id, a domain's name
  long version = 0;     // set by the store: 1 on creation, +1 per write
  long created_ms = 0;  // Unix time
  long updated_ms = 0;
  Json doc = Json::object();
};

enum class StoreResult { kOk, kConflict, kFull, kNotFound, kUnavailable };

class DocumentStore {
 public:
  virtual ~DocumentStore() = default;
  // The document, nullopt when unknown or expired, or an Error (kUnavailable) when the store fails.
  virtual std::variant<std::optional<StoredDocument>, Error> Get(const std::string& id) = 0;
  // kConflict when the id exists, kFull when `max` live documents exist. Sets version and times.
  virtual StoreResult Create(StoredDocument& d) = 0;
  // Writes d.doc if the document exists and, unless any_version, its stored version is still
  // d.version (kConflict otherwise); kNotFound when unknown or expired. On kOk d.version is the
  // new version.
  virtual StoreResult Write(StoredDocument& d, bool any_version) = 0;
  StoreResult Update(StoredDocument& d) { return Write(d, false); }  // compare-and-set
  StoreResult Replace(StoredDocument& d) { return Write(d, true); }  // whatever was stored
  virtual StoreResult Delete(const std::string& id) = 0;
  // Live documents (expired ones are dropped first); -1 when the store fails.
  virtual long Count() = 0;
  // Live documents whose top-level member `field` is the string `value`; -1 when the store fails.
  // CountWhere("domain", name) refuses deleting a domain sessions use (contract section 12); a
  // document written meanwhile is not seen.
  virtual long CountWhere(const std::string& field, const std::string& value) = 0;
  // The ids of live documents: oldest first when the kind expires (SQLite: by creation; Redis: by
  // last write), sorted when it does not.
  virtual std::variant<std::vector<std::string>, Error> List() = 0;
  // The backend's words for the last failure ("database or disk is full"); "" when unknown.
  virtual std::string LastError() const = 0;
  // A small write that changes no document (a heartbeat row or key): false when it fails. Tells
  // /healthz whether a store that failed to write writes again.
  virtual bool Probe() = 0;
};

struct DocumentStoreConfig {
  std::string url;  // "" or "sqlite" (the default), "memory", "redis://host:port/db"
  std::string data_dir = "./data";
  std::string kind = "session";  // "session", "execution" or "domain": its table and keys
  long max = 1000;               // live documents at most
  long idle_s = 0;               // dropped this long after the last write; 0: never
};

// Opens (and creates) the store, or an Error naming what failed (kInvalidInput for a bad URL,
// kUnavailable otherwise).
std::variant<std::unique_ptr<DocumentStore>, Error> OpenDocumentStore(const DocumentStoreConfig& c);

// Reads "redis://host:port/db" (host defaults to 127.0.0.1, port 6379, db 0); an Error
// (kInvalidInput) for anything else.
std::optional<Error> ParseRedisUrl(const std::string& url, std::string& host, int& port, int& db);

}  // namespace ctb::app
