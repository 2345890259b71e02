// Storage faults survived (issue 30 item 3). The rule: a request the service acknowledged is
// never lost; when it cannot store, it says so (a 503 naming the store and the reason), goes on
// serving what needs no storage (/solve, health), and recovers by itself when storage comes back.
//
// - StorageHealth: what the stores last did, for /healthz, /readyz, /metrics and the log (one
//   line when a store starts failing, one when it works again, a reminder every 30 s between).
// - GuardDocumentStore: a store behind a guard that opens it when it can (a
//   read-only or missing data directory, Redis down at start: the server starts anyway and the
//   store opens on a later call, at most one try a second) and reports every result to the health.
// - CheckSqliteFile: the database file's integrity at start; a damaged file is never written
//   into: it is moved aside (sessions.db.damaged-<time>), what can be read of it is copied into a
//   new file, and a note says so in the log and in /healthz.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "app/document_store.h"

namespace ctb::app {

class StorageHealth {
 public:
  explicit StorageHealth(std::string backend) : backend_(std::move(backend)) {}
  // `store`: "session", "domain" or "execution"; `why`: the backend's words ("database or disk
  // is full", "Connection refused").
  // `write`: the call would have changed the store. A failed write is not cleared by a read that
  // works (a full disk still reads), only by a write.
  void Failed(const std::string& store, const std::string& why, bool write = false);
  void Worked(const std::string& store, bool write = true);
  void Note(const std::string& note);  // start-up findings, kept for /healthz
  // A cheap call that tells whether `store` works again (its outcome reported like any other);
  // Refresh() runs those of the failing stores, so /healthz does not wait for a user's request.
  void Watch(const std::string& store, std::function<void()> probe);
  void Unwatch(const std::string& store);
  void Refresh();
  bool Degraded() const;
  // Why `store` last failed ("" when it works).
  std::string Why(const std::string& store) const;
  // {"status": "ok"|"degraded", "backend", "stores": {name: {"status", "error"?, "failing_since_ms"?}},
  //  "notes"?: [...]}
  Json ToJson() const;
  // Prometheus lines: ctb_storage_up{store="..."} 1|0.
  std::string Metrics() const;

 private:
  struct State {
    bool ok = true;
    bool write_failed = false;
    std::string why;
    long since_ms = 0;
    long logged_ms = 0;
    long failures = 0;
  };
  mutable std::mutex mu_;
  std::string backend_;
  std::map<std::string, State> stores_;
  std::map<std::string, std::function<void()>> probes_;
  std::vector<std::string> notes_;
};

// The store's 503: "the session store failed (database or disk is full); retry later".
Error StoreFailed(const StorageHealth& health, const std::string& store);

using DocumentStoreOpener = std::function<std::variant<std::unique_ptr<DocumentStore>, Error>()>;

// The store `open` gives, reported to `health` as `store` ("session", "domain", "execution"):
// opened at once if it can be, otherwise on a later call. Never fails. A read that fails gives
// StoreFailed(health, store); LastError() is health.Why(store); Probe() is the guard's own.
std::unique_ptr<DocumentStore> GuardDocumentStore(DocumentStoreOpener open, std::string store,
                                                  std::shared_ptr<StorageHealth> health);

struct SqliteFileCheck {
  bool damaged = false;
  std::string problem;   // SQLite's words
  std::string kept_at;   // where the damaged file went
  long salvaged = 0;     // rows copied into the new file
};

// Checks the file at `path` (nothing to do when it does not exist). A damaged file is moved
// aside with its -wal and -shm and the rows that read are copied into a new file at `path`;
// an Error when the file is damaged and cannot be moved (the server then refuses to start).
std::variant<SqliteFileCheck, Error> CheckSqliteFile(const std::string& path);

}  // namespace ctb::app
