// SQLite store of versioned documents (sessions; executions use the same store in their own
// table): table <kind>s(id, version, created_ms, updated_ms, doc), WAL mode, one
// connection behind a mutex. Expiry and the cap are checked inside one IMMEDIATE transaction, so
// several processes sharing the file (not recommended; use Redis) still respect them.
#include <sqlite3.h>

#include <chrono>
#include <filesystem>
#include <mutex>

#include "app/session_store.h"
#include "app/store_common.h"

namespace ctb::app {

namespace {

using store::Dump;
using store::NowMs;
using store::Stmt;

class SqliteStore : public SessionStore {
 public:
  SqliteStore(sqlite3* db, std::string path, std::string table, long max_sessions, long idle_s)
      : db_(db), path_(std::move(path)), table_(std::move(table)), max_(max_sessions), idle_ms_(idle_s * 1000) {}
  ~SqliteStore() override { sqlite3_close(db_); }

  std::variant<std::optional<StoredSession>, Error> Get(const std::string& id) override {
    std::lock_guard<std::mutex> lock(mu_);
    Stmt q(db_, Sql("SELECT version, created_ms, updated_ms, doc FROM {T} WHERE id = ? AND updated_ms >= ?"));
    if (!q.ok()) return Unavailable();
    q.Bind(1, id).Bind(2, NowMs() - idle_ms_);
    int rc = q.Step();
    if (rc == SQLITE_DONE) return std::optional<StoredSession>();
    if (rc != SQLITE_ROW) return Unavailable();
    StoredSession s;
    s.id = id;
    s.version = q.Int(0);
    s.created_ms = q.Int(1);
    s.updated_ms = q.Int(2);
    s.doc = Json::parse(q.Text(3), nullptr, false);
    if (s.doc.is_discarded()) return Unavailable("a stored document is not JSON");
    return std::optional<StoredSession>(std::move(s));
  }

  StoreResult Create(StoredSession& s) override {
    std::lock_guard<std::mutex> lock(mu_);
    if (!Exec("BEGIN IMMEDIATE")) return Fail();
    const long now = NowMs();
    Expire(now);
    Stmt count(db_, Sql("SELECT COUNT(*) FROM {T}"));
    if (!count.ok() || count.Step() != SQLITE_ROW) return Rollback();
    if (count.Int(0) >= max_) {
      Exec("ROLLBACK");
      return StoreResult::kFull;
    }
    Stmt ins(db_, Sql("INSERT INTO {T}(id, version, created_ms, updated_ms, doc) VALUES (?, 1, ?, ?, ?)"));
    if (!ins.ok()) return Rollback();
    ins.Bind(1, s.id).Bind(2, now).Bind(3, now).Bind(4, Dump(s.doc));
    if (ins.Step() != SQLITE_DONE) return Rollback();
    if (!Exec("COMMIT")) return Rollback();
    s.version = 1;
    s.created_ms = s.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Update(StoredSession& s) override {
    std::lock_guard<std::mutex> lock(mu_);
    const long now = NowMs();
    Stmt up(db_, Sql("UPDATE {T} SET version = version + 1, updated_ms = ?, doc = ? "
                 "WHERE id = ? AND version = ? AND updated_ms >= ?"));
    if (!up.ok()) return Fail();
    up.Bind(1, now).Bind(2, Dump(s.doc)).Bind(3, s.id);
    up.Bind(4, s.version).Bind(5, now - idle_ms_);
    if (up.Step() != SQLITE_DONE) return Fail();
    if (sqlite3_changes(db_) == 1) {
      ++s.version;
      s.updated_ms = now;
      return StoreResult::kOk;
    }
    Stmt exists(db_, Sql("SELECT 1 FROM {T} WHERE id = ? AND updated_ms >= ?"));
    exists.Bind(1, s.id).Bind(2, now - idle_ms_);
    return exists.ok() && exists.Step() == SQLITE_ROW ? StoreResult::kConflict : StoreResult::kNotFound;
  }

  StoreResult Delete(const std::string& id) override {
    std::lock_guard<std::mutex> lock(mu_);
    Stmt del(db_, Sql("DELETE FROM {T} WHERE id = ? AND updated_ms >= ?"));
    if (!del.ok()) return Fail();
    del.Bind(1, id).Bind(2, NowMs() - idle_ms_);
    if (del.Step() != SQLITE_DONE) return Fail();
    return sqlite3_changes(db_) == 1 ? StoreResult::kOk : StoreResult::kNotFound;
  }

  long Count() override {
    std::lock_guard<std::mutex> lock(mu_);
    Expire(NowMs());
    Stmt count(db_, Sql("SELECT COUNT(*) FROM {T}"));
    if (!count.ok() || count.Step() != SQLITE_ROW) return Fail(), -1;
    return count.Int(0);
  }

  long CountUsing(const std::string& domain) override {
    std::lock_guard<std::mutex> lock(mu_);
    Stmt count(db_, Sql("SELECT COUNT(*) FROM {T} WHERE updated_ms >= ? AND json_extract(doc, '$.domain') = ?"));
    if (!count.ok()) return Fail(), -1;
    count.Bind(1, NowMs() - idle_ms_).Bind(2, domain);
    if (count.Step() != SQLITE_ROW) return Fail(), -1;
    return count.Int(0);
  }

  std::variant<std::vector<std::string>, Error> List() override {
    std::lock_guard<std::mutex> lock(mu_);
    Stmt q(db_, Sql("SELECT id FROM {T} WHERE updated_ms >= ? ORDER BY created_ms"));
    if (!q.ok()) return Unavailable();
    q.Bind(1, NowMs() - idle_ms_);
    std::vector<std::string> ids;
    int rc;
    while ((rc = q.Step()) == SQLITE_ROW) ids.push_back(q.Text(0));
    if (rc != SQLITE_DONE) return Unavailable();
    return ids;
  }

  std::string Describe() const override { return "sqlite:" + path_ + " (" + table_ + ")"; }
  bool Probe() override {
    std::lock_guard<std::mutex> lock(mu_);
    return store::WriteProbe(db_) || (Fail(), false);
  }
  std::string LastError() const override {
    std::lock_guard<std::mutex> lock(mu_);
    return last_error_;
  }

 private:
  // The statement with {T} as this store's table.
  std::string Sql(std::string pattern) const {
    for (std::size_t at; (at = pattern.find("{T}")) != std::string::npos;) pattern.replace(at, 3, table_);
    return pattern;
  }
  bool Exec(const char* sql) { return sqlite3_exec(db_, sql, nullptr, nullptr, nullptr) == SQLITE_OK; }
  StoreResult Rollback() {
    Fail();
    Exec("ROLLBACK");
    return StoreResult::kUnavailable;
  }
  // Keeps SQLite's words for the failure (LastError).
  StoreResult Fail(const char* why = nullptr) {
    last_error_ = why ? why : sqlite3_errmsg(db_);
    return StoreResult::kUnavailable;
  }
  void Expire(long now) {
    Stmt del(db_, Sql("DELETE FROM {T} WHERE updated_ms < ?"));
    if (del.ok()) {
      del.Bind(1, now - idle_ms_);
      del.Step();
    }
  }
  Error Unavailable(const char* why = nullptr) {
    Fail(why);
    return Error{ErrorCode::kUnavailable, "the session store failed; retry later", {}};
  }

  mutable std::mutex mu_;
  sqlite3* db_;
  std::string last_error_;
  std::string path_;
  std::string table_;
  long max_, idle_ms_;
};

}  // namespace

std::unique_ptr<SessionStore> OpenSqliteStore(const std::string& path, long max_sessions, long idle_s,
                                              std::string& error, const std::string& table) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                      nullptr) != SQLITE_OK) {
    error = "cannot open the session database " + path + ": " + (db ? sqlite3_errmsg(db) : "out of memory");
    sqlite3_close(db);
    return nullptr;
  }
  sqlite3_busy_timeout(db, 5000);
  const std::string setup =
      "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;" + store::kProbeTableSql +
      store::TableSql(table, "id") + "CREATE INDEX IF NOT EXISTS " + table + "_updated ON " + table + "(updated_ms);";
  char* msg = nullptr;
  if (sqlite3_exec(db, setup.c_str(), nullptr, nullptr, &msg) != SQLITE_OK) {
    error = "cannot set up the session database " + path + ": " + (msg ? msg : "?");
    sqlite3_free(msg);
    sqlite3_close(db);
    return nullptr;
  }
  return std::make_unique<SqliteStore>(db, path, table, max_sessions, idle_s);
}

std::optional<Error> ParseRedisUrl(const std::string& url, std::string& host, int& port, int& db) {
  const std::string prefix = "redis://";
  if (url.rfind(prefix, 0) != 0)
    return Error{ErrorCode::kInvalidInput, "session store must be \"sqlite\" or redis://host:port/db", {}};
  std::string rest = url.substr(prefix.size());
  db = 0;
  if (auto slash = rest.find('/'); slash != std::string::npos) {
    const std::string d = rest.substr(slash + 1);
    if (!d.empty() && (d.size() > 3 || d.find_first_not_of("0123456789") != std::string::npos))
      return Error{ErrorCode::kInvalidInput, "redis database must be a small number", {}};
    if (!d.empty()) db = std::stoi(d);
    rest = rest.substr(0, slash);
  }
  port = 6379;
  if (auto colon = rest.rfind(':'); colon != std::string::npos) {
    const std::string p = rest.substr(colon + 1);
    if (p.empty() || p.size() > 5 || p.find_first_not_of("0123456789") != std::string::npos || std::stoi(p) > 65535)
      return Error{ErrorCode::kInvalidInput, "redis port must be 1..65535", {}};
    port = std::stoi(p);
    rest = rest.substr(0, colon);
  }
  host = rest.empty() ? "127.0.0.1" : rest;
  return std::nullopt;
}

std::variant<std::unique_ptr<SessionStore>, Error> OpenSessionStore(const SessionStoreConfig& c) {
  std::string error;
  if (c.url == "memory") {  // the CLI's local mode: sessions die with the process
    auto s = OpenSqliteStore(":memory:", c.max_sessions, c.idle_s, error, c.kind + "s");
    if (!s) return Error{ErrorCode::kUnavailable, error, {}};
    return s;
  }
  if (c.url.empty() || c.url == "sqlite") {
    std::error_code ec;
    std::filesystem::create_directories(c.data_dir, ec);
    auto s = OpenSqliteStore(c.data_dir + "/sessions.db", c.max_sessions, c.idle_s, error, c.kind + "s");
    if (!s) return Error{ErrorCode::kUnavailable, error, {}};
    return s;
  }
  std::string host;
  int port = 6379, db = 0;
  if (auto e = ParseRedisUrl(c.url, host, port, db)) return *e;
  auto s = OpenRedisStore(host, port, db, c.max_sessions, c.idle_s, error, c.kind);
  if (!s) return Error{ErrorCode::kUnavailable, error, {}};
  return s;
}

}  // namespace ctb::app
