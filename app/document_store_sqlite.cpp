// SQLite document store (document_store.h): table <kind>s(<key>, version, created_ms, updated_ms,
// doc), WAL mode, one connection behind a mutex. Expiry and the cap are checked inside one
// IMMEDIATE transaction, so several processes sharing the file (not recommended; use Redis) still
// respect them. A kind that never expires reads every row as live.
#include <sqlite3.h>

#include <limits>
#include <mutex>

#include "app/document_store.h"
#include "app/store_common.h"

namespace ctb::app::store {

namespace {

class SqliteDocuments : public DocumentStore {
 public:
  SqliteDocuments(sqlite3* db, const DocumentStoreConfig& c)
      : db_(db),
        kind_(c.kind),
        table_(c.kind + "s"),
        key_(KeyColumn(c.kind)),
        max_(c.max),
        idle_ms_(c.idle_s * 1000) {}
  ~SqliteDocuments() override { sqlite3_close(db_); }

  std::variant<std::optional<StoredDocument>, Error> Get(const std::string& id) override {
    std::lock_guard<std::mutex> lock(mu_);
    Stmt q(db_, Sql("SELECT version, created_ms, updated_ms, doc FROM {T} WHERE {K} = ? AND "
                    "updated_ms >= ?"));
    if (!q.ok()) return Unavailable();
    q.Bind(1, id).Bind(2, LiveSince(NowMs()));
    int rc = q.Step();
    if (rc == SQLITE_DONE) return std::optional<StoredDocument>();
    if (rc != SQLITE_ROW) return Unavailable();
    StoredDocument d{id, q.Int(0), q.Int(1), q.Int(2), Json::parse(q.Text(3), nullptr, false)};
    if (d.doc.is_discarded()) return Unavailable("a stored document is not JSON");
    return std::optional<StoredDocument>(std::move(d));
  }

  StoreResult Create(StoredDocument& d) override {
    std::lock_guard<std::mutex> lock(mu_);
    if (!Exec("BEGIN IMMEDIATE")) return Fail();
    const long now = NowMs();
    Expire(now);
    Stmt exists(db_, Sql("SELECT 1 FROM {T} WHERE {K} = ?"));
    if (!exists.ok()) return Rollback();
    const int rc = exists.Bind(1, d.id).Step();
    if (rc != SQLITE_ROW && rc != SQLITE_DONE) return Rollback();
    Stmt count(db_, Sql("SELECT COUNT(*) FROM {T}"));
    if (!count.ok() || count.Step() != SQLITE_ROW) return Rollback();
    if (rc == SQLITE_ROW || count.Int(0) >= max_) {
      Exec("ROLLBACK");
      return rc == SQLITE_ROW ? StoreResult::kConflict : StoreResult::kFull;
    }
    Stmt ins(
        db_,
        Sql("INSERT INTO {T}({K}, version, created_ms, updated_ms, doc) VALUES (?, 1, ?, ?, ?)"));
    if (!ins.ok()) return Rollback();
    ins.Bind(1, d.id).Bind(2, now).Bind(3, now).Bind(4, Dump(d.doc));
    if (ins.Step() != SQLITE_DONE || !Exec("COMMIT")) return Rollback();
    d.version = 1;
    d.created_ms = d.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Write(StoredDocument& d, bool any_version) override {
    std::lock_guard<std::mutex> lock(mu_);
    const long now = NowMs();
    Stmt up(db_, Sql("UPDATE {T} SET version = version + 1, updated_ms = ?, doc = ? "
                     "WHERE {K} = ? AND updated_ms >= ? AND (? OR version = ?) RETURNING version"));
    if (!up.ok()) return Fail();
    up.Bind(1, now).Bind(2, Dump(d.doc)).Bind(3, d.id).Bind(4, LiveSince(now));
    up.Bind(5, any_version ? 1L : 0L).Bind(6, d.version);
    int rc = up.Step();
    if (rc == SQLITE_ROW) {
      const long version = up.Int(0);
      if (up.Step() != SQLITE_DONE) return Fail();
      d.version = version;
      d.updated_ms = now;
      return StoreResult::kOk;
    }
    if (rc != SQLITE_DONE) return Fail();
    Stmt exists(db_, Sql("SELECT 1 FROM {T} WHERE {K} = ? AND updated_ms >= ?"));
    if (!exists.ok()) return Fail();
    rc = exists.Bind(1, d.id).Bind(2, LiveSince(now)).Step();
    if (rc != SQLITE_ROW && rc != SQLITE_DONE) return Fail();
    return rc == SQLITE_ROW ? StoreResult::kConflict : StoreResult::kNotFound;
  }

  StoreResult Delete(const std::string& id) override {
    std::lock_guard<std::mutex> lock(mu_);
    Stmt del(db_, Sql("DELETE FROM {T} WHERE {K} = ? AND updated_ms >= ?"));
    if (!del.ok()) return Fail();
    if (del.Bind(1, id).Bind(2, LiveSince(NowMs())).Step() != SQLITE_DONE) return Fail();
    return sqlite3_changes(db_) == 1 ? StoreResult::kOk : StoreResult::kNotFound;
  }

  long Count() override {
    std::lock_guard<std::mutex> lock(mu_);
    Expire(NowMs());
    Stmt count(db_, Sql("SELECT COUNT(*) FROM {T}"));
    if (!count.ok() || count.Step() != SQLITE_ROW) return Fail(), -1;
    return count.Int(0);
  }

  long CountWhere(const std::string& field, const std::string& value) override {
    std::lock_guard<std::mutex> lock(mu_);
    Stmt count(db_,
               Sql("SELECT COUNT(*) FROM {T} WHERE updated_ms >= ? AND json_extract(doc, ?) = ?"));
    if (!count.ok()) return Fail(), -1;
    count.Bind(1, LiveSince(NowMs())).Bind(2, "$.\"" + field + "\"").Bind(3, value);
    if (count.Step() != SQLITE_ROW) return Fail(), -1;
    return count.Int(0);
  }

  std::variant<std::vector<std::string>, Error> List() override {
    std::lock_guard<std::mutex> lock(mu_);
    Stmt q(db_, Sql("SELECT {K} FROM {T} WHERE updated_ms >= ? ORDER BY ") +
                    (idle_ms_ > 0 ? "created_ms" : key_));
    if (!q.ok()) return Unavailable();
    q.Bind(1, LiveSince(NowMs()));
    std::vector<std::string> ids;
    int rc;
    while ((rc = q.Step()) == SQLITE_ROW) ids.push_back(q.Text(0));
    if (rc != SQLITE_DONE) return Unavailable();
    return ids;
  }

  bool Probe() override {
    std::lock_guard<std::mutex> lock(mu_);
    return WriteProbe(db_) || (Fail(), false);
  }
  std::string LastError() const override {
    std::lock_guard<std::mutex> lock(mu_);
    return last_error_;
  }

 private:
  // The statement with {T} as this kind's table and {K} as its key column.
  std::string Sql(std::string pattern) const {
    for (std::size_t at; (at = pattern.find("{T}")) != std::string::npos;)
      pattern.replace(at, 3, table_);
    for (std::size_t at; (at = pattern.find("{K}")) != std::string::npos;)
      pattern.replace(at, 3, key_);
    return pattern;
  }
  // The oldest last write that is still live.
  long LiveSince(long now) const {
    return idle_ms_ > 0 ? now - idle_ms_ : std::numeric_limits<long>::min();
  }
  bool Exec(const char* sql) {
    return sqlite3_exec(db_, sql, nullptr, nullptr, nullptr) == SQLITE_OK;
  }
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
    if (idle_ms_ <= 0) return;
    Stmt del(db_, Sql("DELETE FROM {T} WHERE updated_ms < ?"));
    if (del.ok()) del.Bind(1, LiveSince(now)).Step();
  }
  Error Unavailable(const char* why = nullptr) {
    Fail(why);
    return Error{ErrorCode::kUnavailable, "the " + kind_ + " store failed; retry later", {}};
  }

  mutable std::mutex mu_;
  sqlite3* db_;
  std::string last_error_;
  std::string kind_, table_, key_;
  long max_, idle_ms_;
};

}  // namespace

std::unique_ptr<DocumentStore> OpenSqliteDocuments(const std::string& path,
                                                   const DocumentStoreConfig& c,
                                                   std::string& error) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db,
                      SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                      nullptr) != SQLITE_OK) {
    error = "cannot open the " + c.kind + " database " + path + ": " +
            (db ? sqlite3_errmsg(db) : "out of memory");
    sqlite3_close(db);
    return nullptr;
  }
  sqlite3_busy_timeout(db, 5000);
  const std::string table = c.kind + "s";
  std::string setup = "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;" + kProbeTableSql +
                      TableSql(table, KeyColumn(c.kind));
  if (c.idle_s > 0)
    setup += "CREATE INDEX IF NOT EXISTS " + table + "_updated ON " + table + "(updated_ms);";
  char* msg = nullptr;
  if (sqlite3_exec(db, setup.c_str(), nullptr, nullptr, &msg) != SQLITE_OK) {
    error = "cannot set up the " + c.kind + " database " + path + ": " + (msg ? msg : "?");
    sqlite3_free(msg);
    sqlite3_close(db);
    return nullptr;
  }
  return std::make_unique<SqliteDocuments>(db, c);
}

}  // namespace ctb::app::store
