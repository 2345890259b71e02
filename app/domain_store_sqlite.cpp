// SQLite domain store: table domains(name, version, created_ms, updated_ms, doc) in the sessions'
// database file, one connection behind a mutex (domain_store.h).
#include <sqlite3.h>

#include <chrono>
#include <filesystem>
#include <mutex>

#include "app/domain_store.h"
#include "app/store_common.h"

namespace ctb::app {

namespace {

using store::Dump;
using store::NowMs;
using store::Stmt;

class SqliteDomainStore : public DomainStore {
 public:
  SqliteDomainStore(sqlite3* db, std::string path, long max_domains)
      : db_(db), path_(std::move(path)), max_(max_domains) {}
  ~SqliteDomainStore() override { sqlite3_close(db_); }

  std::variant<std::optional<StoredDomain>, Error> Get(const std::string& name) override {
    std::lock_guard<std::mutex> lock(mu_);
    Stmt q(db_, "SELECT version, created_ms, updated_ms, doc FROM domains WHERE name = ?");
    if (!q.ok()) return Unavailable();
    q.Bind(1, name);
    int rc = q.Step();
    if (rc == SQLITE_DONE) return std::optional<StoredDomain>();
    if (rc != SQLITE_ROW) return Unavailable();
    StoredDomain d;
    d.name = name;
    d.version = q.Int(0);
    d.created_ms = q.Int(1);
    d.updated_ms = q.Int(2);
    d.doc = Json::parse(q.Text(3), nullptr, false);
    if (d.doc.is_discarded()) return Unavailable("a stored document is not JSON");
    return std::optional<StoredDomain>(std::move(d));
  }

  std::variant<std::vector<std::string>, Error> List() override {
    std::lock_guard<std::mutex> lock(mu_);
    Stmt q(db_, "SELECT name FROM domains ORDER BY name");
    if (!q.ok()) return Unavailable();
    std::vector<std::string> out;
    int rc;
    while ((rc = q.Step()) == SQLITE_ROW) out.push_back(q.Text(0));
    if (rc != SQLITE_DONE) return Unavailable();
    return out;
  }

  StoreResult Create(StoredDomain& d) override {
    std::lock_guard<std::mutex> lock(mu_);
    if (!Exec("BEGIN IMMEDIATE")) return Fail();
    Stmt exists(db_, "SELECT 1 FROM domains WHERE name = ?");
    if (!exists.ok()) return Rollback();
    exists.Bind(1, d.name);
    int rc = exists.Step();
    if (rc == SQLITE_ROW) {
      Exec("ROLLBACK");
      return StoreResult::kConflict;
    }
    Stmt count(db_, "SELECT COUNT(*) FROM domains");
    if (!count.ok() || count.Step() != SQLITE_ROW) return Rollback();
    if (count.Int(0) >= max_) {
      Exec("ROLLBACK");
      return StoreResult::kFull;
    }
    const long now = NowMs();
    Stmt ins(db_, "INSERT INTO domains(name, version, created_ms, updated_ms, doc) "
                  "VALUES (?, 1, ?, ?, ?)");
    if (!ins.ok()) return Rollback();
    ins.Bind(1, d.name).Bind(2, now).Bind(3, now).Bind(4, Dump(d.doc));
    if (ins.Step() != SQLITE_DONE || !Exec("COMMIT")) return Rollback();
    d.version = 1;
    d.created_ms = d.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Replace(StoredDomain& d) override {
    std::lock_guard<std::mutex> lock(mu_);
    const long now = NowMs();
    Stmt up(db_, "UPDATE domains SET version = version + 1, updated_ms = ?, doc = ? WHERE name = ?");
    if (!up.ok()) return Fail();
    up.Bind(1, now).Bind(2, Dump(d.doc)).Bind(3, d.name);
    if (up.Step() != SQLITE_DONE) return Fail();
    if (sqlite3_changes(db_) != 1) return StoreResult::kNotFound;
    Stmt v(db_, "SELECT version FROM domains WHERE name = ?");
    if (v.ok() && v.Bind(1, d.name).Step() == SQLITE_ROW) d.version = v.Int(0);
    d.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Delete(const std::string& name) override {
    std::lock_guard<std::mutex> lock(mu_);
    Stmt del(db_, "DELETE FROM domains WHERE name = ?");
    if (!del.ok()) return Fail();
    del.Bind(1, name);
    if (del.Step() != SQLITE_DONE) return Fail();
    return sqlite3_changes(db_) == 1 ? StoreResult::kOk : StoreResult::kNotFound;
  }

  std::string Describe() const override { return "sqlite:" + path_ + " (domains)"; }
  bool Probe() override {
    std::lock_guard<std::mutex> lock(mu_);
    return store::WriteProbe(db_) || (Fail(), false);
  }
  std::string LastError() const override {
    std::lock_guard<std::mutex> lock(mu_);
    return last_error_;
  }

 private:
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
  Error Unavailable(const char* why = nullptr) {
    Fail(why);
    return Error{ErrorCode::kUnavailable, "the domain store failed; retry later", {}};
  }

  mutable std::mutex mu_;
  sqlite3* db_;
  std::string last_error_;
  std::string path_;
  long max_;
};

}  // namespace

std::unique_ptr<DomainStore> OpenSqliteDomainStore(const std::string& path, long max_domains,
                                                   std::string& error) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db,
                      SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                      nullptr) != SQLITE_OK) {
    error = "cannot open the domain database " + path + ": " +
            (db ? sqlite3_errmsg(db) : "out of memory");
    sqlite3_close(db);
    return nullptr;
  }
  sqlite3_busy_timeout(db, 5000);
  const std::string setup =
      "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;" + store::kProbeTableSql + store::TableSql("domains", "name");
  char* msg = nullptr;
  if (sqlite3_exec(db, setup.c_str(), nullptr, nullptr, &msg) != SQLITE_OK) {
    error = "cannot set up the domain database " + path + ": " + (msg ? msg : "?");
    sqlite3_free(msg);
    sqlite3_close(db);
    return nullptr;
  }
  return std::make_unique<SqliteDomainStore>(db, path, max_domains);
}

std::variant<std::unique_ptr<DomainStore>, Error> OpenDomainStore(const SessionStoreConfig& c,
                                                                 long max_domains) {
  std::string error;
  if (c.url == "memory") {  // the CLI's local mode: domains die with the process
    auto s = OpenSqliteDomainStore(":memory:", max_domains, error);
    if (!s) return Error{ErrorCode::kUnavailable, error, {}};
    return s;
  }
  if (c.url.empty() || c.url == "sqlite") {
    std::error_code ec;
    std::filesystem::create_directories(c.data_dir, ec);
    auto s = OpenSqliteDomainStore(c.data_dir + "/sessions.db", max_domains, error);
    if (!s) return Error{ErrorCode::kUnavailable, error, {}};
    return s;
  }
  std::string host;
  int port = 6379, db = 0;
  if (auto e = ParseRedisUrl(c.url, host, port, db)) return *e;
  auto s = OpenRedisDomainStore(host, port, db, max_domains, error);
  if (!s) return Error{ErrorCode::kUnavailable, error, {}};
  return s;
}

}  // namespace ctb::app
